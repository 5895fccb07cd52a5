/// Tests of stc/loops.hpp: strips, crossings, self-intersections, sides, crossing graph.

#include "stcweave/stc/loops.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <tuple>

#include "support/shapes.hpp"

namespace stcweave::stc {
namespace {

/// k lunes (N, x_i, S, x_{i+1}) around two poles: a closed sphere of k quads. For odd k
/// its single loop crosses every quad twice.
QuadSurface pillow(int k) {
  QuadSurface s;
  s.num_nodes = static_cast<std::size_t>(k + 2);
  const NodeId north(k), south(k + 1);
  for (int i = 0; i < k; ++i) s.quads.push_back({north, NodeId(i), south, NodeId((i + 1) % k)});
  return s;
}

/// Every quad split into 2 x 2 (one node per edge, one per quad), orientation kept.
QuadSurface refined(const QuadSurface& s) {
  QuadSurface out;
  std::map<std::pair<NodeId, NodeId>, NodeId> mid;
  std::size_t next = s.num_nodes;
  const auto midpoint = [&](NodeId a, NodeId b) {
    auto key = a < b ? std::make_pair(a, b) : std::make_pair(b, a);
    auto [it, inserted] = mid.emplace(key, NodeId(next));
    if (inserted) ++next;
    return it->second;
  };
  for (const Quad& q : s.quads) {
    const NodeId m01 = midpoint(q[0], q[1]), m12 = midpoint(q[1], q[2]), m23 = midpoint(q[2], q[3]),
                 m30 = midpoint(q[3], q[0]);
    const NodeId c(next++);
    out.quads.push_back({q[0], m01, c, m30});
    out.quads.push_back({m01, q[1], m12, c});
    out.quads.push_back({c, m12, q[2], m23});
    out.quads.push_back({m30, c, m23, q[3]});
  }
  out.num_nodes = next;
  return out;
}

/// Checks that every loop's strip is a walk: leave by the opposite side into the neighbour.
void expect_strips_are_walks(const QuadSurface& s, const SurfaceTopology& t, const LoopSet& set) {
  std::size_t passages = 0;
  for (const Loop& l : set.loops) {
    passages += l.length();
    for (std::size_t k = 0; k < l.length(); ++k) {
      const StripStep& step = l.strip[k];
      EXPECT_EQ(set.quad_loops[step.quad.index()][static_cast<std::size_t>(step.direction())],
                l.id);
      if (k + 1 == l.length() && !l.closed) break;
      const StripStep& next = l.strip[(k + 1) % l.length()];
      EXPECT_EQ(t.neighbour(QuadSide{step.quad, step.exit()}), (QuadSide{next.quad, next.entry}))
          << l.id << " step " << k;
    }
  }
  EXPECT_EQ(passages, 2 * s.num_quads());
}

TEST(Loops, BoxHasOneLoopPerLayer) {
  const int a = 2, b = 3, c = 4;
  const auto box = test::box_surface(a, b, c);
  const SurfaceTopology t = surface_topology(box.surface);
  const LoopSet set = find_loops(box.surface, t);
  EXPECT_EQ(set.size(), static_cast<std::size_t>(a + b + c));
  EXPECT_EQ(set.longest_length(), static_cast<std::size_t>(2 * (b + c)));
  EXPECT_EQ(set.num_self_intersecting(), 0u);
  EXPECT_EQ(set.num_self_crossing_quads(), 0u);
  EXPECT_EQ(set.num_open(), 0u);
  std::multiset<std::size_t> lengths;
  for (const Loop& l : set.loops) {
    lengths.insert(l.length());
    EXPECT_TRUE(l.closed);
    EXPECT_EQ(l.crossings.size(), l.length());
  }
  EXPECT_EQ(lengths.count(2 * (b + c)), static_cast<std::size_t>(a));
  EXPECT_EQ(lengths.count(2 * (a + c)), static_cast<std::size_t>(b));
  EXPECT_EQ(lengths.count(2 * (a + b)), static_cast<std::size_t>(c));
  expect_strips_are_walks(box.surface, t, set);
  for (std::size_t l = 0; l < set.size(); ++l) EXPECT_EQ(set.loops[l].id, LoopId(l));
}

TEST(Loops, CrossingGraphOfABox) {
  const auto box = test::box_surface(2, 1, 3);
  const LoopSet set = find_loops(box.surface);
  const LoopCrossingGraph& g = set.crossing_graph;
  EXPECT_EQ(boost::num_vertices(g), set.size());
  EXPECT_EQ(boost::num_edges(g), box.surface.num_quads());
  // Two loops around perpendicular axes cross twice; parallel loops never.
  std::map<std::pair<std::size_t, std::size_t>, int> multiplicity;
  for (auto [e, end] = boost::edges(g); e != end; ++e) {
    const auto u = boost::source(*e, g), v = boost::target(*e, g);
    EXPECT_NE(u, v);
    const QuadId q = g[*e].quad;
    const auto& pair = set.quad_loops[q.index()];
    EXPECT_TRUE((pair[0] == g[u].loop && pair[1] == g[v].loop) ||
                (pair[1] == g[u].loop && pair[0] == g[v].loop));
    ++multiplicity[{std::min(u, v), std::max(u, v)}];
  }
  for (const auto& [uv, n] : multiplicity) EXPECT_EQ(n, 2);
  for (std::size_t l = 0; l < set.size(); ++l) EXPECT_EQ(g[l].loop, LoopId(l));
}

TEST(Loops, OddPillowHasOneLoopCrossingEveryQuadTwice) {
  const QuadSurface s = pillow(3);
  const SurfaceTopology t = surface_topology(s);
  ASSERT_TRUE(t.is_closed());
  ASSERT_TRUE(t.is_manifold());
  ASSERT_EQ(t.genus(), 0);
  const LoopSet set = find_loops(s, t);
  ASSERT_EQ(set.size(), 1u);
  const Loop& l = set.loops[0];
  EXPECT_EQ(l.length(), 6u);
  EXPECT_TRUE(l.is_self_intersecting());
  EXPECT_THAT(l.self_crossing_quads, ::testing::ElementsAre(QuadId(0), QuadId(1), QuadId(2)));
  EXPECT_TRUE(l.crossings.empty());
  EXPECT_FALSE(l.sides.has_value());
  // A self-intersection is a self-loop of the crossing graph.
  EXPECT_EQ(boost::num_edges(set.crossing_graph), 3u);
  for (auto [e, end] = boost::edges(set.crossing_graph); e != end; ++e)
    EXPECT_EQ(boost::source(*e, set.crossing_graph), boost::target(*e, set.crossing_graph));
  expect_strips_are_walks(s, t, set);
}

TEST(Loops, EvenPillowHasTwoLoopsCrossingInEveryQuad) {
  const QuadSurface s = pillow(4);
  const LoopSet set = find_loops(s);
  ASSERT_EQ(set.size(), 2u);
  EXPECT_EQ(set.num_self_intersecting(), 0u);
  EXPECT_EQ(set.loops[0].crossings.size(), 4u);
  EXPECT_EQ(boost::num_edges(set.crossing_graph), 4u);  // four parallel edges l0-l1
}

TEST(Loops, RefinedOddPillowHasTwoSelfIntersectingLoops) {
  const QuadSurface s = refined(pillow(3));
  const SurfaceTopology t = surface_topology(s);
  ASSERT_EQ(t.num_quads(), 12u);
  ASSERT_TRUE(t.is_closed());
  ASSERT_TRUE(t.is_consistently_oriented());
  const LoopSet set = find_loops(s, t);
  EXPECT_EQ(set.size(), 2u);
  EXPECT_EQ(set.num_self_intersecting(), 2u);
  EXPECT_EQ(set.num_self_crossing_quads(), 6u);
  for (const Loop& l : set.loops) {
    EXPECT_EQ(l.length(), 12u);
    EXPECT_EQ(l.self_crossing_quads.size(), 3u);
    EXPECT_EQ(l.crossings.size(), 6u);  // the two loops cross in the other six quads
  }
  expect_strips_are_walks(s, t, set);
}

TEST(Loops, OpenSurfaceGivesOpenLoops) {
  auto box = test::box_surface(2, 2, 2);
  box.surface.quads.pop_back();
  const SurfaceTopology t = surface_topology(box.surface);
  const LoopSet set = find_loops(box.surface, t);
  EXPECT_EQ(set.num_open(), 2u);  // the two loops through the removed quad
  EXPECT_EQ(set.size(), 6u);
  for (const Loop& l : set.loops) {
    EXPECT_EQ(l.length(), l.closed ? 8u : 7u);
    EXPECT_FALSE(!l.closed && l.sides.has_value());
    if (!l.closed) {
      // Both ends are open sides.
      EXPECT_FALSE(t.neighbour(QuadSide{l.strip.front().quad, l.strip.front().entry}).is_valid());
      EXPECT_FALSE(t.neighbour(QuadSide{l.strip.back().quad, l.strip.back().exit()}).is_valid());
    }
  }
  expect_strips_are_walks(box.surface, t, set);
}

TEST(Loops, SidesOfABoxLoopPartitionTheSurface) {
  const auto box = test::box_surface(2, 2, 2);
  const SurfaceTopology t = surface_topology(box.surface);
  const LoopSet set = find_loops(box.surface, t);
  for (const Loop& l : set.loops) {
    ASSERT_TRUE(l.sides.has_value()) << l.id;
    const LoopSides& sides = *l.sides;
    // Quads: strip + both sides = all, disjoint.
    std::set<QuadId> quads;
    for (const StripStep& s : l.strip) quads.insert(s.quad);
    for (int d = 0; d < 2; ++d)
      for (QuadId q : sides.quads[d]) EXPECT_TRUE(quads.insert(q).second) << q;
    EXPECT_EQ(quads.size(), box.surface.num_quads());
    // Nodes: strip nodes of both sides + strictly-side nodes = all, disjoint.
    std::set<NodeId> nodes;
    for (int d = 0; d < 2; ++d) {
      for (NodeId v : sides.strip_nodes[d]) EXPECT_TRUE(nodes.insert(v).second) << v;
      for (NodeId v : sides.nodes[d]) EXPECT_TRUE(nodes.insert(v).second) << v;
    }
    EXPECT_EQ(nodes.size(), box.surface.num_nodes);
    EXPECT_EQ(sides.strip_nodes[0].size(), 8u);
    EXPECT_EQ(sides.strip_nodes[1].size(), 8u);
    // On a 2x2x2 box each loop has a 4-quad cap (1 inner node) on one side and 12 quads
    // (9 nodes) on the other.
    std::multiset<std::size_t> side_quads{sides.quads[0].size(), sides.quads[1].size()};
    EXPECT_EQ(side_quads, (std::multiset<std::size_t>{4, 12}));
    std::multiset<std::size_t> side_nodes{sides.nodes[0].size(), sides.nodes[1].size()};
    EXPECT_EQ(side_nodes, (std::multiset<std::size_t>{1, 9}));
    EXPECT_EQ(sides.weight(LoopSide::Left), sides.nodes[0].size() + 8);
  }
}

TEST(Loops, LeftIsLeftOfTheTravelSeenFromOutside) {
  const auto box = test::box_surface(3, 2, 2);
  const LoopSet set = find_loops(box.surface);
  const auto p = [&](NodeId v) -> Eigen::Vector3d { return box.points.row(v.value()).transpose(); };
  for (const Loop& l : set.loops) {
    ASSERT_TRUE(l.sides.has_value());
    const auto edges = loop_transversal_edges(box.surface, l);
    ASSERT_EQ(edges.size(), l.length());
    for (std::size_t k = 0; k < l.length(); ++k) {
      const Quad& f = box.surface.quad(l.strip[k].quad);
      const auto at = [&](int i) {
        return p(f[static_cast<std::size_t>((l.strip[k].entry + i) % 4)]);
      };
      const Eigen::Vector3d travel = (at(2) + at(3) - at(0) - at(1)) / 2;
      const Eigen::Vector3d normal = (at(1) - at(0)).cross(at(3) - at(0));  // outward
      const Eigen::Vector3d left = normal.cross(travel);
      const Eigen::Vector3d centre = (at(0) + at(1) + at(2) + at(3)) / 4;
      EXPECT_GT((p(edges[k][0]) - centre).dot(left), 0.0);
      EXPECT_LT((p(edges[k][1]) - centre).dot(left), 0.0);
      EXPECT_TRUE(std::binary_search(l.sides->strip_nodes[0].begin(), l.sides->strip_nodes[0].end(),
                                     edges[k][0]));
      EXPECT_TRUE(std::binary_search(l.sides->strip_nodes[1].begin(), l.sides->strip_nodes[1].end(),
                                     edges[k][1]));
    }
  }
}

TEST(Loops, NoSidesOnATorusOrWhenNotAsked) {
  QuadSurface torus;
  const int n = 4, m = 3;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i)
      torus.quads.push_back({NodeId(i + n * j), NodeId((i + 1) % n + n * j),
                             NodeId((i + 1) % n + n * ((j + 1) % m)),
                             NodeId(i + n * ((j + 1) % m))});
  torus.num_nodes = static_cast<std::size_t>(n * m);
  const LoopSet set = find_loops(torus);
  EXPECT_EQ(set.size(), static_cast<std::size_t>(n + m));
  for (const Loop& l : set.loops) EXPECT_FALSE(l.sides.has_value());

  const auto box = test::box_surface(1, 1, 1);
  const LoopSet plain = find_loops(box.surface, FindLoopsOptions{false});
  for (const Loop& l : plain.loops) EXPECT_FALSE(l.sides.has_value());
  const SurfaceTopology t = surface_topology(box.surface);
  const auto sides = loop_sides(box.surface, t, plain.loops[0]);
  ASSERT_TRUE(sides.has_value());
  EXPECT_EQ(sides->quads[0].size() + sides->quads[1].size(), 2u);
}

}  // namespace
}  // namespace stcweave::stc
