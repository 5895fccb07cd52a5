#pragma once
/// \file
/// The weaving engine: fills a closed quad surface with hexahedra by shrinking its loops one
/// after the other (Reliable Whisker Weaving, seed sect. 2.2 and 7), working on the front in
/// the dual. `weave` knows no coordinates.
///
/// What it guarantees: on success, every input quad is a face of exactly one hex, every
/// other hex face is shared by exactly two hexes (the front is empty), input nodes keep their
/// ids, and every hex is positively oriented with respect to the outward input orientation
/// (its faces built on front faces are its outward faces). It does not certify the complex:
/// run `stc::validate_hex_complex` on the result (the CLI always does).

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "stcweave/stc/ids.hpp"
#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::weave {

/// Which loop-selection rules run.
enum class RuleSet {
  /// Reliable Whisker Weaving: the (loop, side) with the smallest topological weight.
  Reliable,
  /// The seed's extension: parallel crossing, then the non-convex, depth, first and second
  /// convex filters, then the fewest faces collapsed (seed sect. 4 and 7, Fig. 15).
  Extended,
};

/// Name of a rule set as used on the command line ("reliable", "extended").
[[nodiscard]] std::string to_string(RuleSet rules);
/// \throw InvalidInput for an unknown name.
[[nodiscard]] RuleSet rule_set_from_name(const std::string& name);

/// Progress report, given to `WeaveOptions::progress` now and then.
struct WeaveProgress {
  std::size_t front_faces = 0;  ///< faces still on the front
  std::size_t hexes = 0;        ///< hexes created so far
  std::size_t loops_shrunk = 0;
};

/// Classes of a front edge by its dihedral angle a (degrees, through the region still to
/// mesh; 180 is flat), seed sect. 4.4, Fig. 8.
enum class EdgeClass {
  SharpConvex,           ///< ]0, sharp]
  LittleSharpConvex,     ///< ]sharp, little_sharp]
  Flat,                  ///< ]little_sharp, flat]
  LittleSharpNonConvex,  ///< ]flat, little_sharp_nonconvex]
  SharpNonConvex,        ///< ]little_sharp_nonconvex, 360[
};

/// Parameters of the rule set `extended` (seed sect. 4-7). Every filter can be switched off.
struct ExtendedParameters {
  double sharp = 120.0;
  double little_sharp = 170.0;
  double flat = 190.0;
  double little_sharp_nonconvex = 240.0;
  /// Parallel crossing (sect. 4.5): a loop whose side edges are all sharp convex and lie
  /// along one other loop of the same length is shrunk toward it first.
  bool parallel_crossing = true;
  /// Non-convex rule (sect. 4.4): never shrink toward a side holding a non-convex edge.
  /// When it would leave no candidate the seed stops; we keep the sides with the fewest
  /// (`nonconvex_least`) or, without that, relax the filter for that selection.
  bool nonconvex_filter = true;
  /// Non-convex rule, our relaxation (docs/extended-rules.md, "Non-convex: the fewest
  /// non-convex edges"): when every side holds a non-convex edge, keep the sides holding the
  /// fewest rather than every side. Default true; false relaxes the filter entirely (CLI
  /// `--no-nonconvex-least`).
  bool nonconvex_least = true;
  /// Depth rule (sect. 4.1): keep the candidates whose side has the least depth.
  bool depth_filter = true;
  /// First convex rule (sect. 4.2): keep loops crossing a sharp or a little sharp edge;
  /// relaxed when it would leave no candidate.
  bool first_convex_filter = true;
  /// First convex rule, our condition (docs/extended-rules.md, "First convex: loops along a
  /// rim"): a side whose every side edge is sharp convex passes too, though its loop crosses
  /// no sharp edge. Such a loop runs along a rim (the first ring of a paved face), and its
  /// shrink lays a layer along that face, as a parallel crossing does. Default true; false
  /// is the seed's rule (CLI `--no-first-convex-rim`).
  bool first_convex_rim = true;
  /// Second convex rule (sect. 4.3): keep the highest side elimination weight (sharp
  /// convex edges along that side of the strip / loop length).
  bool second_convex_filter = true;
  /// Second convex rule: a side elimination weight below this counts as 0 (0: the seed's
  /// rule; see stcweave/weave/second_convex_threshold.hpp). Default 0.1: a side with fewer
  /// than one sharp edge in ten along it does not run along a sharp region (measured on the
  /// kitty: 7,643 -> 7,083 hexes, `reliable`'s and the reference's count; nothing else of
  /// the shared corpus worse; docs/extended-rules.md "Second convex threshold: 0.1"). 0.75
  /// breaks the structured answer of an L-block made of three transfinite blocks, 0.2 makes
  /// `box_c3` and `cylinder2_c3` worse.
  double second_convex_min_weight = 0.1;
  /// Second convex rule, our condition (docs/extended-rules.md, "Second convex: the smaller
  /// side"): a side's elimination weight counts only when that side collapses no more faces
  /// than the other side of the same loop; otherwise it weighs 0. The sharp edges along a
  /// loop that circles one vertex of a triangle-split surface lie on the side that is the rest
  /// of the front, and the seed's rule would collapse it. Default true; false is the seed's
  /// rule (CLI `--no-second-convex-smaller-side`).
  bool second_convex_smaller_side = true;
  /// Order of the filters (docs/extended-rules.md, "Depth after the convex filters"): true
  /// (default) applies the depth filter after the first and second convex filters, false in
  /// the seed's order (before them, Fig. 15; CLI `--depth-before-convex`). Measured, the
  /// seed's order peels the front evenly, which bends the sheets of a structured L-block
  /// around its corners (`lblock_tf_medium`: 11,743 hexes against the structured 6,591).
  bool depth_after_convex = true;
  /// Geometric precondition of the cross (sect. 2.2, RWW): refuse a cross at a corner
  /// where more than one of the three edges is flatter than `little_sharp`. Lifted for a
  /// shrink in which every node would otherwise be blocked.
  bool flat_cross_precondition = true;
  /// Parallel merging (sect. 5.1, as read in docs/extended-rules.md): a loop of sharp
  /// convex side edges on both sides, between two discs of the front that its strip maps
  /// onto each other, closes as one layer of hexes (one per disc face, no new node). It
  /// runs before the selection and chooses the loop directly.
  bool parallel_merging = true;
  /// Non-convexity seam (sect. 5.2, as read in docs/extended-rules.md): a hex face folded
  /// onto the input quad it meets at a convex edge next to a non-convex one. Runs before
  /// every selection. Off by default: measured, applying it wherever it is allowed blocks
  /// later weaving (docs/extended-rules.md has the figures).
  bool nonconvexity_seam = false;
};

