#pragma once
/// \file
/// Weaving a surface whose loops cross themselves (docs/self-intersecting-loops.md): attach
/// hexes to it until its loops are simple (`stc::untangle_loops`), weave the front left
/// (`weave::weave`, with the attached hexes' nodes as fixed "input" nodes of that front), and
/// join the two complexes. When the direct join is not a valid complex (the weaver built a
/// hex on two faces of one attached hex), the front is pillowed: one more hex on every front
/// face, between the attached hexes and a copy of the front that the same weave fills.

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "stcweave/primal/mesh.hpp"
#include "stcweave/stc/loop_moves.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::primal {

struct SelfCrossingOptions {
  /// Bounds of the search for moves (stc::LoopMoveOptions documents them).
  stc::LoopMoveOptions search;
  /// When the search gives up, the front at that point is written here (OBJ, OFF or VTK by
  /// extension; the nodes the attached hexes made are placed at the average of their
  /// neighbours). Empty: not written.
  std::string front_on_failure;
  /// A front of at most this many faces whose loops stay crossed, or whose weave blocks, is
  /// filled by the moves alone (`stc::fill_front`). 0: never.
  std::size_t fill_up_to = 200;
  /// The weaves of this stage undo a shrink that leaves a seam blocked
  /// (`weave::WeaveOptions::undo_seam_blocking_shrinks`). Measured on `cylinder2_c3`,
  /// `fandisk_quads` and medial `fertility`: fewer hexes and far fewer inverted ones
  /// (docs/self-intersecting-loops.md "Seams left blocked").
  bool undo_seam_blocking_shrinks = true;
  /// When every way fails (the reliable fallback included) and that fill stalled on an even
  /// front of at most `fill_residual_up_to` faces (fewer than it started from), the front it
  /// left is meshed by this stage as a surface of its own (its nodes fixed) and joined to the
  /// fill's hexes, nested at most `fill_residual_depth` deep. A last way only: as an earlier
  /// way it won on hex count where the reliable fallback gives fewer (measured: 548 hexes
  /// against 53 on an 18-quad sphere). The fill of small blocked spheres stalls on 8- to
  /// 12-face fronts (the one 8-quad sphere map has self-crossing loops). 0: off.
  std::size_t fill_residual_depth = 1;
  std::size_t fill_residual_up_to = 48;
  /// Weave the front with every front node fixed and join through the pillow layer even when
  /// the direct join is valid (for tests and comparisons; no other way is tried).
  bool always_pillow = false;
  /// Weave the front with the attached hexes known to the weaver (`weave::weave_attached`):
  /// the nodes they made are free (mergeable) interior nodes of the weave. When that weave
  /// blocks, the front is woven again with every front node fixed, as without this option.
  bool free_nodes = true;
  /// When the search gives up with loops still crossed, weave that front anyway (with
  /// `free_nodes`): the weave never shrinks a loop that crosses itself, but shrinking the
  /// others reroutes it. Off: measured, it completed none of the generated spheres or shared
  /// surfaces whose search gave up, and its weaves of large fronts cost minutes.
  bool weave_unsimple = false;
  /// With `free_nodes`: when the weave of the front blocks, pillow one front face at a blocked
  /// valence-2 node and go on, at most this many times (`weave::WeaveOptions::
  /// recovery_pillows`; the larger of the two applies). Measured on the generated spheres: the
  /// untangled fronts block on seams that would merge two input nodes, which a pillow lifts.
  std::size_t recovery_pillows = 64;
  /// With `free_nodes`: when the weave of the front blocks on loops that cross themselves, run
  /// the search for moves on the weave's own front and go on, at most this many times
  /// (`weave::AttachedWeaveOptions`). 0 (off): measured, 8 rounds changed no outcome of the
  /// generated spheres.
  std::size_t untangle_rounds = 0;
  /// When every way above blocks with the `extended` rules, run them all again with the
  /// `reliable` rules (the extended filters read angles that the attached hexes' faces only
  /// get by propagation). Measured: pmp/fandisk_quads, whose untangled front blocks every
  /// extended weave, is woven this way (docs/self-intersecting-loops.md).
  bool reliable_fallback = true;
  /// Set by a caller that has already woven this surface with the same weave options and
  /// seen it block (`mesh_file`'s rescue of a loop-clean surface): when no hex is attached,
  /// the first way (that very weave) is not run again.
  bool plain_weave_blocked = false;
};

/// What `weave_self_crossing` did.
struct SelfCrossingReport {
  /// The surface went through this stage: it had self-intersecting loops, or its plain weave
  /// blocked (`after_block`).
  bool used = false;
  /// When the stage rescued a loop-clean surface whose weave blocked even with the block
  /// recovery (`mesh_file`), why that weave blocked (as the `WeaveError` said it); else empty.
  std::string after_block;
  stc::LoopMoveResult moves;
  std::size_t attached_hexes = 0;
  std::size_t pillow_hexes = 0;  ///< 0 unless the join needed the pillow layer
  std::size_t woven_hexes = 0;
  bool pillowed = false;
  /// The weave ran with the attached hexes' nodes free (`SelfCrossingOptions::free_nodes`).
  bool free_nodes = false;
  /// Recovery pillows the weave of the front used (`weave::WeaveStats::front_pillows`).
  std::size_t front_pillows = 0;
  /// Rounds of front moves during that weave, and the hexes they attached
  /// (`SelfCrossingOptions::untangle_rounds`).
  std::size_t untangle_rounds = 0;
  std::size_t round_hexes = 0;
  /// When a free weave gave a complex that is not valid (never returned), its first violation.
  std::string free_weave_violation;
  /// The front was filled by moves alone (`stc::fill_front`), without the weave.
  bool filled = false;
  /// The fill stalled on a front of this many faces, which this stage meshed as a surface of
  /// its own (`SelfCrossingOptions::fill_residual_depth`); 0 otherwise. `filled` is false then.
  std::size_t fill_residual = 0;
  /// The front was woven with the `reliable` rules after the `extended` ones blocked
  /// (`SelfCrossingOptions::reliable_fallback`).
  bool reliable_fallback = false;
  /// Why the weave of the front failed, when it did and the moves filled the front instead.
  std::string weave_failure;
  /// The first violated invariant of the direct join, when it was invalid.
  std::string direct_join_violation;
  double search_seconds = 0.0;
  double weave_seconds = 0.0;
  double join_seconds = 0.0;
};

/// Meshes `surface` (closed, manifold, oriented outward, genus 0 per component) whose loops
/// may cross themselves. The result has the layout of a plain weave's: input nodes
/// 0 .. n-1 with their ids, then every other node; `hex_rule` says "attached", "pillow" or
/// the weaver's rule; `dual` is rebuilt from the joined complex; `stats` and `trace` are the
/// weave's of the front. The complex is certified with `stc::validate_hex_complex` against
/// `surface` before it is returned.
/// \param side_angles per input quad and side, the dihedral angles (or empty), as for
///        `weave::weave`; faces of the attached hexes get 270 on an edge between two faces of
///        the same hex and 180 elsewhere.
/// \throw WeaveError when the search gives up (the message names the bound, the
///        self-crossing quads left, and the file the front was written to), or when the weave
///        of the front is blocked.
/// \throw InternalError when neither join is a valid complex.
weave::WeaveResult weave_self_crossing(const SurfaceMesh& surface,
                                       const weave::WeaveOptions& weave_options,
                                       const std::vector<std::array<double, 4>>& side_angles,
                                       const SelfCrossingOptions& options,
                                       SelfCrossingReport& report);

}  // namespace stcweave::primal
