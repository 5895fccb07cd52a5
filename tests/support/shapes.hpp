#pragma once
/// \file
/// Test shapes generated in code: structured boxes (surface and hex mesh), the seed's
/// Fig. 5 bar, the rhombic dodecahedron. Surfaces are oriented outward.

#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::test {

/// `surface` as the in-memory file the pipeline reads (`primal::mesh_file`): path `name`,
/// format "memory", the surface's points and quads.
primal::MeshFile file_of(const primal::SurfaceMesh& surface, const std::string& name);

/// The a x b x c structured hex mesh of the box [0,a*sx] x [0,b*sy] x [0,c*sz], hexes
/// positively oriented (VTK order). Node (i,j,k) has id i + (a+1)(j + (b+1)k).
primal::HexMesh box_hexes(int a, int b, int c, double sx = 1.0, double sy = 1.0, double sz = 1.0);

/// The boundary of `box_hexes(a,b,c)`: 2(ab+bc+ca) quads, outward, nodes renumbered
/// 0..n-1 in increasing order of their hex-mesh ids.
primal::SurfaceMesh box_surface(int a, int b, int c, double sx = 1.0, double sy = 1.0,
                                double sz = 1.0);

/// The boundary quads of a hex mesh (faces used by one hex, outward), nodes renumbered
/// compactly. Independent of the library's own extraction, for cross-checks.
primal::SurfaceMesh boundary_of(const primal::HexMesh& mesh);

/// The hex mesh of a union of unit cubes (voxel (i,j,k) = [i,i+1]x[j,j+1]x[k,k+1]), hexes
/// positively oriented, shared nodes merged.
primal::HexMesh voxel_hexes(const std::vector<std::array<int, 3>>& cells);

/// The boundary of `voxel_hexes(cells)`.
primal::SurfaceMesh voxel_surface(const std::vector<std::array<int, 3>>& cells);

/// Ten unit cubes: 3x3x2 minus a 2x2x2 corner (an L-block).
std::vector<std::array<int, 3>> lblock_cells();

/// Eight unit cubes: the 3x3x1 slab minus its centre (a square ring, genus 1).
std::vector<std::array<int, 3>> ring_cells();

/// The boundary of a column of n = sections.size() - 1 hexes (4n + 2 quads, the topology of
/// `box_surface(1, 1, n)`) whose k-th cross-section has the corners `sections[k]`, listed as
/// the box's nodes (0,0), (1,0), (1,1), (0,1) of layer k. Outward when every hex of the column
/// is positively oriented (as for the straight bar, cross-sections counter-clockwise seen from
/// the next one). \pre sections.size() >= 2.
primal::SurfaceMesh bar_surface(const std::vector<std::array<Eigen::RowVector3d, 4>>& sections);

/// A planar quad mesh: points in the xy-plane and counter-clockwise quads over them.
struct PlanarQuads {
  std::vector<Eigen::RowVector2d> points;
  std::vector<std::array<int, 4>> quads;
};

/// The O-grid disk of radius 1: a 2 x 2 grid on the square [-s, s]^2 ringed by 8 quads out to
/// 8 points of the unit circle (12 quads, 17 points).
PlanarQuads ogrid_disk(double s = 0.35);

/// The prism over `section`: one layer of hexes between each two consecutive heights (z),
/// hexes positively oriented. \pre heights increasing, at least two.
primal::HexMesh extruded_hexes(const PlanarQuads& section, const std::vector<double>& heights);

/// The rhombic dodecahedron: 12 rhombi, 14 nodes, outward.
primal::SurfaceMesh rhombic_dodecahedron();

/// A surface with every quad reversed (inward).
primal::SurfaceMesh reversed_surface(primal::SurfaceMesh mesh);

/// A torus about the z axis: `around` quads round the tube (a regular polygon of radius `r`
/// as cross-section, so 3 gives a triangular tube), `along` quads along it (centre radius
/// `big_r`); around x along quads, outward. \pre around >= 3, along >= 3, big_r > r > 0.
primal::SurfaceMesh torus_surface(int around, int along, double big_r = 3.0, double r = 1.0);

/// The union of `surfaces` (nodes of each renumbered after the previous ones).
primal::SurfaceMesh merged_surfaces(const std::vector<primal::SurfaceMesh>& surfaces);

/// Every point of `mesh` moved by `offset`.
primal::SurfaceMesh translated(primal::SurfaceMesh mesh, const Eigen::RowVector3d& offset);

/// A triangle mesh (outward, vertex ids 0 .. V-1 at the rows of `vertices`) with every
/// triangle split into three quads at its centre and the middles of its edges, built
/// independently of stc::recognise_triangle_split: the vertices keep their ids, then one node
/// per edge in order of first use (at its middle), then one per triangle (at its centroid).
struct SplitTriangles {
  primal::SurfaceMesh mesh;
  std::map<std::pair<int, int>, NodeId> edge_node;  ///< (smaller, larger vertex id) -> node
  std::vector<NodeId> centre;                       ///< per triangle
};
SplitTriangles split_triangles(const std::vector<std::array<int, 3>>& triangles,
                               const primal::Points& vertices);

/// The triangle-split surface of a quad surface: each quad cut into two triangles along its
/// diagonal (0, 2), then `split_triangles`.
primal::SurfaceMesh triangle_split_of(const primal::SurfaceMesh& quads);

}  // namespace stcweave::test
