// Accumulation measures (stcweave/primal/valence_stats.hpp) on hand-built complexes whose
// counts are known: structured boxes, a fan of hexes around one edge (a 17-hex edge) and a
// two-layer fan whose middle node is a star.
#include "stcweave/primal/valence_stats.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

using Histogram = std::vector<std::size_t>;

/// k hexes in `layers` layers around the vertical axis: the 2k-gon split into k quads (centre,
/// rim 2i, rim 2i+1, rim 2i+2), extruded. Node (layer l, centre) = l (2k + 1), rim node j of
/// layer l = l (2k + 1) + 1 + j.
stc::HexComplex fan(int k, int layers) {
  stc::HexComplex c;
  const int per_layer = 2 * k + 1;
  c.num_nodes = static_cast<std::size_t>(per_layer) * static_cast<std::size_t>(layers + 1);
  const auto rim = [&](int l, int j) { return NodeId(l * per_layer + 1 + (j % (2 * k))); };
  for (int l = 0; l < layers; ++l) {
    for (int i = 0; i < k; ++i) {
      c.hexes.push_back({NodeId(l * per_layer), rim(l, 2 * i), rim(l, 2 * i + 1), rim(l, 2 * i + 2),
                         NodeId((l + 1) * per_layer), rim(l + 1, 2 * i), rim(l + 1, 2 * i + 1),
                         rim(l + 1, 2 * i + 2)});
    }
  }
  return c;
}

TEST(ValenceStats, AStructuredBoxHasFourHexesPerEdgeAndEightPerNode) {
  const ValenceStats s = valence_stats(test::box_hexes(3, 3, 3).complex);
  EXPECT_EQ(s.interior_nodes, 8u);
  // interior edges of a 3x3x3 box: 3 directions x 3 edges along x 2 x 2 interior lines
  EXPECT_EQ(s.interior_edges, 36u);
  EXPECT_EQ(s.max_hexes_at_interior_edge, 4u);
  EXPECT_EQ(s.max_hexes_at_interior_node, 8u);
  EXPECT_EQ(s.edge_histogram, (Histogram{0, 0, 0, 0, 36}));
  EXPECT_EQ(s.node_histogram, (Histogram{0, 0, 0, 0, 0, 0, 0, 0, 8}));
  EXPECT_EQ(s.interior_edges_over_4, 0u);
  EXPECT_EQ(s.interior_edges_under_3, 0u);
  EXPECT_EQ(s.interior_nodes_over_8, 0u);
}

TEST(ValenceStats, ASingleHexHasNothingInside) {
  const ValenceStats s = valence_stats(test::box_hexes(1, 1, 1).complex);
  EXPECT_EQ(s.interior_edges, 0u);
  EXPECT_EQ(s.interior_nodes, 0u);
  EXPECT_EQ(s.max_hexes_at_interior_edge, 0u);
  EXPECT_EQ(s.max_hexes_at_interior_node, 0u);
  EXPECT_TRUE(s.edge_histogram.empty());
}

TEST(ValenceStats, SeventeenHexesAroundOneEdgeShow) {
  const ValenceStats s = valence_stats(fan(17, 1));
  EXPECT_EQ(s.interior_edges, 1u) << "only the axis: every other edge is on the boundary";
  EXPECT_EQ(s.interior_nodes, 0u);
  EXPECT_EQ(s.max_hexes_at_interior_edge, 17u);
  EXPECT_EQ(s.interior_edges_over_4, 1u);
  ASSERT_EQ(s.edge_histogram.size(), 18u);
  EXPECT_EQ(s.edge_histogram[17], 1u);
}

TEST(ValenceStats, AStarNodeShows) {
  // two layers of 6: the middle centre node is in all 12 hexes; the two halves of the axis
  // have 6 hexes each, the 6 spokes from the middle centre to even rim nodes 4 each.
  const ValenceStats s = valence_stats(fan(6, 2));
  EXPECT_EQ(s.interior_nodes, 1u);
  EXPECT_EQ(s.max_hexes_at_interior_node, 12u);
  EXPECT_EQ(s.interior_nodes_over_8, 1u);
  EXPECT_EQ(s.interior_edges, 8u);
  EXPECT_EQ(s.edge_histogram, (Histogram{0, 0, 0, 0, 6, 0, 2}));
  EXPECT_EQ(s.max_hexes_at_interior_edge, 6u);
  EXPECT_EQ(s.interior_edges_over_4, 2u);
  const nlohmann::json j = valence_json(s);
  EXPECT_EQ(j["max_hexes_at_interior_node"], 12);
  EXPECT_EQ(j["edge_histogram"], nlohmann::json::parse("[[4, 6], [6, 2]]"));
  EXPECT_EQ(j["node_histogram"], nlohmann::json::parse("[[12, 1]]"));
}

TEST(ValenceStats, ANodeOutOfRangeIsRefused) {
  stc::HexComplex c = test::box_hexes(1, 1, 1).complex;
  c.num_nodes = 7;
  EXPECT_THROW((void)valence_stats(c), InvalidInput);
}

}  // namespace
}  // namespace stcweave::primal
