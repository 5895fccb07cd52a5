#pragma once
/// \file
/// The tetrahedral interior of a triangle-split surface (docs/tet-interior.md).
///
/// On a triangle-split quad surface (every triangle of a triangle mesh cut into three quads,
/// stc/tet_split.hpp) the weave makes a star: every loop circles one triangle vertex, every
/// sheet is a small cap, and the caps meet at one interior node. That node cannot see the
/// whole boundary of a non-convex solid, so hexes stay inverted, and on a convex one the
/// hexes at it are needles. This stage gives such surfaces another interior: the solid
/// bounded by the surface's triangles is tetrahedralised (Gmsh's Delaunay mesher, the
/// boundary triangles kept) and every tetrahedron is split into four hexes. The boundary
/// stays exactly the input; the STC is the boundary loops' caps plus one closed blind sheet
/// around each interior vertex, so interior vertices play the part of the star's one node.

#include <cstddef>
#include <string>
#include <string_view>

#include "stcweave/primal/mesh.hpp"
#include "stcweave/stc/tet_split.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::primal {

/// How the pipeline fills a triangle-split surface.
enum class InteriorMode {
  /// Weave it, and also split a tetrahedral mesh of it; keep the better (fewer inverted
  /// hexes, then the larger minimum scaled Jacobian, then fewer hexes). With a handle or
  /// several shells the tets go first and are kept without weaving when no hex is inverted.
  /// Only for a closed triangle-split surface with Gmsh at build time; anything else is woven.
  Auto,
  /// Always weave (the seed's way).
  Weave,
  /// Split a tetrahedral mesh; a surface that is not triangle-split is refused.
  Tets,
};

[[nodiscard]] std::string_view interior_mode_name(InteriorMode mode);
/// \throw InvalidInput for a name other than auto, weave, tets.
[[nodiscard]] InteriorMode interior_mode_from_name(std::string_view name);

/// The interior's options.
struct TetInteriorOptions {
  InteriorMode mode = InteriorMode::Auto;
  /// Above 1: the interior tetrahedra grow away from the boundary, to at most this many times
  /// the nearest boundary vertex's mean edge length h (Gmsh's size min(growth h, h + d / 2)
  /// at distance d); 1: Gmsh's own sizes, extended from the boundary. 1.5 was measured to
  /// give fewer hexes than Gmsh's own all-hex meshes on six of eight of their boundaries with
  /// a minimum scaled Jacobian still well above Gmsh's (docs/tet-interior.md).
  double growth = 1.5;
  /// 3-2 flips of the tetrahedra before the split (one tet, four hexes fewer per flip), each
  /// only when the worse of its two new tets has a corner quality (`tet_corner_quality`) of
  /// at least `flip_floor` or at least that of the worst of the three it replaces
  /// (docs/tet-interior.md, "Fewer tets").
  bool flips = true;
  double flip_floor = 1.0;
};

/// What the stage did.
struct TetInteriorReport {
  /// The surface was recognised as triangle-split (only looked for with `tets`, and with
  /// `auto` when Gmsh is there; false with `weave`).
  bool triangle_split = false;
  bool used = false;      ///< the output's interior is the tet split
  bool compared = false;  ///< auto positioned both interiors and chose
  std::string reason;     ///< one line: why this interior
  std::size_t triangles = 0;
  std::size_t tets = 0;               ///< after the flips
  std::size_t flips = 0;              ///< 3-2 flips made (tets removed)
  std::size_t interior_vertices = 0;  ///< tet vertices that Gmsh put inside
  double seconds = 0.0;               ///< tetrahedralisation and split
};

/// True when stcweave was built with Gmsh (the tetrahedraliser); same as has_cad_support().
[[nodiscard]] bool has_tet_interior_support();

/// Tetrahedralises the solid bounded by the triangles of `split` and splits every tet into
/// four hexes. The result has the surface's nodes first (ids and order kept) and is shaped
/// like a weave's (`hex_rule` "tet-split", `hex_shrink` -1, no trace); `positions` receives
/// coordinates for every node of the complex: the surface's, Gmsh's for interior tet
/// vertices, and each added node at the centre of its tet vertices.
/// Several shells are meshed together: one volume per shell of positive signed volume, with
/// the shells of negative volume inside it (cavities) as holes.
/// \pre `surface` is closed and oriented outward (a cavity's shell into the cavity); `split`
///      is its triangle split.
/// \throw Unsupported when stcweave was built without Gmsh.
/// \throw InvalidInput when Gmsh cannot tetrahedralise the solid while keeping the boundary
///        triangles (for instance a self-intersecting surface), with Gmsh's reason.
weave::WeaveResult tet_interior(const SurfaceMesh& surface, const stc::TriangleSplit& split,
                                const TetInteriorOptions& options, Points& positions,
                                TetInteriorReport* report = nullptr);

}  // namespace stcweave::primal
