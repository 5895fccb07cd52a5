#pragma once
/// \file
/// Solids the weave cannot take whole: several disjoint shells, and handles (genus > 0).
///
/// Each solid (a connected shell) is woven on its own. A solid of genus g > 0 is first cut
/// along g quad-meshed discs, one per handle cycle found by `diagnose_handles`: the disc is a
/// grid whose boundary is the cycle (corners where the cycle turns most), its nodes placed
/// by transfinite interpolation of the cycle, or a loop-following chord disc (its dual chords
/// pair the cycle's crossings of each loop, so that crossing loops are not merged). Cutting along
/// it duplicates the cycle's nodes and the disc (one copy on each side), which lowers the genus by
/// one; the cut ball is woven with every node of the cut surface fixed (the weave takes them as
/// input nodes), then the two copies are glued back by identifying their nodes: the disc's nodes
/// become interior nodes of the final mesh. A disc choice whose cut surface has a self-intersecting
/// loop, whose weave is blocked or whose glued complex breaks an invariant is discarded and the
/// next is tried. docs/topology.md explains the choices.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/mesh.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::primal {

/// Settings of `weave_solids`.
struct CutOptions {
  /// Apply the extended rules' depth filter (sect. 4.1) in the weaves of cut balls. Off by
  /// default: the two copies of a disc (or of a cavity's annulus) are faces of the ball's
  /// front with depth 0 like the solid's boundary, so the filter peels layers off the discs
  /// too; measured, it made the cinolib rocker arm 14,148 hexes with min scaled Jacobian
  /// 0.143, against 9,888 and 0.568 without it (docs/extended-rules.md, "The depth filter in
  /// cut balls"). Measured before the non-convex filter kept the sides with the fewest
  /// non-convex edges (`nonconvex_least`); with it the rocker arm's woven hexes hardly depend
  /// on this (5,140 without, 5,164 with). An uncut solid keeps
  /// `weave::ExtendedParameters::depth_filter`.
  bool ball_depth_filter = false;
  /// Disc choices woven per handle before giving up (choices whose cut has a
  /// self-intersecting loop are discarded without weaving and not counted).
  std::size_t max_disc_attempts = 12;
  /// Cut surfaces whose loops are checked per solid (over every handle's disc choices, in a
  /// depth-first search) before giving up.
  std::size_t max_loop_checks = 2000;
  /// When the weave of a cut ball blocks, it is tried once more with up to this many one-face
  /// pillows at blocked nodes (`weave::WeaveOptions::recovery_pillows`); 0: no second try.
  std::size_t recovery_pillows = 16;
  /// Run the weave's block recovery search (`weave::WeaveOptions::block_recovery`) in the
  /// weaves of the disc search too. Off by default: those weaves have alternatives (other
  /// discs, the reliable rules, recovery pillows, then the slab route, which keeps the
  /// recovery for its few weaves), and a recovery
  /// search on every blocked candidate made refusals take minutes (a plate with a hole from
  /// CAD: 8 s without, over 5 min with). A shell without handles keeps the block recovery.
  bool ball_block_recovery = false;
  /// Weaves one cut ball (a genus-0 surface over the cut surface's node ids, its points
  /// included); empty: `weave::weave` with the dihedral angles of the extended rule set. The
  /// result must have the layout of a plain weave's (the surface's nodes first).
  std::function<weave::WeaveResult(const SurfaceMesh&, const weave::WeaveOptions&)> ball_weaver;
  /// Accept cut surfaces whose loops cross themselves, as long as the cut adds no quad where a
  /// loop crosses itself (the count never exceeds the solid's own); `ball_weaver` must weave
  /// such balls (`weave_solids_self_crossing`, self_crossing.hpp). False: every cut surface
  /// with a self-intersecting loop is discarded.
  bool allow_self_crossing = false;
  /// Try the slab route (docs/topology.md, "Slabs") before the disc search instead of after
  /// it: each handle's band of quads closed by two discs and woven on its own.
  bool slab_first = false;
};

/// One handle cut: where, with which disc, after how many attempts.
struct HandleCut {
  std::vector<NodeId> cycle;  ///< surface node ids (of the woven surface)
  int grid_a = 0;             ///< the disc is a grid_a x grid_b grid of quads
  int grid_b = 0;
  /// The disc, in words: "3x3" (a grid), "3x3 O-grid", "loop-following (14 quads)" (a chord
  /// disc pairing the crossings of each loop, grid_a = grid_b = 0), "annulus 1x4" (a cavity
  /// cut off along the annulus between a cavity quad and an outer-shell quad), "column hex" (the
  /// hex between those two quads attached to the front instead, in a solid with handles; the
  /// cycle lists the outer quad's nodes, then the cavity quad's),
  /// "slab: A and B, N hexes" (the slab route: the discs on the cycle and on the band's other
  /// boundary, and the slab's hexes).
  std::string disc;
  std::size_t attempts = 0;  ///< disc choices tried, loop-checked or woven (the last was kept)
};

/// What `weave_solids` did.
struct SolidsReport {
  std::size_t solids = 0;  ///< shells woven separately
  std::vector<HandleCut> cuts;
  double cut_seconds = 0.0;    ///< building discs and cut surfaces
  double weave_seconds = 0.0;  ///< the weaves of the cut balls (including discarded ones)
  double glue_seconds = 0.0;   ///< gluing, renumbering, checking the glued complexes
  /// Solids whose kept weave was not the first of the second pass's chain (recovery pillows
  /// or the reliable rule set after the weave with the given options blocked).
  std::size_t relaxed_weaves = 0;
};

/// Weaves every solid of `mesh` on its own, cutting its handles first, and combines them:
/// input nodes keep their ids, interior nodes (disc nodes included) follow, solid by solid.
/// \pre `mesh` is closed, manifold, oriented outward (`orient_outward`; a cavity's shell then
///      faces into the cavity), every handle cycle even (`require_weavable`). Solids inside
///      cavities (any nesting depth) are solids of their own; each cavity belongs to the
///      smallest solid that encloses it.
/// \throw Unsupported when the handle diagnosis cannot decide, when handle cycles share nodes,
///        when no disc choice gives a loop-clean cut, a complete weave and a valid glue, for a
///        cavity with handles, for a solid with handles and cavities whose loops cross
///        themselves, and when no quad pair is free to join a cavity.
/// \throw TopologyError when a handle cycle is odd (no hex mesh exists).
/// \throw WeaveError when a solid without handles cannot be woven.
weave::WeaveResult weave_solids(const SurfaceMesh& mesh, const weave::WeaveOptions& options,
                                const CutOptions& cut_options = {}, SolidsReport* report = nullptr);

}  // namespace stcweave::primal
