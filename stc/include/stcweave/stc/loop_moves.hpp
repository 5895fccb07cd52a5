#pragma once
/// \file
/// Front moves that reroute the loops of a quad surface: attach hexes to the surface until no
/// loop crosses itself, so that the rest can be woven by loop shrinking (docs/
/// self-intersecting-loops.md).
///
/// Attaching a hex to a front (the surface, oriented outward from the region still to mesh) on
/// k of its faces replaces those k front faces with the hex's 6 - k other faces: a flip of the
/// front. Each flip acts on the loops as a local move: a cross (k = 3 around a valence-3 node)
/// is a Reidemeister III move of three loops, a blind chord (k = 2) adds a bigon, a bigon
/// removal (k = 4, the two faces left adjacent) removes one, a bump (k = 1) adds a small loop,
/// a cap (k = 5) removes one, and the two surgeries, U (k = 3, a strip of three faces) and
/// tube (k = 4, a ring of four), reconnect the loops passing through them. Only a surgery can
/// turn a loop with an odd number of self-crossings into simple loops: the other moves are
/// regular homotopies of the loops, which keep each loop's number of self-crossings even or odd.
///
/// Pure topology: no coordinates.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::stc {

/// The ways a hex can be attached to the front, by the set of its faces lying on the front.
enum class FrontMove : std::uint8_t {
  Bump,        ///< k = 1: one face; four new nodes
  BlindChord,  ///< k = 2: two faces sharing an edge; two new nodes
  Cross,       ///< k = 3: the three faces around a valence-3 node; one new node
  Surgery,     ///< k = 3: a strip of three faces (two opposite hex faces and one between)
  Bigon,       ///< k = 4: four faces whose complement is two faces sharing an edge
  Tube,        ///< k = 4: a ring of four faces (splits the front in two)
  Cap,         ///< k = 5: five faces (removes a bump)
  Close,       ///< k = 6: a front component that is one hex's boundary
};

/// "bump", "blind-chord", "cross", "surgery", "bigon", "tube", "cap", "close".
[[nodiscard]] std::string to_string(FrontMove move);

/// Progress of a search, given to `LoopMoveOptions::progress` now and then.
struct LoopMoveProgress {
  bool filling = false;                 ///< `fill_front` (goal: no front left), not untangling
  std::size_t hexes = 0;                ///< attached so far
  std::size_t self_crossing_quads = 0;  ///< on the front now
  std::size_t front_faces = 0;          ///< on the front now
  std::size_t evaluations = 0;          ///< candidate moves this search has evaluated so far
};

