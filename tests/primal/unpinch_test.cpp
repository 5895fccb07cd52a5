// Pinched face pairs and their removal (`pinched_faces`, `unpinch`; docs/geometry.md
// "Pinched faces"): a hand-built star of hexes around one node whose link holds two
// parallel edges, which no placement can make valid, and the 2-hex pillow that removes it.
#include <gtest/gtest.h>

#include <array>
#include <map>
#include <utility>

#include "../../primal/src/position_pinch.hpp"
#include "position_helpers.hpp"
#include "stcweave/primal/pillow.hpp"
#include "stcweave/primal/position.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/hex_complex.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

/// The hexes around one node n whose vertex link is a sphere triangulation with two
/// distinct edges between the link vertices a and b (the faces n-a-m1-b and n-a-m2-b):
/// each link triangle (p, q, r) is the hex corner at n with edge neighbours p, q, r.
/// Nodes: 6 link vertices (a, b, c, d, e, f = 0..5), 12 link edges (6..17), 8 triangle
/// centres (18..25), n = 26 (the only interior node, numbered last as the pipeline does).
HexMesh pinched_star() {
  constexpr int a = 0, b = 1, c = 2, d = 3, e = 4, f = 5;
  // Edges of the link, the two a-b edges first (ab1 = 0, ab2 = 1).
  const std::array<std::pair<int, int>, 12> edges = {{{a, b},
                                                      {a, b},
                                                      {a, c},
                                                      {b, c},
                                                      {c, d},
                                                      {a, d},
                                                      {b, d},
                                                      {a, e},
                                                      {b, e},
                                                      {e, f},
                                                      {a, f},
                                                      {b, f}}};
  // Triangles, counter-clockwise seen from outside, with the edge of each side (p-q, q-r,
  // r-p). D1 (around +y) between ab1 and ab2 holds c, d; D2 (around -y) holds e, f.
  struct Triangle {
    std::array<int, 3> v;
    std::array<int, 3> e;
  };
  const std::array<Triangle, 8> triangles = {{{{a, b, c}, {0, 3, 2}},
                                              {{a, c, d}, {2, 4, 5}},
                                              {{c, b, d}, {3, 6, 4}},
                                              {{a, d, b}, {5, 6, 1}},
                                              {{a, b, e}, {1, 8, 7}},
                                              {{a, e, f}, {7, 9, 10}},
                                              {{e, b, f}, {8, 11, 9}},
                                              {{a, f, b}, {10, 11, 0}}}};
  const std::array<Eigen::RowVector3d, 6> dir = {
      Eigen::RowVector3d(0, 0, 1),    Eigen::RowVector3d(0, 0, -1),
      Eigen::RowVector3d(0, 1, 0.4),  Eigen::RowVector3d(0.2, 1, -0.4),
      Eigen::RowVector3d(0, -1, 0.4), Eigen::RowVector3d(-0.2, -1, -0.4)};
  constexpr int n = 26;
  HexMesh m;
  m.points.resize(27, 3);
  m.points.row(n) = Eigen::RowVector3d::Zero();
  for (int v = 0; v < 6; ++v) m.points.row(v) = dir[static_cast<std::size_t>(v)].normalized();
  for (int k = 0; k < 12; ++k) {
    const auto [p, q] = edges[static_cast<std::size_t>(k)];
    Eigen::RowVector3d mid = m.points.row(p) + m.points.row(q);
    if (k < 2) mid = Eigen::RowVector3d(k == 0 ? 1.0 : -1.0, 0, 0);
    m.points.row(6 + k) = 1.4 * mid.normalized();
  }
  for (int t = 0; t < 8; ++t) {
    Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
    for (const int v : triangles[static_cast<std::size_t>(t)].v) centre += m.points.row(v);
    m.points.row(18 + t) = 1.7 * centre.normalized();
  }
  m.complex.num_nodes = 27;
  for (int t = 0; t < 8; ++t) {
    const Triangle& tr = triangles[static_cast<std::size_t>(t)];
    const auto node = [](int i) { return NodeId(i); };
    // Corner 0 = n with neighbours 1 = p, 3 = q, 4 = r (VTK order).
    m.complex.hexes.push_back({node(n), node(tr.v[0]), node(6 + tr.e[0]), node(tr.v[1]),
                               node(tr.v[2]), node(6 + tr.e[2]), node(18 + t), node(6 + tr.e[1])});
  }
  return m;
}

