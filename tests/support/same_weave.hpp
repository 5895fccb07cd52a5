#pragma once
/// Two weaves that must have made the same decisions: the same complex, the same rule and
/// shrink behind each hex, the same counts of selections, shrinks and rules. Used where a
/// faster path (branch and bound, candidates computed in part) is compared with the full one.

#include <gtest/gtest.h>

#include <string>

#include "stcweave/weave/weave.hpp"

namespace stcweave::test {

inline void expect_same_weave(const weave::WeaveResult& a, const weave::WeaveResult& b,
                              const std::string& where) {
  EXPECT_EQ(a.complex.num_nodes, b.complex.num_nodes) << where;
  EXPECT_EQ(a.complex.hexes, b.complex.hexes) << where;
  EXPECT_EQ(a.hex_rule, b.hex_rule) << where;
  EXPECT_EQ(a.hex_shrink, b.hex_shrink) << where;
  EXPECT_EQ(a.stats.selections, b.stats.selections) << where;
  EXPECT_EQ(a.stats.shrinks, b.stats.shrinks) << where;
  EXPECT_EQ(a.stats.failed_shrinks, b.stats.failed_shrinks) << where;
  EXPECT_EQ(a.stats.rolled_back_shrinks, b.stats.rolled_back_shrinks) << where;
  EXPECT_EQ(a.stats.crosses, b.stats.crosses) << where;
  EXPECT_EQ(a.stats.seams, b.stats.seams) << where;
  EXPECT_EQ(a.stats.blind_chords, b.stats.blind_chords) << where;
  EXPECT_EQ(a.stats.parallel_merges, b.stats.parallel_merges) << where;
}

}  // namespace stcweave::test
