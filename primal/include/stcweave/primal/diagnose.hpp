#pragma once
/// \file
/// Diagnosis of an input: is it a quad surface a hex mesh can fill, and if not, why.
///
/// The pipeline's "validate" stage: `diagnose` measures (it never throws on a defect),
/// `require_weavable` decides (it throws one precise `TopologyError` per defect), and
/// `orient_outward` fixes the one thing that can be fixed without asking: the orientation.
///
/// Definitions (those of the independent oracle that produced `../shared/data/
/// expected.json`, except where said):
/// - the surface of a hex mesh is its boundary (faces used by exactly one hex), of any
///   other file its quads; every figure describes that surface;
/// - `nodes`: nodes referenced by the surface's quads;
/// - an edge used by one quad side is open, by three or more non-manifold; `closed` means
///   neither kind; `manifold` means no non-manifold edge and no non-manifold node (a node
///   whose quads do not form one fan; unlike the oracle, a node of a single quad is a
///   boundary node, not a non-manifold one);
/// - `consistently_oriented`: every manifold edge is traversed once each way *as given* (the
///   oracle reports it after re-orienting a surface file, which makes it equal to
///   `orientable` for such files; the two agree on every file of the shared corpus);
/// - `orientable`: a consistent orientation exists; not reported for a hex mesh (null);
/// - `euler_characteristic` = nodes - edges + quads; `genus` = sum over components of
///   (2 - chi) / 2, null unless every component is closed, manifold and orientable;
/// - loops are traced across manifold edges; `self_crossing_quads` counts the quads some
///   loop crosses twice; the loop figures are null when there is a non-manifold edge;
/// - `coincident_nodes`: surface nodes falling in the same cell of a grid of step 1e-9 x the
///   largest extent of the bounding box, counted as (cell population - 1) per cell.

#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "stcweave/primal/handles.hpp"
#include "stcweave/primal/mesh.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/hex_complex.hpp"
#include "stcweave/stc/ids.hpp"
#include "stcweave/stc/surface_topology.hpp"

namespace stcweave::primal {

/// An edge as its two end nodes (file numbering).
using NodePair = std::array<NodeId, 2>;

/// A loop that crosses itself, with the quads where it does.
struct SelfIntersection {
  LoopId loop;
  std::size_t length = 0;
  std::vector<QuadId> quads;  ///< increasing
};

/// Where the defects of a surface are, to name them in messages. Node ids are those of the
/// file (0-based rows of its points), quad ids index the diagnosed surface's quads.
struct DefectSites {
  std::vector<NodePair> open_edges;
  std::vector<QuadId> open_edge_quads;  ///< per open edge, its quad
  std::vector<NodePair> nonmanifold_edges;
  std::vector<std::size_t> nonmanifold_edge_uses;  ///< per non-manifold edge, its quad sides
  std::vector<NodeId> nonmanifold_nodes;
  std::vector<QuadId> degenerate_quads;
  /// Quads on the same four nodes as an earlier quad: (earlier, later) pairs.
  std::vector<std::array<QuadId, 2>> duplicate_quads;
  std::vector<NodeId> nonfinite_nodes;
  /// A manifold edge where orientation conflicts with itself, with its two quads.
  std::optional<NodePair> orientation_conflict;
  std::array<QuadId, 2> orientation_conflict_quads;
  std::vector<SelfIntersection> self_intersecting_loops;
  /// Pairs of quads sharing no node whose surfaces pass through each other (lower index
  /// first, sorted).
  std::vector<std::array<QuadId, 2>> crossing_quads;
};

/// Every figure `diagnose` measures. Optional figures are null where the oracle's are.
struct SurfaceDiagnosis {
  std::string path;
  std::string format;
  bool from_hexes = false;    ///< the surface is the boundary of the file's hexes
  std::size_t hexes = 0;      ///< hexes in the file
  std::size_t triangles = 0;  ///< triangles in the file (a quad surface must have none)
  std::size_t tetrahedra = 0;
  std::size_t other_cells = 0;
  std::string first_other_cell;  ///< where and what the first other cell is (MeshFile's)

  std::size_t quads = 0;
  std::size_t nodes = 0;
  std::size_t components = 0;
  bool closed = false;
  bool manifold = false;
  bool consistently_oriented = false;
  std::optional<bool> orientable;  ///< null for a hex mesh
  long euler_characteristic = 0;
  std::optional<int> genus;
  std::vector<std::optional<int>> genus_per_component;  ///< by component id
  std::optional<std::size_t> loops;
  std::optional<std::size_t> self_intersecting_loops;
  std::optional<std::size_t> self_crossing_quads;
  std::optional<std::size_t> longest_loop;
  std::optional<std::size_t> open_loops;  ///< loops stopped by an open or degenerate side
  std::size_t open_edges = 0;
  std::size_t nonmanifold_edges = 0;
  std::size_t nonmanifold_nodes = 0;
  std::size_t inconsistent_edges = 0;  ///< manifold edges traversed twice the same way
  std::size_t coincident_nodes = 0;
  std::size_t degenerate_quads = 0;
  /// Quads on the same four nodes as an earlier quad (in any order): a quad given twice, or
  /// a closed surface of two quads. Two such quads enclose no volume (refused).
  std::size_t duplicate_quads = 0;
  std::size_t nonfinite_nodes = 0;
  /// Pairs of quads (sharing no node) that pass through each other: the surface intersects
  /// itself, so no solid has it as boundary and some hexes stay inverted (a warning, see
  /// `crossing_warning`; not refused). Null when not measured (a node with coordinates that
  /// are not finite). Touching and coplanar contacts are not counted, nor are folds between
  /// quads that share a node (docs/topology.md, "A surface that passes through itself").
  std::optional<std::size_t> crossing_quad_pairs;
  /// The largest absolute coordinate and the largest bounding-box extent of the finite
  /// surface nodes (0 when there are none): `require_weavable` refuses coordinates beyond
  /// `kLargestCoordinate` and extents below `kSmallestExtent`.
  double coordinate_magnitude = 0.0;
  double extent = 0.0;
  /// Faces of the hex mesh used by three or more hexes (0 for a surface file).
  std::size_t nonmanifold_hex_faces = 0;

