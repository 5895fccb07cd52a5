#include "stcweave/stc/tet_split.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <utility>
#include <vector>

#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/shapes.hpp"

namespace stcweave::stc {
namespace {

using Triangle = std::array<int, 3>;
using Point = std::array<double, 3>;

using Built = test::SplitTriangles;

/// The split of `triangles` over `num_vertices` vertices, topology only (points at 0).
Built split_by_hand(const std::vector<Triangle>& triangles, int num_vertices) {
  return test::split_triangles(triangles, primal::Points::Zero(num_vertices, 3));
}

// The octahedron with vertices +x, +y, -x, -y, +z, -z (ids 0..5), outward.
const std::vector<Triangle> kOctahedron = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4},
                                           {1, 0, 5}, {2, 1, 5}, {3, 2, 5}, {0, 3, 5}};
const std::vector<Point> kOctahedronPoints = {{1, 0, 0},  {0, 1, 0}, {-1, 0, 0},
                                              {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
// A tetrahedron, outward.
const std::vector<Triangle> kTetrahedron = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};

/// The tet with its vertices ordered so that it is positively oriented at `points`.
Tet positive(std::array<int, 4> v, const std::vector<Point>& points) {
  const auto d = [&](int a, int b, int k) {
    return points[static_cast<std::size_t>(b)][static_cast<std::size_t>(k)] -
           points[static_cast<std::size_t>(a)][static_cast<std::size_t>(k)];
  };
  const double det =
      d(v[0], v[1], 0) *
          (d(v[0], v[2], 1) * d(v[0], v[3], 2) - d(v[0], v[2], 2) * d(v[0], v[3], 1)) -
      d(v[0], v[1], 1) *
          (d(v[0], v[2], 0) * d(v[0], v[3], 2) - d(v[0], v[2], 2) * d(v[0], v[3], 0)) +
      d(v[0], v[1], 2) *
          (d(v[0], v[2], 0) * d(v[0], v[3], 1) - d(v[0], v[2], 1) * d(v[0], v[3], 0));
  if (det < 0) std::swap(v[2], v[3]);
  return {NodeId(v[0]), NodeId(v[1]), NodeId(v[2]), NodeId(v[3])};
}

/// The octahedron cut into four tets around its axis 4-5.
std::vector<Tet> octahedron_axis_tets() {
  std::vector<Tet> tets;
  for (int i = 0; i < 4; ++i) tets.push_back(positive({4, 5, i, (i + 1) % 4}, kOctahedronPoints));
  return tets;
}

TEST(TriangleSplit, RecognisesTheOctahedronsTrianglesAndNodes) {
  const Built b = split_by_hand(kOctahedron, 6);
  const std::optional<TriangleSplit> split = recognise_triangle_split(b.mesh.surface);
  ASSERT_TRUE(split.has_value());
  ASSERT_EQ(split->triangles.size(), 8U);
  EXPECT_EQ(split->vertices, (std::vector<NodeId>{NodeId(0), NodeId(1), NodeId(2), NodeId(3),
                                                  NodeId(4), NodeId(5)}));
  // Every triangle is one of the octahedron's, in its own orientation, with its own nodes.
  std::set<std::array<int, 3>> found;
  for (std::size_t t = 0; t < split->triangles.size(); ++t) {
    const auto& tri = split->triangles[t];
    // Rotate so that the smallest vertex is first (keeps the orientation).
    std::size_t first = 0;
    for (std::size_t k = 1; k < 3; ++k)
      if (tri[k] < tri[first]) first = k;
    found.insert({tri[first].value(), tri[(first + 1) % 3].value(), tri[(first + 2) % 3].value()});
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(split->edge_nodes[t][k],
                b.edge_node.at(std::minmax(tri[k].value(), tri[(k + 1) % 3].value())));
    }
    EXPECT_EQ(b.mesh.surface.quads[split->quads[t][0].index()][0], tri[0]);
    EXPECT_EQ(b.mesh.surface.quads[split->quads[t][0].index()][2], split->centres[t]);
  }
  std::set<std::array<int, 3>> expected;
  for (const Triangle& t : kOctahedron) {
    std::size_t first = 0;
    for (std::size_t k = 1; k < 3; ++k)
      if (t[k] < t[first]) first = k;
    expected.insert({t[first], t[(first + 1) % 3], t[(first + 2) % 3]});
  }
  EXPECT_EQ(found, expected);
}

