#include "stcweave/stc/shared_nodes.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "stcweave/stc/errors.hpp"

namespace stcweave::stc {
namespace {

Quad quad(int a, int b, int c, int d) {
  return {NodeId(a), NodeId(b), NodeId(c), NodeId(d)};
}

Hex hex(int first) {
  Hex h{};
  for (int i = 0; i < 8; ++i) h[static_cast<std::size_t>(i)] = NodeId(first + i);
  return h;
}

void expect_pair(const SharedNodesPair& p, std::size_t first, std::size_t second,
                 std::size_t shared) {
  EXPECT_EQ(p.first, first);
  EXPECT_EQ(p.second, second);
  EXPECT_EQ(p.shared, shared);
}

// A 2 x 1 strip of quads (0-1-4-3, 1-2-5-4), a quad on two opposite corners of the first
// (0 and 4), one far away: the pairs, their counts, in (first, second) order.
TEST(SharedNodes, PairsAreCountedAndListedInOrder) {
  const std::vector<Quad> quads = {quad(0, 1, 4, 3), quad(1, 2, 5, 4), quad(0, 6, 4, 7),
                                   quad(10, 11, 12, 13)};
  const std::vector<SharedNodesPair> two = pairs_sharing_nodes(quads, 2);
  ASSERT_EQ(two.size(), 2U);
  expect_pair(two[0], 0, 1, 2);
  expect_pair(two[1], 0, 2, 2);
  // At least one node: the second and third quads share node 4 too.
  const std::vector<SharedNodesPair> one = pairs_sharing_nodes(quads, 1);
  ASSERT_EQ(one.size(), 3U);
  expect_pair(one[2], 1, 2, 1);
  EXPECT_TRUE(pairs_sharing_nodes(quads, 3).empty());
  EXPECT_THROW((void)pairs_sharing_nodes(quads, 0), InvalidInput);
}

// The side test tells an edge from two opposite corners.
TEST(SharedNodes, SharesASideTellsAnEdgeFromOppositeCorners) {
  EXPECT_TRUE(shares_a_side(quad(0, 1, 4, 3), quad(1, 2, 5, 4)));
  EXPECT_TRUE(shares_a_side(quad(1, 2, 5, 4), quad(0, 1, 4, 3)));
  EXPECT_FALSE(shares_a_side(quad(0, 1, 4, 3), quad(0, 6, 4, 7)));
  EXPECT_FALSE(shares_a_side(quad(0, 1, 4, 3), quad(10, 11, 12, 13)));
  // The side from the last corner back to the first counts too.
  EXPECT_TRUE(shares_a_side(quad(0, 1, 4, 3), quad(3, 8, 9, 0)));
}

// Hexes: two stacked on a face (4 nodes), one sharing six nodes with the first, one apart.
TEST(SharedNodes, HexPairsCountEveryNodeTheyShare) {
  Hex six = hex(100);
  for (std::size_t i = 0; i < 6; ++i) six[i] = NodeId(static_cast<int>(i));
  const std::vector<Hex> hexes = {hex(0), hex(4), six, hex(50)};
  const std::vector<SharedNodesPair> four = pairs_sharing_nodes(hexes, 4);
  ASSERT_EQ(four.size(), 2U);
  expect_pair(four[0], 0, 1, 4);
  expect_pair(four[1], 0, 2, 6);
  const std::vector<SharedNodesPair> any = pairs_sharing_nodes(hexes, 1);
  ASSERT_EQ(any.size(), 3U);
  expect_pair(any[2], 1, 2, 2);  // nodes 4 and 5
}

}  // namespace
}  // namespace stcweave::stc
