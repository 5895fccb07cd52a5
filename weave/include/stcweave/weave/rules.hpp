#pragma once
/// \file
/// The rules of the weave, one free function each, one source file each under
/// `weave/src/rules/` named after the seed's rule. Each reads like its section of the seed:
/// precondition, move, what it propagates; each returns what it did or why it refused.
///
/// | rule | seed | file |
/// |---|---|---|
/// | `seam`, `seam_fixpoint` | sect. 2.2, Fig. 2 | rules/seam.cpp |
/// | `cross` | sect. 2.2, Fig. 2 | rules/cross.cpp |
/// | `blind_chord` | sect. 2.2, Fig. 2-3 | rules/blind_chord.cpp |
/// | `shrink` (loop shrinking) | sect. 2.2, Fig. 3-4 | rules/shrink.cpp |
/// | `parallel_merging` | sect. 5.1, Fig. 10 | rules/parallel_merging.cpp |
/// | `nonconvexity_seam` | sect. 5.2, Fig. 11 | rules/nonconvexity_seam.cpp |
/// | `edge_angle`, `propagate` | sect. 6, Fig. 12-14 | rules/propagate.cpp |
/// | loops of the front | sect. 2.1 | rules/front_loops.cpp |

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "stcweave/weave/kernel.hpp"