TEST(TriangleSplit, ATetrahedronSplitIsReadWithItsSmallestNodeAVertex) {
  const Built b = split_by_hand(kTetrahedron, 4);
  const std::optional<TriangleSplit> split = recognise_triangle_split(b.mesh.surface);
  ASSERT_TRUE(split.has_value());
  EXPECT_EQ(split->triangles.size(), 4U);
  EXPECT_EQ(split->vertices.front(), NodeId(0));
  EXPECT_EQ(split->vertices.size(), 4U);
}

TEST(TriangleSplit, SurfacesThatAreNotSplitTrianglesAreNotRecognised) {
  // Boxes of quads: no (vertex, edge node, centre, edge node) reading of their quads.
  EXPECT_FALSE(recognise_triangle_split(test::box_surface(3, 3, 3).surface).has_value());
  EXPECT_FALSE(recognise_triangle_split(test::box_surface(3, 2, 1).surface).has_value());
  // A split octahedron with one triangle's quads re-cut the other way round is not one.
  Built b = split_by_hand(kOctahedron, 6);
  std::swap(b.mesh.surface.quads[0][1], b.mesh.surface.quads[0][3]);
  EXPECT_FALSE(recognise_triangle_split(b.mesh.surface).has_value());
  // Nor is an open one (a triangle's quads removed).
  Built open = split_by_hand(kOctahedron, 6);
  open.mesh.surface.quads.resize(open.mesh.surface.quads.size() - 3);
  EXPECT_FALSE(recognise_triangle_split(open.mesh.surface).has_value());
  EXPECT_FALSE(recognise_triangle_split(QuadSurface{}).has_value());
}

TEST(TriangleSplit, TheTwoByTwoByTwoBoxIsTheOctahedronSplit) {
  // Its face centres are the octahedron's vertices, its corners the triangles' centres.
  const primal::SurfaceMesh box = test::box_surface(2, 2, 2);
  const std::optional<TriangleSplit> split = recognise_triangle_split(box.surface);
  ASSERT_TRUE(split.has_value());
  EXPECT_EQ(split->triangles.size(), 8U);
  ASSERT_EQ(split->vertices.size(), 6U);
  for (const NodeId v : split->vertices) {
    // A face centre of the box: one coordinate at 0 or 2, the two others at 1.
    int ones = 0;
    for (int c = 0; c < 3; ++c) ones += box.points(v.value(), c) == 1.0 ? 1 : 0;
    EXPECT_EQ(ones, 2) << v;
  }
}

TEST(TetSplit, OneTetrahedronGivesFourHexesBoundedByTheSurface) {
  const Built b = split_by_hand(kTetrahedron, 4);
  const TriangleSplit split = *recognise_triangle_split(b.mesh.surface);
  const std::vector<Point> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const TetSplit cut =
      split_tets(split, b.mesh.surface.num_nodes, {positive({0, 1, 2, 3}, points)});
  EXPECT_EQ(cut.complex.hexes.size(), 4U);
  EXPECT_EQ(cut.first_added, b.mesh.surface.num_nodes);
  EXPECT_EQ(cut.added_parents.size(), 1U);  // the tet's centre only
  EXPECT_EQ(cut.interior_edges, 0U);
  EXPECT_EQ(cut.interior_faces, 0U);
  const ValidationReport v = validate_hex_complex(cut.complex, &b.mesh.surface);
  EXPECT_TRUE(v.valid) << v.summary();
}