/// The class of an edge of dihedral angle `angle` (degrees).
[[nodiscard]] EdgeClass classify_edge(double angle, const ExtendedParameters& parameters);
[[nodiscard]] std::string to_string(EdgeClass edge_class);
/// \throw InvalidInput unless 0 < sharp <= little_sharp <= flat <= little_sharp_nonconvex < 360.
void check_parameters(const ExtendedParameters& parameters);

struct TraceEvent;
struct Selection;
class WeaveObserver;

/// What the weave does when every (loop, side) is blocked (issue 11; docs/weave-recovery.md).
enum class BlockRecovery {
  /// The block is an error (`WeaveError`).
  Off,
  /// A bounded search over pillows of blocked front faces (weave/src/recovery.cpp): each
  /// trial pillows one or more front faces and weaves on from there; the first trial that
  /// completes is kept, a trial that blocks again is searched further, up to the limits of
  /// `RecoveryLimits`. With `extended`, when that finds nothing, the rest of the weave runs
  /// with the reliable selection from the same blocked front (recovered the same way). Only
  /// a weave that would otherwise throw is changed.
  Auto,
};

/// Name as used on the command line ("auto", "off").
[[nodiscard]] std::string to_string(BlockRecovery recovery);
/// \throw InvalidInput for an unknown name.
[[nodiscard]] BlockRecovery block_recovery_from_name(const std::string& name);

/// Bounds of the search of `BlockRecovery::Auto`.
struct RecoveryLimits {
  /// Pillows stacked on one path of the search (recoveries of one weave), default 24.
  std::size_t max_depth = 24;
  /// Weaves tried from a blocked front, in all, default 100.
  std::size_t max_trials = 100;
  /// Valence-2 (then lowest-valence) nodes whose faces are tried at each block, default 4.
  std::size_t nodes_per_block = 4;
};

