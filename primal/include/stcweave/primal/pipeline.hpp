#pragma once
/// \file
/// The whole pipeline as one call: diagnose -> require weavable -> orient outward -> weave
/// -> validate the complex -> primal recovery -> pillowing (pillow.hpp) -> node positioning
/// (untangling) -> quality. Each stage is also a public function of its own; this only strings them
/// together, times them and keeps every intermediate value for inspection.

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "stcweave/primal/cut.hpp"
#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/mesh.hpp"
#include "stcweave/primal/pillow.hpp"
#include "stcweave/primal/position.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/primal/recover.hpp"
#include "stcweave/primal/self_crossing.hpp"
#include "stcweave/primal/tet_interior.hpp"
#include "stcweave/stc/hex_stc.hpp"
#include "stcweave/stc/validate.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::primal {

struct MeshOptions {
  /// Weaving options. The pipeline knows the geometry, so its default rule set is
  /// `extended` (the library's `weave::weave` alone defaults to `reliable`).
  weave::WeaveOptions weave = [] {
    weave::WeaveOptions o;
    o.rules = weave::RuleSet::Extended;
    return o;
  }();
  /// Return an invalid complex instead of throwing InternalError (for debugging).
  bool keep_invalid = false;
  /// Untangle and optimise the interior nodes after the harmonic placement (stage
  /// "position"); false keeps the harmonic placement.
  bool untangle = true;
  /// Start the untangling from the weave's layer placement (`layer_positions`) instead of the
  /// harmonic placement; the positioner's Auto start keeps whichever of the two has fewer
  /// inverted corners. Off by default: measured on the woven shared corpus it gives the same
  /// result as the harmonic start or a worse one (docs/geometry.md).
  bool layer_start = false;
  /// Pillowing between recovery and positioning (stage "pillow"): `auto` by default, which
  /// pillows only the shells with a flat or non-convex fixed corner (docs/pillowing.md).
  PillowOptions pillow;
  /// Mesh surfaces whose loops cross themselves by attaching hexes until they do not
  /// (`weave_self_crossing`, docs/self-intersecting-loops.md); false refuses them as the seed
  /// does.
  bool self_crossing_moves = true;
  /// Bounds of that search, and where the front goes when it gives up.
  SelfCrossingOptions self_crossing;
  /// Settings of the positioning stage; `num_fixed` is set by the pipeline (the input
  /// surface's nodes are fixed).
  PositionOptions position;
  /// Settings of the handle cuts (surfaces of genus > 0, see cut.hpp).
  CutOptions cut;
  /// A genus-0 shell woven whole under `extended` with the depth filter on
  /// (`weave.extended.depth_filter`) is first woven without it, and only when that weave
  /// blocks is it woven again with the filter (docs/extended-rules.md, "The depth filter in
  /// an uncut shell"): measured, the filter's peeling lays extra sheets along the boundary
  /// on unstructured surfaces, while on some small spheres it is what lets the weave close.
  /// false: the weave options as given (the filter from the start). Cut balls have their own
  /// setting (`CutOptions::ball_depth_filter`).
  bool depth_filter_after_block = true;
  /// The interior of a triangle-split surface: woven, or a split tetrahedral mesh, or
  /// (`auto`, the default) both and the better kept (tet_interior.hpp, docs/tet-interior.md).
  TetInteriorOptions interior;
  /// Also build the final mesh's STC (`MeshResult::stc`), beside the positioning when
  /// `position.threads` allows a second thread (the positioning moves nodes only).
  bool build_stc = false;
  /// Called when a stage starts ("diagnose", "orient", "weave", "validate", "recover",
  /// "pillow", "position", "quality"; with `build_stc` and no second thread, "stc").
  std::function<void(const std::string& stage)> on_stage;
};

/// Wall-clock seconds per stage. Two stages may run side by side (the validation beside the
/// harmonic placement of `recover`, the STC beside the positioning, when
/// `PositionOptions::threads` allows a second thread):
/// each is given its own duration, and `overlap` the seconds counted twice that way.
struct StageSeconds {
  double diagnose = 0.0;
  double orient = 0.0;
  double weave = 0.0;
  double validate = 0.0;
  double recover = 0.0;
  double pillow = 0.0;
  double position = 0.0;
  double quality = 0.0;
  /// `InteriorMode::Auto` on a triangle-split surface: the whole pipeline with the interior
  /// that was not kept (the other stages are those of the kept one).
  double other_interior = 0.0;
  double stc = 0.0;  ///< the final mesh's STC (`MeshOptions::build_stc`)
  /// Seconds during which two of the stages above ran at once (counted in both).
  double overlap = 0.0;
  /// Wall-clock seconds of the whole run.
  [[nodiscard]] double total() const {
    return diagnose + orient + weave + validate + recover + pillow + position + quality +
           other_interior + stc - overlap;
  }
};

