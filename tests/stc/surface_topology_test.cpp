/// Tests of stc/surface_topology.hpp: adjacency, defects, orientation, components, genus.

#include "stcweave/stc/surface_topology.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <map>
#include <tuple>

#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::stc {
namespace {

/// The quads of several meshes as one surface, nodes at the same position merged.
QuadSurface merge_by_position(const std::vector<primal::SurfaceMesh>& parts) {
  QuadSurface out;
  std::map<std::tuple<double, double, double>, NodeId> ids;
  for (const auto& part : parts) {
    for (Quad q : part.surface.quads) {
      for (NodeId& v : q) {
        const auto p = part.points.row(v.value());
        const auto key = std::make_tuple(p(0), p(1), p(2));
        auto [it, inserted] = ids.emplace(key, NodeId(ids.size()));
        v = it->second;
      }
      out.quads.push_back(q);
    }
  }
  out.num_nodes = ids.size();
  return out;
}

primal::SurfaceMesh translated(primal::SurfaceMesh m, double x, double y, double z) {
  for (Eigen::Index r = 0; r < m.points.rows(); ++r) m.points.row(r) += Eigen::RowVector3d(x, y, z);
  return m;
}

/// An n x m grid on a torus (identify i mod n, j mod m); with `klein`, the seam j = m is
/// glued to j = 0 with i mirrored, which makes a Klein bottle.
QuadSurface torus_grid(int n, int m, bool klein = false) {
  QuadSurface s;
  const auto node = [&](int i, int j) {
    if (j == m) {
      j = 0;
      if (klein) i = n - i;
    }
    i = ((i % n) + n) % n;
    return NodeId(i + n * j);
  };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i)
      s.quads.push_back({node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)});
  s.num_nodes = static_cast<std::size_t>(n * m);
  return s;
}

TEST(SurfaceTopology, BoxIsClosedOrientedSphere) {
  const auto box = test::box_surface(2, 3, 4);
  const SurfaceTopology t = surface_topology(box.surface);
  EXPECT_EQ(t.num_quads(), 52u);
  EXPECT_EQ(t.edges.size(), 104u);  // 2 x quads on a closed quad surface
  EXPECT_EQ(t.num_nodes_used, 54u);
  EXPECT_TRUE(t.is_closed());
  EXPECT_TRUE(t.is_manifold());
  EXPECT_TRUE(t.is_orientable());
  EXPECT_TRUE(t.is_consistently_oriented());
  EXPECT_EQ(t.euler_characteristic(), 2);
  EXPECT_EQ(t.genus(), 0);
  ASSERT_EQ(t.components.size(), 1u);
  EXPECT_EQ(t.components[0].genus, 0);
  EXPECT_TRUE(t.degenerate_quads.empty());
  for (bool f : t.orientation_flips) EXPECT_FALSE(f);
}

TEST(SurfaceTopology, NeighboursAreSymmetricAndShareTheEdgeReversed) {
  const auto box = test::box_surface(2, 2, 1);
  const SurfaceTopology t = surface_topology(box.surface);
  for (std::size_t q = 0; q < t.num_quads(); ++q) {
    for (int i = 0; i < 4; ++i) {
      const QuadSide s{QuadId(q), i};
      const QuadSide n = t.neighbour(s);
      ASSERT_TRUE(n.is_valid()) << s.quad << " side " << i;
      EXPECT_NE(n.quad, s.quad);
      EXPECT_EQ(t.neighbour(n), s);
      EXPECT_EQ(t.edge_of(n), t.edge_of(s));
      const auto a = side_nodes(box.surface, s);
      const auto b = side_nodes(box.surface, n);
      EXPECT_EQ(a[0], b[1]);
      EXPECT_EQ(a[1], b[0]);
      EXPECT_EQ(t.uses(t.edge_of(s)).size(), 2u);
    }
  }
}

TEST(SurfaceTopology, CubeWithAQuadRemovedIsOpen) {
  auto box = test::box_surface(1, 1, 1);
  box.surface.quads.pop_back();
  const SurfaceTopology t = surface_topology(box.surface);
  EXPECT_EQ(t.open_edges.size(), 4u);
  EXPECT_TRUE(t.nonmanifold_edges.empty());
  EXPECT_FALSE(t.is_closed());
  EXPECT_TRUE(t.is_manifold());  // a disk: its boundary nodes are not defects
  EXPECT_EQ(t.euler_characteristic(), 1);
  EXPECT_EQ(t.genus(), std::nullopt);
  for (EdgeId e : t.open_edges) {
    ASSERT_EQ(t.uses(e).size(), 1u);
    EXPECT_FALSE(t.neighbour(t.uses(e)[0]).is_valid());
  }
}

TEST(SurfaceTopology, TwoCubesSharingAnEdgeAreNonManifold) {
  const auto cube = test::box_surface(1, 1, 1);
  const QuadSurface s = merge_by_position({cube, translated(cube, 1, 1, 0)});
  ASSERT_EQ(s.num_nodes, 14u);
  const SurfaceTopology t = surface_topology(s);
  ASSERT_EQ(t.nonmanifold_edges.size(), 1u);
  EXPECT_EQ(t.uses(t.nonmanifold_edges[0]).size(), 4u);
  EXPECT_FALSE(t.is_manifold());
  EXPECT_FALSE(t.is_closed());
  EXPECT_EQ(t.components.size(), 1u);  // connected through the shared edge
  EXPECT_EQ(t.genus(), std::nullopt);
  for (const QuadSide& use : t.uses(t.nonmanifold_edges[0]))
    EXPECT_FALSE(t.neighbour(use).is_valid());
}

