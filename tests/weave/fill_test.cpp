// The last ways of `weave` (docs/weave-recovery.md "The fill", "Reliable from the start"): the
// fill of a small blocked front by front moves (weave/src/fill.cpp) on fronts built by hand,
// and on 20-quad sphere quadrangulations that no other way completes (taken from the closure
// of complete_test.cpp, whose 20-quad run is slow: these four are written out here).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "blocked_spheres.hpp"
#include "recovery.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/validate.hpp"
#include "stcweave/weave/kernel.hpp"
#include "stcweave/weave/weave.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

WeaveOptions options_for(RuleSet rules, bool last_ways) {
  WeaveOptions o;
  o.rules = rules;
  if (!last_ways) {
    o.fill_up_to = 0;
    o.reliable_from_start = false;
  }
  return o;
}

/// The weave completes only through the last ways, and its complex is certified.
WeaveResult woven_by_the_last_ways(const stc::QuadSurface& s, RuleSet rules) {
  EXPECT_THROW((void)weave(s, options_for(rules, false)), WeaveError)
      << "this shape no longer needs the last ways: pick another";
  const WeaveResult r = weave(s, options_for(rules, true));
  const stc::ValidationReport v = stc::validate_hex_complex(r.complex, &s);
  EXPECT_TRUE(v.valid) << v.summary();
  return r;
}

TEST(Fill, CompletesTheReliableWeaveOfAShapeTheRecoveryLeavesBlocked) {
  const WeaveResult r = woven_by_the_last_ways(test::blocked_sphere_12(), RuleSet::Reliable);
  EXPECT_EQ(r.stats.fill_hexes, 16U);
  EXPECT_EQ(r.complex.hexes.size(), 16U) << "the input's front filled before any rule";
  EXPECT_EQ(std::count(r.hex_rule.begin(), r.hex_rule.end(), "fill"), 16);
  EXPECT_EQ(r.stats.reliable_from_start, 0U);
  EXPECT_EQ(r.stats.recoveries, 0U) << "the kept weave is the fill, not a recovered one";
}

TEST(Fill, CompletesAnExtendedWeaveWithHexesThatJoinTheWovenComplex) {
  // The fill's 16 hexes join the one hex woven before the front blocked (the fill searches
  // with `strict_contacts`, and the weave checks each of its hexes as it puts it on).
  const WeaveResult r = woven_by_the_last_ways(test::blocked_sphere_16(), RuleSet::Extended);
  EXPECT_EQ(r.stats.fill_hexes, 16U);
  EXPECT_EQ(r.complex.hexes.size(), 17U);
  EXPECT_EQ(std::count(r.hex_rule.begin(), r.hex_rule.end(), "fill"), 16);
  EXPECT_EQ(r.stats.reliable_from_start, 0U);
  EXPECT_EQ(r.stats.recoveries, 0U) << "the kept weave is the fill, not a recovered one";
}

TEST(Fill, ExtendedWeavesWithTheReliableRulesFromTheStartWhenTheFillStalls) {
  const WeaveResult r = woven_by_the_last_ways(test::blocked_sphere_18(), RuleSet::Extended);
  EXPECT_EQ(r.stats.fill_hexes, 0U);
  EXPECT_EQ(r.stats.reliable_from_start, 1U);
  // The same complex as the reliable weave of the shape.
  const WeaveResult reliable =
      weave(test::blocked_sphere_18(), options_for(RuleSet::Reliable, false));
  EXPECT_EQ(r.complex.hexes, reliable.complex.hexes);
}

TEST(Fill, IsNotTriedUnderReliableFromStartOrWithTheRecoveryOff) {
  WeaveOptions o = options_for(RuleSet::Reliable, true);
  o.block_recovery = BlockRecovery::Off;
  EXPECT_THROW((void)weave(test::blocked_sphere_12(), o), WeaveError);
  WeaveOptions e = options_for(RuleSet::Extended, true);
  e.fill_up_to = 0;
  e.reliable_from_start = false;
  EXPECT_THROW((void)weave(test::blocked_sphere_18(), e), WeaveError);
}

TEST(Fill, ClosesACubeFrontWithOneHex) {
  const stc::QuadSurface cube = test::box_surface(1, 1, 1).surface;
  WeaveState state(cube);
  WeaveOptions options;
  WeaveContext ctx(options, nullptr, 1000);
  EXPECT_EQ(fill_blocked_front(state, ctx, 200), std::nullopt);
  EXPECT_EQ(state.front.num_faces(), 0U);
  ASSERT_EQ(state.woven.hexes.size(), 1U);
  EXPECT_EQ(state.woven.hex_rule.front(), "fill");
  EXPECT_EQ(state.stats.fill_hexes, 1U);
}

TEST(Fill, RefusesALargeFrontAndLeavesTheStateAsItWas) {
  const stc::QuadSurface box = test::box_surface(2, 2, 2).surface;  // 24 quads
  WeaveState state(box);
  WeaveOptions options;
  WeaveContext ctx(options, nullptr, 1000);
  const auto why = fill_blocked_front(state, ctx, 20);
  ASSERT_TRUE(why.has_value());
  EXPECT_NE(why->find("24 faces, more than the 20"), std::string::npos) << *why;
  EXPECT_EQ(state.front.num_faces(), 24U);
  EXPECT_TRUE(state.woven.hexes.empty());
  EXPECT_EQ(state.stats.fill_hexes, 0U);
}

TEST(Fill, RefusesAnOddFrontAndLeavesTheStateAsItWas) {
  // Three lunes (N, x_i, S, x_i+1) around two poles: a closed oriented front of 3 faces, which
  // no set of hexes fills (every hex glues faces in pairs).
  stc::QuadSurface lunes;
  lunes.num_nodes = 5;
  const NodeId north(3), south(4);
  for (int i = 0; i < 3; ++i) lunes.quads.push_back({north, NodeId(i), south, NodeId((i + 1) % 3)});
  WeaveState state(lunes);
  ASSERT_EQ(state.front.check_invariants(), std::nullopt);
  WeaveOptions options;
  WeaveContext ctx(options, nullptr, 1000);
  const auto why = fill_blocked_front(state, ctx, 200);
  ASSERT_TRUE(why.has_value());
  EXPECT_NE(why->find("odd number of faces"), std::string::npos) << *why;
  EXPECT_EQ(state.front.num_faces(), 3U);
  EXPECT_TRUE(state.woven.hexes.empty());
  EXPECT_EQ(state.stats.fill_hexes, 0U);
}

}  // namespace
}  // namespace stcweave::weave