/// Bounds of the search. Every bound is a hard limit; the search says which one stopped it.
struct LoopMoveOptions {
  /// Moves applied in all (the attached hexes).
  std::size_t max_moves = 400;
  /// Candidate moves evaluated from one front (those nearest the self-crossings first).
  std::size_t max_candidates = 600;
  /// Fronts kept per level of the beam search, run when no single move improves the score.
  std::size_t beam_width = 8;
  /// Levels of the beam search (moves looked ahead).
  std::size_t beam_depth = 3;
  /// The front may not grow beyond the input's quads plus this many faces.
  std::size_t max_extra_faces = 400;
  /// Candidate moves evaluated in all (the search's cost bound).
  std::size_t max_evaluations = 1000000;
  /// Work bound: the sum over evaluated candidates of the front's faces (each evaluation
  /// copies the front and re-traces the loops the move changed). Measured at the default:
  /// `bl3d_5_fine` (10,096 quads) stops here after 5.5 s. The bounds were 2e5 evaluations and
  /// 1e8 until the score was updated from the changed loops alone; these keep the wall time
  /// of a search that gives up below what the old ones cost (`bl3d_5_fine` 10.9 s, `rod`
  /// 21.6 s there; `rod` now stalls after 6.7 s with 26 self-crossing quads left, not 32).
  std::size_t max_work = 500000000;
  /// Fronts of at most this many faces get the deeper, wider look-ahead below (they are
  /// cheap to evaluate and the moves they need are longer).
  std::size_t small_front = 48;
  std::size_t small_beam_depth = 10;
  std::size_t small_beam_width = 48;
  /// The surgery look-ahead, run when the beam finds nothing: sequences of up to
  /// `surgery_depth` surgeries (U or tube) seeded at any face of a self-intersecting loop, at
  /// most `surgery_candidates` evaluated per front, `surgery_width` fronts kept per level,
  /// ranked by self-crossing quads before odd loops. 0: off.
  std::size_t surgery_depth = 3;
  std::size_t surgery_width = 16;
  std::size_t surgery_candidates = 4000;
  /// The tunnel, tried when the surgery look-ahead finds nothing too: a row of hexes along a
  /// straight strip of the front (the faces a loop P passes through in turn) from a face
  /// crossed by a self-intersecting loop L to a face further along P that L crosses again;
  /// it reconnects the two strands of L there however far apart they are (a long U-surgery:
  /// blind chords, then a surgery). `tunnel_length`: the most hexes in the row; 0: off.
  /// `tunnel_hits`: how many crossings of P with L the strip may run past before it ends on
  /// one (0: only the next crossing along P).
  std::size_t tunnel_length = 64;
  std::size_t tunnel_hits = 2;
  /// When no single tunnel lowers (odd loops, self-crossing quads): the tunnels kept (by
  /// self-crossing quads first) to try a second tunnel after each.
  std::size_t tunnel_width = 8;
  /// The curl slide, tried when the tunnel finds nothing too. A curl of a loop is a
  /// self-crossing whose two passes follow each other among the loop's self-crossing passes
  /// (no other self-crossing on the arc between them). The curl gap of a front: for every loop
  /// with 2 to `curl_gap_crossings` self-crossings, two of which are curls, the least distance
  /// between two of its curls (the passes strictly between them along the loop, or with
  /// `curl_gap_surface` the fewest steps across front edges between their arcs; with
  /// `curl_gap_opposite` only curls of opposite sense pair up), summed over those loops. Two
  /// curls of one loop (the residue a loop with Gauss word 1 1 2 2 leaves) cancel only side
  /// by side, and the moves that slide them together change no figure of the score; the slide
  /// is a beam (`curl_slide_width` fronts per level, `curl_slide_depth` levels) ranked by the
  /// score with the curl gap before the front faces, which accepts a sequence that lowers
  /// (odd loops, self-crossing quads, curl gap). After one, the greedy step ranks the same
  /// way until (odd loops, self-crossing quads) fall, so that it does not undo the slide.
  /// Fronts whose search never stalls there are searched as without it.
  /// `curl_gap_crossings` or `curl_slide_depth` 0: off.
  std::size_t curl_gap_crossings = 2;
  bool curl_gap_surface = false;
  bool curl_gap_opposite = false;
  std::size_t curl_slide_depth = 3;
  std::size_t curl_slide_width = 8;
  /// Fronts of at most `tiny_front` faces, when every look-ahead above found nothing: an
  /// iterative deepening over every move of every face, up to `tiny_depth` moves and
  /// `tiny_evaluations` evaluations. 0 depth: off.
  std::size_t tiny_front = 24;
  std::size_t tiny_depth = 8;
  std::size_t tiny_evaluations = 300000;
  /// Evaluations left in a pool that several searches share (`primal::SharedSearchBudget`
  /// passes one to every search of a solid's cut balls: the untangling, the fills and the
  /// rounds during a weave): when set, each evaluation of a search run with these options, or
  /// with a copy of them, is also taken from the pool, and the search stops at its evaluation
  /// bound once the pool is empty. Not synchronised: the searches sharing it run one after
  /// another.
  std::shared_ptr<std::size_t> shared_evaluations;
  /// For debugging and tests: after every candidate move, trace the whole front again and
  /// compare its score with the one updated from the loops the move changed (the search
  /// updates the score by re-tracing only those); a difference throws `InternalError`. Slow:
  /// a full trace per evaluation, as the search did before it updated scores.
  bool check_scores = false;
  /// Refuse a hex that would share more than four nodes with an attached hex, or four nodes
  /// with one whose face it is not built on (the weave's own check of a hex put on its front,
  /// `weave::WeaveState::contact_conflict`; `stc::validate_hex_complex` refuses such pairs as
  /// `SharedNodesNotAFace`, and the pipeline asks it of every complex it outputs). On by
  /// default: without it the attached hexes can hold such a pair, and then no complex that
  /// contains them is valid (off only to compare with the searches before 2026-12-07).
  bool strict_contacts = true;
  /// Called when set: every 10th hex attached, and every `progress_every` evaluations (a
  /// look-ahead can evaluate for seconds without attaching a hex). Reports only; the search
  /// is the same with or without it.
  std::function<void(const LoopMoveProgress&)> progress;
  std::size_t progress_every = 50000;
};