struct WeaveOptions {
  RuleSet rules = RuleSet::Reliable;
  ExtendedParameters extended;
  /// Check the front invariants after every rule (slow: for debugging and tests).
  bool check = false;
  /// Record one trace event per loop selection and per rule application.
  bool trace = false;
  /// Undo a loop shrink that ends blocked and try the next candidate (the front is saved
  /// before each shrink); when all fail, the first candidate's partial shrink is kept. Off:
  /// a failed shrink's partial work is always kept.
  bool backtrack = true;
  /// With `backtrack`: when every candidate fails from a front, the first one's partial shrink
  /// is kept and the selection starts again (the last resort). Off: the weave is blocked
  /// there (what the fill of `fill_up_to` runs with, so that it starts from the first such
  /// front and not from one that partial shrinks grew).
  bool keep_partial_shrink = true;
  /// With `backtrack`: a shrink that completes but leaves a valence-2 node whose seam is
  /// refused (more blocked seams than before it) is undone like a failed one and the next
  /// candidate tried. Such a seam stays refused (the merge would make two hexes share two
  /// faces), and covering either of its two faces leaves a pinched face pair in the complex
  /// (docs/geometry.md "Pinched faces"). Off by default: a weave that completes keeping such
  /// shrinks is kept as it is (`undo_seam_blocking_on_block` retries the ones that block);
  /// the front-move stage sets it from `primal::SelfCrossingOptions`.
  bool undo_seam_blocking_shrinks = false;
  /// `weave` only, with `undo_seam_blocking_shrinks` off, `backtrack` on and no `max_rules` of
  /// the caller's (a budget given is kept): when the weave ends blocked (its
  /// block recovery included) or spends its rule budget, it is woven once more from the start
  /// with `undo_seam_blocking_shrinks` on, and that weave is returned when it completes
  /// (`WeaveStats::seam_undo_retries`); when it fails too, the last ways below are tried
  /// (`fill_up_to`, `reliable_from_start`), and when they fail the first weave's error is
  /// thrown.
  /// A weave that completes is never woven twice, so its result is the same with this on or
  /// off. Measured on the loop-clean sphere quadrangulations of 18 and 20 quads and on the
  /// corpus (docs/weave-recovery.md "Seams left blocked"). The trace (`trace`, `on_trace`)
  /// holds the weave returned, or the first one when every way fails; an `observer` sees all.
  bool undo_seam_blocking_on_block = true;
  /// `weave` only, under the same conditions, when that retry fails too: the weave is run once
  /// more, without the block recovery and without `keep_partial_shrink`, to the first front
  /// where every candidate fails (then the same undoing those shrinks, then the input itself
  /// before any rule), and a front of at most this many faces is filled by the front
  /// moves of stc/loop_moves.hpp (`stc::fill_front`: hexes attached until nothing is left,
  /// knowing the woven hexes at the front's nodes), each hex of the fill checked against the
  /// woven complex and built on the front (rule "fill", `WeaveStats::fill_hexes`). A weave
  /// that completes otherwise never gets here, so its result is the same whatever this is.
  /// Only with `block_recovery` `Auto`. 0: off. docs/weave-recovery.md "The fill".
  std::size_t fill_up_to = 200;
  /// `weave` only, under the same conditions, with `extended` rules (and no `selection` of the
  /// caller's), when the fill fails too: the whole weave with the `reliable` rules from the
  /// start, its own retries included (`WeaveStats::reliable_from_start`). Only with
  /// `block_recovery` `Auto`. docs/weave-recovery.md "The fill".
  bool reliable_from_start = true;
  /// When set, every trace event is also handed to it as it happens (independently of
  /// `trace`), so that the trace of a weave that throws is not lost.
  std::function<void(const TraceEvent&)> on_trace;
  /// The trace's selection events hold only the candidate chosen (`chosen` 0), not every
  /// candidate ranked. The driver then needs the chosen one only and computes the others in
  /// part, as with no trace at all (branch and bound for `reliable`, side properties on demand
  /// for a geometric selection: select/bounded.hpp, select/candidates.hpp), so a trace of the
  /// choices costs no more than the weave. The choices, rules and hexes are the same.
  bool trace_chosen_only = false;
  /// Give up after this many rule applications; 0 chooses 8 * quads^1.5 + 20000 (a k x k x k
  /// box needs about 3 k^3 = 0.02 quads^1.5).
  std::size_t max_rules = 0;
  /// When every (loop, side) is blocked, pillow one face at a blocked valence-2 node (the
  /// whole front when there is none; stcweave/weave/front_pillow.hpp) and go on, at most
  /// this many times. 0: off (the block is an error).
  std::size_t recovery_pillows = 0;
  /// When every (loop, side) is still blocked (after `recovery_pillows`): `Auto` (default)
  /// searches for pillows that let the weave complete; `Off` throws.
  BlockRecovery block_recovery = BlockRecovery::Auto;
  /// Bounds of that search.
  RecoveryLimits recovery;
  /// Called every `progress_every` rules when set.
  std::function<void(const WeaveProgress&)> progress;
  std::size_t progress_every = 20000;
  /// When set, replaces the loop selection of `rules` (see stcweave/weave/select.hpp: a list
  /// of filters; `reliable_selection()`, `extended_selection()` or one of your own). `rules`
  /// still decides the rest (geometric preconditions and intermediate rules with `extended`).
  std::shared_ptr<const Selection> selection;
  /// When set, watches the weave (selections, rules, failed shrinks) besides the trace; see
  /// stcweave/weave/kernel.hpp. Not owned; must outlive the call.
  WeaveObserver* observer = nullptr;
};

