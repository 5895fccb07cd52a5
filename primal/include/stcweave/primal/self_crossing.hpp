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
  /// Join through the pillow layer even when the direct join is valid (for tests and
  /// comparisons).
  bool always_pillow = false;
};

/// What `weave_self_crossing` did.
struct SelfCrossingReport {
  bool used = false;  ///< the surface had self-intersecting loops and went through this stage
  stc::LoopMoveResult moves;
  std::size_t attached_hexes = 0;
  std::size_t pillow_hexes = 0;  ///< 0 unless the join needed the pillow layer
  std::size_t woven_hexes = 0;
  bool pillowed = false;
  /// The front was filled by moves alone (`stc::fill_front`), without the weave.
  bool filled = false;
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