  DefectSites sites;
  /// Handles (genus > 0, `diagnose_handles`), with node ids of the file; null when the genus
  /// is 0 or undefined, or the surface is not a closed, finite, orientable manifold.
  std::optional<HandleDiagnosis> handles;
  /// For a hex mesh, per boundary quad the hex face it comes from (empty otherwise).
  std::vector<stc::HexFaceRef> quad_origins;
  /// For a surface file, per quad its 1-based line in the file (0 or empty when unknown).
  std::vector<std::size_t> quad_lines;

  [[nodiscard]] bool has_even_quads() const { return quads % 2 == 0; }
};

/// The coordinate range the geometry stages work in. Their arithmetic multiplies up to six
/// coordinates (Jacobian determinants squared in the untangling energy, Gmsh's Delaunay
/// predicates in the tet interior), which overflows near 1e50 and underflows near 1e-50; the
/// bounds leave a wide margin, and no model in real units comes near them.
inline constexpr double kLargestCoordinate = 1e30;
inline constexpr double kSmallestExtent = 1e-30;

/// The quad surface of a file: the boundary of its hexes (via `stc::boundary_surface`,
/// oriented outward for positively oriented hexes, nodes compacted to those used, in
/// increasing order of their file ids), or else its quads with all its points.
/// \param file_nodes when given, receives for each node of the result its file node id.
/// \throw InvalidInput when a hex or quad refers to a node that is not a row of `points`.
[[nodiscard]] SurfaceMesh surface_of(const MeshFile& file,
                                     std::vector<NodeId>* file_nodes = nullptr);

/// Measures everything listed in `SurfaceDiagnosis` in O(n log n). Never throws on a
/// defect of the surface: that is `require_weavable`'s job.
/// \throw InvalidInput when a hex or quad refers to a node that is not a row of `points`.
[[nodiscard]] SurfaceDiagnosis diagnose(const MeshFile& file);

/// The diagnosis as JSON: the keys of `expected.json` (quads, nodes, components, closed,
/// manifold, consistently_oriented, orientable, euler_characteristic, genus, loops,
/// self_intersecting_loops, self_crossing_quads, longest_loop, open_edges,
/// nonmanifold_edges, coincident_nodes) plus path, format, source ("hex boundary" or
/// "file quads"), hexes, triangles, tetrahedra, other_cells, quad_parity ("even"/"odd"),
/// genus_per_component, open_loops, nonmanifold_nodes, inconsistent_edges,
/// degenerate_quads, nonfinite_nodes, coordinate_magnitude, extent, nonmanifold_hex_faces, the
/// self-intersecting loops with their quads, and weavable / defect (the message of
/// `require_weavable`, or null).
[[nodiscard]] nlohmann::json to_json(const SurfaceDiagnosis& diagnosis);

/// The warning for a surface that passes through itself (`crossing_quad_pairs` > 0), naming
/// the first pairs of quads by line or hex face; "" when no pair crosses.
[[nodiscard]] std::string crossing_warning(const SurfaceDiagnosis& diagnosis);

/// Throws when the diagnosed surface cannot be filled with hexes by weaving, with a message
/// naming the defect, the elements concerned (first few, and how many) and what to do.
/// Checked in this order, one message each: cells other than quads (triangles, ...; the
/// first one named by line), hexes without a boundary face, no quads at all,
/// non-finite coordinates, coordinates beyond `kLargestCoordinate`, an extent below
/// `kSmallestExtent`, degenerate quads, open surface, non-manifold edges,
/// non-manifold nodes, non-orientable surface, odd number of quads, an odd handle cycle
/// (a cycle of odd length bounding inside the solid: Erickson's obstruction), self-intersecting
/// loops. Genus > 0 and several components are not defects here (the weaver decides).
/// \param allow_self_intersecting_loops when true, self-intersecting loops are no defect
///        (the pipeline attaches hexes until they are gone, `weave_self_crossing`); an odd
///        number of quads still is.
/// \throw TopologyError on the first defect found.
void require_weavable(const SurfaceDiagnosis& diagnosis,
                      bool allow_self_intersecting_loops = false);

/// Throws InvalidInput, naming the first few, when a node of the file's hexes has a
/// non-finite coordinate (the certification and quality commands, which take a hex mesh as
/// it is, would otherwise report figures of NaN geometry as valid).
void require_finite_hex_nodes(const MeshFile& file);

/// What `orient_outward` did.
struct OrientationReport {
  std::size_t flipped_quads = 0;
  std::size_t components = 0;
  /// Per component, how many other closed components enclose it (a cavity has 1).
  std::vector<int> nesting_depth;
};

/// Orients the surface consistently, then each component outward: positive signed volume,
/// except a component enclosed by an odd number of other closed components (the surface
/// of a cavity), which gets a negative one so that its quads face away from the material.
/// (The brief asked for positive volume per component; that would turn a cavity inside out,
/// so enclosure is decided by ray parity against the other components.)
/// Components with zero volume (flat, open) keep the orientation of their first quad.
/// \throw TopologyError when a component is not orientable (naming a conflicting edge).
/// \throw InvalidInput when a quad refers to a node that is not a row of `points`.
OrientationReport orient_outward(SurfaceMesh& mesh);

}  // namespace stcweave::primal