/// One neighbour of a hex face in the woven STC: another hex, or an input quad (a boundary
/// point of the STC).
struct DualLink {
  bool is_boundary = false;
  std::int32_t id = -1;         ///< HexId value, or QuadId value when `is_boundary`
  std::int8_t local_face = -1;  ///< face index in the neighbouring hex (kHexFaces order)
};

/// A candidate of one loop selection, as the trace reports it.
struct TraceCandidate {
  std::int32_t loop = -1;  ///< index of the loop in this selection's enumeration
  int side = 0;            ///< 0 = side A, 1 = side B (DESIGN.md "Sides of a loop")
  std::size_t length = 0;  ///< number of strip passages
  std::size_t strictly_on_side = 0;
  std::size_t on_strip = 0;
  std::size_t weight = 0;  ///< strictly_on_side + on_strip
  bool self_intersecting = false;
  // Properties of the extended rule set (zero with `reliable`).
  std::size_t faces_collapsed = 0;    ///< faces strictly on that side + strip faces
  std::int32_t depth = 0;             ///< least strictly positive face depth on that side, or 0
  std::size_t crossed_sharp = 0;      ///< sharp or little sharp convex edges the loop crosses
  std::size_t side_sharp = 0;         ///< sharp convex edges along that side of the strip
  std::size_t nonconvex_on_side = 0;  ///< non-convex front edges on that side
  std::int32_t parallel_to = -1;      ///< the loop it runs along (parallel crossing), or -1
};

/// One line of the trace: a loop selection, a rule application, or a failed shrink.
struct TraceEvent {
  enum class Kind { Selection, Rule, ShrinkFailed };
  Kind kind = Kind::Rule;
  std::size_t step = 0;  ///< rules applied before this event
  // Selection: every candidate, sorted as ranked; `chosen` indexes `candidates`.
  std::vector<TraceCandidate> candidates;
  std::int32_t chosen = -1;
  std::string reason;  ///< why this candidate (or why the shrink failed)
  /// Selection: the filters applied in order, each with the candidates it left
  /// ("nonconvex:12", "depth:4", ...; "relaxed" when a filter would have left none and was
  /// skipped, "least:M" when it kept the M candidates of least `Filter::relax_cost` instead).
  std::vector<std::string> filters;
  /// Selection: what decided the choice: "weight" (reliable), "parallel_crossing", the first
  /// filter after which one candidate was left, "topological" (fewest faces collapsed among
  /// several), or "fallback" when earlier candidates failed to shrink.
  std::string decided_by;
  // Rule: which rule, at which node, on which front faces (their whiskers), which hex.
  /// "seam", "seam-coincident", "cross", "cross-relaxed" (geometric precondition lifted),
  /// "blind-chord", "parallel-merge", "nonconvexity-seam"
  std::string rule;
  NodeId node;
  std::vector<std::string> faces;
  HexId hex;
  std::int32_t shrink = -1;  ///< index of the loop shrink in progress (-1: between shrinks)
};

struct WeaveStats {
  std::size_t selections = 0;
  std::size_t shrinks = 0;
  std::size_t failed_shrinks = 0;
  std::size_t seams = 0;
  std::size_t coincident_glues = 0;
  std::size_t crosses = 0;
  std::size_t blind_chords = 0;
  std::size_t blocked_seams = 0;  ///< seam attempts refused by a precondition
  /// Shrink steps in which the geometric preconditions were lifted (extended only).
  std::size_t relaxed_preconditions = 0;
  /// Layers closed by the parallel merging rule (extended only).
  std::size_t parallel_merges = 0;
  /// Non-convexity seams applied (extended only).
  std::size_t nonconvexity_seams = 0;
  /// Failed shrinks that were undone (`WeaveOptions::backtrack`).
  std::size_t rolled_back_shrinks = 0;
  /// Pillows put on a blocked front (`WeaveOptions::recovery_pillows`).
  std::size_t front_pillows = 0;
  /// Pillows of the block recovery kept in the result (`WeaveOptions::block_recovery`).
  std::size_t recoveries = 0;
  /// Weaves tried from a blocked front by the block recovery (kept or not).
  std::size_t recovery_trials = 0;
  /// Weaves that blocked keeping the shrinks that leave a seam blocked, whose second weave,
  /// undoing them, is the one kept (`WeaveOptions::undo_seam_blocking_on_block`): 0 or 1 for
  /// one weave, summed over the weaves of a cut solid.
  std::size_t seam_undo_retries = 0;
  /// Hexes of the fill of a blocked front (`WeaveOptions::fill_up_to`); 0 when no fill was
  /// kept.
  std::size_t fill_hexes = 0;
  /// 1 when the weave returned is the `reliable` one of `WeaveOptions::reliable_from_start`.
  std::size_t reliable_from_start = 0;
};

