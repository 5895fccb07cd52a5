#pragma once
/// \file
/// Triangle-split quad surfaces and the split of tetrahedra into hexahedra (pure topology).
///
/// A triangle-split surface is a triangle mesh with every triangle cut into three quads at
/// its centre and its edges' middles: each quad is (vertex, edge node, centre, edge node).
/// CAD surfaces become such surfaces (docs/cad.md), and so do the boundaries of Gmsh's
/// all-hex meshes, which split every tetrahedron into four hexes. The same split of any
/// tetrahedral mesh of the solid whose boundary triangles are the surface's triangles gives
/// a hex complex whose boundary quads are exactly the surface's quads. Its STC has one cap
/// sheet per boundary vertex (bounded by the loop around it) and one closed blind sheet
/// around each interior vertex (docs/tet-interior.md).

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::stc {

/// The triangle mesh behind a triangle-split quad surface.
struct TriangleSplit {
  /// Per triangle its three vertex nodes, in the order the quads run round them (outward
  /// for an outward surface).
  std::vector<std::array<NodeId, 3>> triangles;
  /// Per triangle, the node at its centre (in three quads, those of this triangle).
  std::vector<NodeId> centres;
  /// Per triangle, the node on its edge (triangles[t][i], triangles[t][(i + 1) % 3]).
  std::vector<std::array<NodeId, 3>> edge_nodes;
  /// Per triangle, its three quads: quad i is the one at vertex triangles[t][i].
  std::vector<std::array<QuadId, 3>> quads;
  /// The surface nodes that are triangle vertices, increasing.
  std::vector<NodeId> vertices;
};

/// Recognises a closed triangle-split quad surface: a 2-colouring of its nodes puts the edge
/// nodes (four quads each) on one side; a 2-colouring of the other nodes by the quads'
/// diagonals separates the centres (three quads each) from the vertices. Where both colours
/// of that second colouring could be centres, the larger class is taken (a closed triangle
/// mesh of genus 0 with more than four vertices has more triangles than vertices); on a tie
/// (a tetrahedron split, where either reading is a triangle mesh) the class of the smallest
/// node id are the vertices.
/// \return the triangles, or nothing when the surface is not one (any quad not of the form
///         (vertex, edge node, centre, edge node), a triangle edge with two edge nodes, an
///         edge node between more or fewer than two triangles, an open surface).
[[nodiscard]] std::optional<TriangleSplit> recognise_triangle_split(const QuadSurface& surface);

/// A tetrahedron over node ids, positively oriented: (b - a, c - a, d - a) is a right-handed
/// frame.
using Tet = std::array<NodeId, 4>;

/// The four-hex split of a tetrahedral mesh.
struct TetSplit {
  /// Nodes 0 .. num_nodes - 1 are the tet vertices' ids as given (the surface's nodes first);
  /// the nodes added follow, tet by tet in the order given: the middles of its edges and the
  /// centres of its faces not met before (interior ones only), then its centre.
  HexComplex complex;
  /// Per added node (complex node `first_added + i`), the tet vertices it is the centre of
  /// (2 for an edge, 3 for a face, 4 for a tet).
  std::vector<std::vector<NodeId>> added_parents;
  std::size_t first_added = 0;
  std::size_t interior_edges = 0;
  std::size_t interior_faces = 0;
};

/// Splits each tetrahedron into four hexes, one at each vertex, made of the vertex, the
/// middles of its three edges there, the centres of its three faces there and the tet's
/// centre. The middles and centres on the boundary are the surface's own edge nodes and
/// centres (`split`), so the hexes' boundary is exactly the surface's quads.
/// \pre `split` comes from `recognise_triangle_split` of a surface with `num_nodes` nodes or
///      fewer; node ids below `num_nodes` that are not vertices of `split` are the surface's
///      edge nodes and centres and must not appear in `tets`.
/// \throw InvalidInput when a tet repeats a node, uses a surface edge node or centre, or a
///        node id of `num_nodes` or more, or when a boundary triangle is not the face of
///        exactly one tet, or an interior face not of exactly two.
[[nodiscard]] TetSplit split_tets(const TriangleSplit& split, std::size_t num_nodes,
                                  const std::vector<Tet>& tets);

}  // namespace stcweave::stc