TEST(SurfaceTopology, TwoCubesSharingANodeHaveANonManifoldNode) {
  const auto cube = test::box_surface(1, 1, 1);
  const QuadSurface s = merge_by_position({cube, translated(cube, 1, 1, 1)});
  ASSERT_EQ(s.num_nodes, 15u);
  const SurfaceTopology t = surface_topology(s);
  EXPECT_TRUE(t.nonmanifold_edges.empty());
  ASSERT_EQ(t.nonmanifold_nodes.size(), 1u);
  EXPECT_TRUE(t.is_closed());
  EXPECT_FALSE(t.is_manifold());
  EXPECT_EQ(t.components.size(), 2u);
  EXPECT_FALSE(t.components[0].manifold);
  EXPECT_FALSE(t.components[1].manifold);
  EXPECT_EQ(t.genus(), std::nullopt);
}

TEST(SurfaceTopology, TwoSeparateCubesAreTwoSpheres) {
  const auto cube = test::box_surface(1, 1, 1);
  const QuadSurface s = merge_by_position({cube, translated(cube, 3, 0, 0)});
  const SurfaceTopology t = surface_topology(s);
  EXPECT_EQ(t.components.size(), 2u);
  EXPECT_EQ(t.euler_characteristic(), 4);
  EXPECT_EQ(t.genus(), 0);
  for (std::size_t q = 0; q < 6; ++q) EXPECT_EQ(t.quad_components[q], ComponentId(0));
  for (std::size_t q = 6; q < 12; ++q) EXPECT_EQ(t.quad_components[q], ComponentId(1));
}

TEST(SurfaceTopology, TorusHasGenusOne) {
  const SurfaceTopology t = surface_topology(torus_grid(5, 4));
  EXPECT_TRUE(t.is_closed());
  EXPECT_TRUE(t.is_manifold());
  EXPECT_TRUE(t.is_orientable());
  EXPECT_TRUE(t.is_consistently_oriented());
  EXPECT_EQ(t.euler_characteristic(), 0);
  EXPECT_EQ(t.genus(), 1);
}

TEST(SurfaceTopology, KleinBottleIsClosedManifoldButNotOrientable) {
  const QuadSurface s = torus_grid(5, 4, /*klein=*/true);
  const SurfaceTopology t = surface_topology(s);
  EXPECT_TRUE(t.is_closed());
  EXPECT_TRUE(t.is_manifold());
  EXPECT_FALSE(t.is_orientable());
  EXPECT_FALSE(t.is_consistently_oriented());
  EXPECT_EQ(t.euler_characteristic(), 0);
  EXPECT_EQ(t.genus(), std::nullopt);
  ASSERT_EQ(t.orientation_conflicts.size(), 1u);
  EXPECT_EQ(t.uses(t.orientation_conflicts[0]).size(), 2u);
  EXPECT_FALSE(t.components[0].orientable);
}

TEST(SurfaceTopology, MirroredQuadsAreReorientedConsistently) {
  auto box = test::box_surface(2, 2, 2);
  box.surface.quads[3] = reversed(box.surface.quads[3]);
  box.surface.quads[17] = reversed(box.surface.quads[17]);
  const SurfaceTopology t = surface_topology(box.surface);
  EXPECT_FALSE(t.is_consistently_oriented());
  EXPECT_EQ(t.inconsistent_edges.size(), 8u);
  EXPECT_TRUE(t.is_orientable());
  EXPECT_EQ(t.genus(), 0);  // genus is topological: it does not need the given orientation
  const QuadSurface fixed = consistently_oriented(box.surface, t);
  const SurfaceTopology u = surface_topology(fixed);
  EXPECT_TRUE(u.is_consistently_oriented());
  // Quad 0 keeps its orientation, so exactly the two mirrored quads are reversed.
  EXPECT_EQ(std::count(t.orientation_flips.begin(), t.orientation_flips.end(), true), 2);
  EXPECT_TRUE(t.orientation_flips[3]);
  EXPECT_TRUE(t.orientation_flips[17]);
}

TEST(SurfaceTopology, DegenerateQuadIsReportedAndItsCollapsedSideHasNoEdge) {
  QuadSurface s;
  s.num_nodes = 4;
  s.quads = {{NodeId(0), NodeId(1), NodeId(1), NodeId(2)},
             {NodeId(0), NodeId(1), NodeId(2), NodeId(3)}};
  const SurfaceTopology t = surface_topology(s);
  ASSERT_EQ(t.degenerate_quads.size(), 1u);
  EXPECT_EQ(t.degenerate_quads[0], QuadId(0));
  EXPECT_FALSE(t.edge_of(QuadSide{QuadId(0), 1}).is_valid());
  EXPECT_TRUE(t.edge_of(QuadSide{QuadId(0), 0}).is_valid());
}

TEST(SurfaceTopology, NodeOutOfRangeIsInvalidInput) {
  QuadSurface s;
  s.num_nodes = 3;
  s.quads = {{NodeId(0), NodeId(1), NodeId(2), NodeId(7)}};
  try {
    (void)surface_topology(s);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("q0"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("n7"));
  }
}

TEST(SurfaceTopology, EmptySurface) {
  const SurfaceTopology t = surface_topology(QuadSurface{});
  EXPECT_TRUE(t.edges.empty());
  EXPECT_TRUE(t.components.empty());
  EXPECT_EQ(t.euler_characteristic(), 0);
}

}  // namespace
}  // namespace stcweave::stc