/// One pillow of the block recovery, as kept in the result.
struct Recovery {
  std::size_t hexes_before = 0;  ///< hexes woven when the weave blocked
  std::size_t front_faces = 0;   ///< faces on the front then
  std::size_t pillowed = 0;      ///< front faces pillowed (one hex each); 0: rule set switch
  NodeId node;                   ///< the blocked node whose faces were pillowed (or invalid)
  std::string why;               ///< why the weave was blocked (the first refusals)
};

/// One loop shrink as the weave records it: the (loop, side) its selection chose.
struct ShrinkRecord {
  std::int32_t shrink = -1;  ///< the shrink index (`TraceEvent::shrink`)
  std::int32_t loop = -1;    ///< the loop, numbered in that selection's enumeration
  int side = 0;              ///< 0 = side A, 1 = side B
  std::size_t length = 0;    ///< strip passages of the loop
  std::int32_t depth = 0;    ///< the candidate's depth (0 with `reliable`)
  std::string decided_by;    ///< what decided the choice (`TraceEvent::decided_by`)
  bool failed = false;       ///< the shrink ended blocked (undone, or kept in part)
};

/// Files `r` into `records` (sorted by shrink index): a record with the same index is
/// replaced (a shrink undone by backtracking gives its index to the next one; weaves merged
/// one after the other shift their shrink indices past the earlier ones' first, as
/// `weave_solids` does), any other is inserted in order.
void file_shrink_record(std::vector<ShrinkRecord>& records, ShrinkRecord r);
/// Marks the record of shrink `shrink` in `records` as failed (none: nothing happens).
void mark_shrink_failed(std::vector<ShrinkRecord>& records, std::int32_t shrink);

struct WeaveResult {
  /// The hexes. Input nodes keep their ids 0..num_input_nodes-1; interior nodes follow.
  stc::HexComplex complex;
  std::size_t num_input_nodes = 0;
  /// The woven STC: for each hex and each of its faces (kHexFaces order), what lies behind.
  std::vector<std::array<DualLink, 6>> dual;
  /// For each hex, the index of the loop shrink that created it (its layer).
  std::vector<std::int32_t> hex_shrink;
  /// For each hex, the rule that created it ("cross" or "blind-chord").
  std::vector<std::string> hex_rule;
  /// For each hex, the front node its rule was applied at (front numbering, as the trace's
  /// `node`). A recovery pillow is one rule for several hexes: its last hex carries the node
  /// it was reported at, the others an invalid id.
  std::vector<NodeId> hex_node;
  /// Every loop shrink kept, by increasing index: what its selection chose. Recorded with or
  /// without a trace (a trace holds the same and more, at a cost per rule).
  std::vector<ShrinkRecord> shrinks;
  WeaveStats stats;
  std::vector<TraceEvent> trace;
  /// The pillows of the block recovery, in order (empty when the weave never blocked).
  std::vector<Recovery> recoveries;
};

/// Weaves the hex complex bounded by `surface`.
/// \pre `surface` is closed, edge- and vertex-manifold, consistently oriented outward, every
///      component of genus 0, no self-intersecting loop (`primal::require_weavable` checks
///      this; `weave` re-checks what it relies on).
/// \throw InvalidInput when the surface is not a valid front (open, pinched, degenerate).
/// \throw WeaveError when every (loop, side) is blocked and the block recovery is off or
///        found nothing within its limits, naming the blocked nodes and why.
/// \throw InternalError when an invariant breaks (with `options.check`).
/// \cite seed sect. 2.2 (loop shrinking, weights), sect. 4-7 (extended rules, sequence).
/// \param side_angles per input quad and side, the dihedral angle of that side's edge in
///        degrees (180 = flat, < 180 convex), as `primal::dihedral_angles` computes it; used
///        by the `extended` rule set. Empty: every edge is taken as flat.
/// \throw InvalidInput when `side_angles` is neither empty nor one entry per quad.
WeaveResult weave(const stc::QuadSurface& surface, const WeaveOptions& options = {},
                  const std::vector<std::array<double, 4>>& side_angles = {});

}  // namespace stcweave::weave