TEST(TetSplit, TheOctahedronCutIntoFourTetsAroundItsAxisIsAValidComplex) {
  const Built b = split_by_hand(kOctahedron, 6);
  const TriangleSplit split = *recognise_triangle_split(b.mesh.surface);
  const std::vector<Tet> tets = octahedron_axis_tets();
  const TetSplit cut = split_tets(split, b.mesh.surface.num_nodes, tets);
  EXPECT_EQ(cut.complex.hexes.size(), 16U);
  EXPECT_EQ(cut.interior_edges, 1U);  // the axis 4-5
  EXPECT_EQ(cut.interior_faces, 4U);  // the four half-planes through the axis
  EXPECT_EQ(cut.added_parents.size(), 1U + 4U + 4U);
  const ValidationReport v = validate_hex_complex(cut.complex, &b.mesh.surface);
  EXPECT_TRUE(v.valid) << v.summary();
  // The same tets with one of them mirrored break the face orientation: not a complex.
  std::vector<Tet> mirrored = tets;
  std::swap(mirrored[0][2], mirrored[0][3]);
  EXPECT_FALSE(validate_hex_complex(split_tets(split, b.mesh.surface.num_nodes, mirrored).complex,
                                    &b.mesh.surface)
                   .valid);
}

TEST(TetSplit, AnInteriorVertexGetsHexesAroundIt) {
  // The tetrahedron coned from an interior node 4 (ids after the surface's nodes).
  const Built b = split_by_hand(kTetrahedron, 4);
  const TriangleSplit split = *recognise_triangle_split(b.mesh.surface);
  const std::size_t centre = b.mesh.surface.num_nodes;
  std::vector<Point> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  points.resize(centre + 1, {0.0, 0.0, 0.0});
  points[centre] = {0.25, 0.25, 0.25};
  std::vector<Tet> tets;
  for (const Triangle& t : kTetrahedron)
    tets.push_back(positive({t[0], t[1], t[2], static_cast<int>(centre)}, points));
  const TetSplit cut = split_tets(split, centre + 1, tets);
  EXPECT_EQ(cut.complex.hexes.size(), 16U);
  EXPECT_EQ(cut.interior_edges, 4U);
  EXPECT_EQ(cut.interior_faces, 6U);
  std::size_t at_centre = 0;
  for (const Hex& h : cut.complex.hexes) at_centre += h[0] == NodeId(centre) ? 1 : 0;
  EXPECT_EQ(at_centre, 4U);  // one hex of each tet at the interior vertex: a closed sheet
  const ValidationReport v = validate_hex_complex(cut.complex, &b.mesh.surface);
  EXPECT_TRUE(v.valid) << v.summary();
}

TEST(TetSplit, RefusesTetsThatDoNotKeepTheSurface) {
  const Built b = split_by_hand(kOctahedron, 6);
  const TriangleSplit split = *recognise_triangle_split(b.mesh.surface);
  const std::vector<Tet> tets = octahedron_axis_tets();
  // A missing tet leaves two boundary triangles uncovered.
  const std::vector<Tet> three(tets.begin(), tets.begin() + 3);
  EXPECT_THROW((void)split_tets(split, b.mesh.surface.num_nodes, three), InvalidInput);
  // A tet twice covers its boundary triangles twice.
  std::vector<Tet> twice = tets;
  twice.push_back(tets[0]);
  EXPECT_THROW((void)split_tets(split, b.mesh.surface.num_nodes, twice), InvalidInput);
  // A tet on an edge node (not a triangle vertex), a repeated node, an unknown node.
  std::vector<Tet> bad = tets;
  bad[0][0] = b.edge_node.at({0, 1});
  EXPECT_THROW((void)split_tets(split, b.mesh.surface.num_nodes, bad), InvalidInput);
  bad = tets;
  bad[0][1] = bad[0][0];
  EXPECT_THROW((void)split_tets(split, b.mesh.surface.num_nodes, bad), InvalidInput);
  bad = tets;
  bad[0][0] = NodeId(b.mesh.surface.num_nodes + 3);
  EXPECT_THROW((void)split_tets(split, b.mesh.surface.num_nodes, bad), InvalidInput);
}

}  // namespace
}  // namespace stcweave::stc
