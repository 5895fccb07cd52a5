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
#include "support/pinched_star.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

HexMesh pinched_star() {
  const test::PinchedStar star = test::pinched_star();
  HexMesh m;
  m.complex = star.complex;
  m.points.resize(static_cast<Eigen::Index>(star.points.size()), 3);
  for (std::size_t v = 0; v < star.points.size(); ++v)
    for (Eigen::Index k = 0; k < 3; ++k)
      m.points(static_cast<Eigen::Index>(v), k) = star.points[v][static_cast<std::size_t>(k)];
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