namespace stcweave::weave {

// ---- loops of the front (rules/front_loops.cpp) ----

/// The loop through front face `f` entered by its side `entry`, traced until it returns.
/// \throw InternalError on an open front edge.
[[nodiscard]] Strip trace_strip(const Front& front, FaceIndex f, int entry);

/// Every loop of the front, and per face slot and direction the loop crossing it.
struct FrontLoops {
  std::vector<Strip> strips;                         ///< loop i is strips[i] (LoopId i)
  std::vector<std::array<std::int32_t, 2>> loop_of;  ///< per face slot, per direction; -1 none
};
/// Loops numbered by their first face slot (lowest first), direction 0 before 1.
[[nodiscard]] FrontLoops front_loops(const Front& front);

/// A directed transversal edge of a strip: (node on the shrinking side, other node).
struct Transversal {
  NodeId side_node;
  NodeId other;
};
/// One transversal edge per step, oriented from side `side` to the other (how a loop is
/// re-found after rules change the front, DESIGN.md "Sides of a loop").
[[nodiscard]] std::vector<Transversal> transversals(const Front& front, const Strip& strip,
                                                    stc::LoopSide side);
/// The loop through the first of `edges` still on the front (through node merges), or an
/// empty strip when none is left (the loop has shrunk to nothing).
[[nodiscard]] Strip retrace(const Front& front, const std::vector<Transversal>& edges);

// ---- propagation of geometric information (rules/propagate.cpp) ----

/// The dihedral angle of front edge (f, side): the two faces' carried angles combined, a
/// convex and a non-convex deviation from flat cancelling (seed sect. 6, Fig. 12), two
/// deviations the same way keeping the larger.
[[nodiscard]] double edge_angle(const Front& front, FaceIndex f, int side);

/// Depth and angles of the six faces of a new hex.
struct Propagated {
  std::array<std::int32_t, 6> depth{};
  std::array<std::array<float, 4>, 6> side_angle{};
};
/// What the faces of new hex `hex` carry (seed sect. 6), given the front faces it is built on
/// (`used[lf]`: the front face on its local face lf, or kNoFace). Depth: i+1 opposite an
/// i-depth used face, -1 otherwise. Angles: a face opposite a used face F takes on each side
/// the angle F stores on the parallel side; other faces are flat (180).
[[nodiscard]] Propagated propagate(const Front& front, const stc::Hex& hex,
                                   const std::array<FaceIndex, 6>& used);

// ---- basic rules ----

/// Seam at a valence-2 node v (rules/seam.cpp): faces A = (v, a, x, b) and B = (v, b, y, a)
/// share two edges; both leave the front, x and y merge, and every other pair of faces the
/// merge makes coincident is glued in the same step. Refused when both faces are input quads,
/// x and y are distinct input nodes, x and y already share a hex or a front face, two hexes
/// would then share more than one face, or the front would be pinched.
/// \cite seed sect. 2.2 (Fig. 2), RWW.
RuleResult seam(WeaveState& state, WeaveContext& ctx, NodeId v);

/// Seams to a fixpoint over the queued nodes (`WeaveState::seam_work`, and the nodes whose
/// seam was refused before). Refused seams are counted and queued for the next pass.
void seam_fixpoint(WeaveState& state, WeaveContext& ctx);

/// Cross at a valence-3 node v (rules/cross.cpp): its three faces F1 = (v, a, xab, b),
/// F2 = (v, b, xbc, c), F3 = (v, c, xca, a) become three faces of the new hex
/// (v, b, xab, a, c, xbc, w, xca), w a new node. With `extended` and the flat-cross
/// precondition, refused where more than one of its three edges is flatter than
/// `little_sharp` (unless `ctx.relax_geometry`). \cite seed sect. 2.2 (Fig. 2).
RuleResult cross(WeaveState& state, WeaveContext& ctx, NodeId v);

/// Blind chord formation at a node v of valence >= 4 on the shrinking side of `strip`
/// (rules/blind_chord.cpp): a strip face f holding v on that side and the non-strip face g
/// across f's shrinking-side edge at v share one edge; a new hex sits on both (two new nodes).
/// `strip_faces` holds the faces of the loop's whole strip; `strip` may be only its steps that
/// hold v (`shrink` passes those, from its strip index). \pre side A of `strip` is the
/// shrinking side.
/// \cite seed sect. 2.2 (Fig. 2, Fig. 3).
RuleResult blind_chord(WeaveState& state, WeaveContext& ctx, NodeId v, const Strip& strip,
                       const FaceSet& strip_faces);

/// The same rule given the positions in `strip` of the steps that hold v on the shrinking
/// side (entry or entry + 3 is v), in strip order: it tries only those steps, so the result
/// is that of the overload above (which scans the whole strip for them) when `steps` lists
/// exactly those positions.
RuleResult blind_chord(WeaveState& state, WeaveContext& ctx, NodeId v, const Strip& strip,
                       const FaceSet& strip_faces, std::span<const std::uint32_t> steps);

/// Shrinks the loop `strip` to side `side` (rules/shrink.cpp): seams to a fixpoint, re-trace,
/// then the side node with the fewest front faces is collapsed (seam, cross or blind chord),
/// until the loop is gone. Returns nothing on success, else why every node was blocked.
/// \cite seed sect. 2.2 (Fig. 3-4).
[[nodiscard]] std::optional<std::string> shrink(WeaveState& state, WeaveContext& ctx,
                                                const Strip& strip, stc::LoopSide side);

// ---- intermediate rules ----

/// Connected components of the front: per node, its component, and per component its nodes.
struct FrontComponents {
  std::vector<std::size_t> component_of;  ///< per node (0 for nodes off the front)
  std::vector<std::size_t> size;          ///< nodes per component
};
[[nodiscard]] FrontComponents front_components(const Front& front, Marks& marks);

/// Parallel merging (rules/parallel_merging.cpp), seed sect. 5.1 (Fig. 10) as read in
/// docs/extended-rules.md: the strip of the central loop is one face high, its transversal
/// edges map the rim of side A onto the rim of side B, and that map extends face by face to
/// an isomorphism of the two regions, which with the strip are the whole front component;
/// the layer is closed at once by one hex per face pair, no node created or merged.
RuleResult parallel_merging(WeaveState& state, WeaveContext& ctx, const Strip& strip,
                            const FrontComponents& components);

/// What parallel merging asks of a loop's two candidates (side A, side B) before their face
/// counts: a loop that does not cross itself, at least 3 long, with sharp convex edges all
/// along both sides. Read off the strip alone.
[[nodiscard]] bool may_merge_in_parallel(const TraceCandidate& a, const TraceCandidate& b);

/// The parallel merging step of Fig. 15: tries `parallel_merging` on every loop whose
/// candidates qualify (sharp convex side edges on both sides, as many faces either side),
/// tracing each attempt; true when one was applied (its seams then run).
bool apply_parallel_merging(WeaveState& state, WeaveContext& ctx, const FrontLoops& loops,
                            const std::vector<TraceCandidate>& candidates,
                            const FrontComponents& components);

/// Non-convexity seam (rules/nonconvexity_seam.cpp), seed sect. 5.2 (Fig. 11) as read in
/// docs/extended-rules.md: input quad F2 = `input_face` and the hex face F1 across its side
/// `side` share only that edge E; E convex, a side of F2 next to E non-convex, F1's two nodes
/// off E interior: F1 is folded onto F2 about E and the coincident faces glued. The state is
/// restored when the fold would break the front.
RuleResult nonconvexity_seam(WeaveState& state, WeaveContext& ctx, FaceIndex input_face, int side);

/// Non-convexity seams wherever they apply on the front, each followed by its seams; the
/// number applied.
std::size_t nonconvexity_seams(WeaveState& state, WeaveContext& ctx);

}  // namespace stcweave::weave