stc::QuadSurface boundary_of_star(const HexMesh& m) {
  stc::QuadSurface s = stc::boundary_surface(m.complex);
  s.num_nodes = 26;  // node 26 (n) is the interior one
  return s;
}

TEST(Unpinch, TheHandBuiltStarIsAValidComplexWithOnePinchedPair) {
  const HexMesh star = pinched_star();
  const stc::QuadSurface boundary = boundary_of_star(star);
  EXPECT_EQ(boundary.quads.size(), 24u);
  const stc::ValidationReport v = stc::validate_hex_complex(star.complex, &boundary);
  EXPECT_TRUE(v.valid) << v.summary();
  const std::vector<PinchedFaces> pinched = pinched_faces(star.complex);
  ASSERT_EQ(pinched.size(), 1u);
  EXPECT_EQ(pinched[0].node, NodeId(26));
  EXPECT_EQ(pinched[0].a, NodeId(0));
  EXPECT_EQ(pinched[0].b, NodeId(1));
}

TEST(Unpinch, PillowsOneTwoHexBlockAndLeavesNoPinchedPair) {
  HexMesh mesh = pinched_star();
  const stc::QuadSurface boundary = boundary_of_star(mesh);
  // As the pipeline does: the boundary pillow first, so the pinch has interior nodes only.
  PillowOptions always;
  always.mode = PillowMode::Always;
  ASSERT_TRUE(pillow(mesh, boundary, always).applied);
  ASSERT_EQ(pinched_faces(mesh.complex).size(), 1u) << "the boundary pillow keeps the pinch";
  const std::size_t hexes = mesh.complex.hexes.size();
  const std::size_t nodes = mesh.complex.num_nodes;

  const UnpinchReport r = unpinch(mesh, boundary.num_nodes, boundary);
  EXPECT_EQ(r.pinched_before, 1u);
  EXPECT_EQ(r.blocks, 1u);
  EXPECT_EQ(r.hexes_added, 10u);
  EXPECT_EQ(r.nodes_added, 12u);
  EXPECT_EQ(r.pinched_after, 0u);
  EXPECT_EQ(mesh.complex.hexes.size(), hexes + 10);
  EXPECT_EQ(mesh.complex.num_nodes, nodes + 12);
  EXPECT_EQ(static_cast<std::size_t>(mesh.points.rows()), nodes + 12);
  EXPECT_TRUE(pinched_faces(mesh.complex).empty());
  const stc::ValidationReport v = stc::validate_hex_complex(mesh.complex, &boundary);
  EXPECT_TRUE(v.valid) << v.summary();
}

TEST(Unpinch, LeavesAPinchWhoseBlocksTouchTheBoundary) {
  // Unpillowed, every hex of the star has boundary nodes: no block may be used.
  HexMesh mesh = pinched_star();
  const stc::QuadSurface boundary = boundary_of_star(mesh);
  const HexMesh before = mesh;
  const UnpinchReport r = unpinch(mesh, boundary.num_nodes, boundary);
  EXPECT_EQ(r.pinched_before, 1u);
  EXPECT_EQ(r.blocks, 0u);
  EXPECT_EQ(r.pinched_after, 1u);
  EXPECT_EQ(mesh.complex.hexes, before.complex.hexes);
  EXPECT_EQ(mesh.points, before.points);
}

TEST(Unpinch, ChangesNothingWithoutAPinchedPair) {
  HexMesh mesh = test::box_hexes(3, 3, 3);
  const std::size_t nb = test::boundary_first(mesh);
  stc::QuadSurface boundary = stc::boundary_surface(mesh.complex);
  boundary.num_nodes = nb;
  const HexMesh before = mesh;
  const UnpinchReport r = unpinch(mesh, nb, boundary);
  EXPECT_EQ(r.pinched_before, 0u);
  EXPECT_EQ(r.blocks, 0u);
  EXPECT_EQ(mesh.complex.hexes, before.complex.hexes);
  EXPECT_EQ(mesh.points, before.points);
}

}  // namespace
}  // namespace stcweave::primal