struct MeshResult {
  HexMesh mesh;                    ///< input nodes first, with their ids in `surface`
  SurfaceMesh surface;             ///< the input surface as woven (oriented outward)
  std::vector<NodeId> file_nodes;  ///< per surface node, its node id in the file
  SurfaceDiagnosis diagnosis;
  OrientationReport orientation;
  weave::WeaveResult woven;
  /// Shells woven separately and handle cuts (empty for a single genus-0 shell, which is
  /// woven whole).
  SolidsReport solids;
  /// Validation of the final complex (`mesh.complex`, after pillowing) against the input.
  stc::ValidationReport validation;
  /// The output's hex pairs sharing four or more nodes that are not a face of both
  /// (`stc::shared_nodes_not_a_face`, part of `validation`): such a mesh has a negative
  /// Jacobian inside some hex whatever the corners say, so it is refused like any invalid
  /// complex; a count above 0 is seen only with `keep_invalid`.
  stc::Violation shared_nodes{stc::Invariant::SharedNodesNotAFace, 0, {}};
  HarmonicReport harmonic;
  /// What the pillow stage decided and did. When it pillowed, `mesh` has the pillow's nodes
  /// and hexes appended while `woven` stays the weave's own result.
  PillowReport pillow;
  PositionReport position;  ///< empty when `MeshOptions::untangle` is false
  /// The moves, attached hexes and join of a surface with self-intersecting loops (`used` is
  /// false for any other surface).
  SelfCrossingReport self_crossing;
  /// Whether the surface is triangle-split and which interior was kept (`used`: the tet
  /// split; then `woven` holds the split's hexes, not a weave's).
  TetInteriorReport interior;
  /// With `MeshOptions::depth_filter_after_block`: empty when the weave without the depth
  /// filter completed (or the option did not apply); otherwise why it blocked, the weave
  /// kept being the one with the filter.
  std::string depth_filter_retry;
  QualitySummary quality;
  /// The STC of `mesh.complex` (with `MeshOptions::build_stc`; null otherwise). Held by
  /// pointer: Boost's adjacency_list (1.74) copies itself when moved, and the result moves.
  std::shared_ptr<const stc::HexStc> stc;
  StageSeconds seconds;
};

/// The order `InteriorMode::Auto` keeps two meshes of one surface in: a valid complex first,
/// then fewer inverted hexes, then the larger minimum scaled Jacobian, then fewer hexes.
/// \return true when `a` is at least as good as `b`.
[[nodiscard]] bool better_or_equal(const MeshResult& a, const MeshResult& b);

/// The weave of a genus-0 shell that `mesh_file` weaves whole (no cut), before any rescue:
/// `weave::weave` with `options.weave`, except that under `extended` with the depth filter on
/// and `options.depth_filter_after_block`, the shell is first woven without the filter, and
/// only when that weave blocks is it woven again as the options say; `retry` then holds why
/// the first weave blocked (empty otherwise). The first weave's trace events are held back
/// until it completes, so `options.weave.on_trace` sees the events of the weave kept only.
/// \throw WeaveError when the weave kept blocks.
[[nodiscard]] weave::WeaveResult weave_whole_shell(const stc::QuadSurface& surface,
                                                   const MeshOptions& options,
                                                   const std::vector<std::array<double, 4>>& angles,
                                                   std::string& retry);

/// Meshes the quad surface of `file` (its quads, or the boundary of its hexes).
/// \throw TopologyError for a surface that cannot be woven (see `require_weavable`).
/// \throw TopologyError for an odd handle cycle (no hex mesh exists).
/// \throw Unsupported for handles that `weave_solids` cannot cut, or loops
///        when no cut of a solid with self-intersecting loops can be woven and glued.
/// \throw WeaveError when the weave is blocked, or the search for front moves of a surface
///        with self-intersecting loops gives up, or (unless keep_invalid) the complex keeps
///        pinched face pairs at boundary nodes on a shell that cannot be pillowed
///        (`PillowReport::unpillowable`).
/// \throw InternalError when the woven complex breaks an invariant (unless keep_invalid).
/// \throw InvalidInput with `interior.mode` Tets, for a surface that is not triangle-split or
///        not one shell, or that Gmsh cannot tetrahedralise.
MeshResult mesh_file(const MeshFile& file, const MeshOptions& options = {});

}  // namespace stcweave::primal