/// One move of the search, as applied.
struct AppliedMove {
  FrontMove move = FrontMove::Bump;
  HexId hex;                            ///< the attached hex
  std::size_t self_crossing_quads = 0;  ///< on the front after the move
  std::size_t front_faces = 0;          ///< after the move
};

/// The outcome of `untangle_loops`.
struct LoopMoveResult {
  /// The attached hexes (VTK order, positively oriented for an outward input). Node ids:
  /// the input's 0 .. num_input_nodes-1, then the nodes the hexes made; `num_nodes` counts
  /// them all.
  HexComplex hexes;
  std::size_t num_input_nodes = 0;
  /// The front after the moves, outward from the region still to mesh, over the same node
  /// ids (`front.num_nodes == hexes.num_nodes`). Its faces are input quads and faces of the
  /// attached hexes (reversed).
  QuadSurface front;
  /// Per front quad, the attached hex it is a face of, or -1 for an input quad.
  std::vector<std::int32_t> front_hex;
  /// Per front quad, the input quad it is, or -1 for a face of an attached hex.
  std::vector<std::int32_t> front_input;
  std::vector<AppliedMove> moves;
  std::size_t self_crossing_quads_before = 0;
  std::size_t self_crossing_quads_after = 0;
  std::size_t evaluations = 0;  ///< candidate moves evaluated
  std::size_t beam_searches = 0;
  std::size_t surgery_searches = 0;  ///< surgery look-aheads run (the beam found nothing)
  std::size_t tunnels = 0;           ///< tunnels applied (rows of hexes, each one step)
  std::size_t curl_slides = 0;       ///< curl slides accepted (`LoopMoveOptions::curl_slide_depth`)
  std::size_t deepenings = 0;        ///< iterative deepenings that lowered (`tiny_front`)
  /// True when no loop of `front` crosses itself.
  bool simple = false;
  /// Why the search stopped ("simple", or which bound).
  std::string stop_reason;
};

/// Attaches hexes to `surface` until its loops are simple: greedily the move that lowers
/// (loops crossing themselves an odd number of times, self-crossing quads, self-intersecting
/// loops, front faces) the most, and when no single move lowers it, a beam search over
/// `beam_depth` moves. Odd loops come first because only a surgery can fix one (the other
/// moves keep each loop's parity), and merging two of them makes one even loop even when it
/// adds self-crossings for a while. Every move keeps the front a closed
/// oriented 2-manifold quad surface with every node of valence >= 3, no two faces on the same
/// four nodes, no two edges on the same two nodes, no face of the front equal to a face of an
/// attached hex, and never builds a hex on two faces of one attached hex (two hexes share at
/// most one face). Deterministic.
/// \pre `surface` is closed, manifold, consistently oriented outward, with four distinct
///      nodes per quad.
/// \throw InvalidInput when the surface is not closed and consistently oriented.
[[nodiscard]] LoopMoveResult untangle_loops(const QuadSurface& surface,
                                            const LoopMoveOptions& options = {});

/// Goes on from `start` (a result of `untangle_loops`, simple or not) attaching hexes until
/// the front is empty: greedily the move that lowers (front faces, self-crossing quads,
/// self-intersecting loops) the most, with the same beam search when none does, under the
/// same preconditions; a component that is one hex's boundary is closed by that hex. The
/// completion Verhetsel et al. search for; meant for small fronts, where the weave of the
/// front can block. `simple` is then true when the front is empty; `moves` lists `start`'s
/// moves and the new ones.
/// \pre `start` is a result of `untangle_loops`.
[[nodiscard]] LoopMoveResult fill_front(const LoopMoveResult& start,
                                        const LoopMoveOptions& options = {});

}  // namespace stcweave::stc
