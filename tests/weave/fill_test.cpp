// The last ways of `weave` (docs/weave-recovery.md "The fill", "Reliable from the start"): the
// fill of a small blocked front by front moves (weave/src/fill.cpp) on fronts built by hand,
// and on 20-quad sphere quadrangulations that no other way completes (taken from the closure
// of complete_test.cpp, whose 20-quad run is slow: these four are written out here).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "recovery.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/validate.hpp"
#include "stcweave/weave/kernel.hpp"
#include "stcweave/weave/weave.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

stc::QuadSurface surface_of(std::size_t nodes, const std::vector<std::array<int, 4>>& quads) {
  stc::QuadSurface s;
  s.num_nodes = nodes;
  for (const auto& q : quads)
    s.quads.push_back({NodeId(q[0]), NodeId(q[1]), NodeId(q[2]), NodeId(q[3])});
  return s;
}

// Loop-clean 20-quad spheres (22 nodes) of the closure whose weave blocks under one rule set
// with the block recovery and the retry; the shape numbers are the loop-clean order of
// SphereClosureSlow.TwentyQuads.
stc::QuadSurface shape170() {  // blocks under reliable
  return surface_of(
      22, {{8, 0, 1, 2},    {12, 13, 14, 15}, {8, 2, 3, 4},     {9, 3, 2, 1},     {10, 4, 5, 6},
           {9, 5, 4, 3},    {10, 6, 7, 11},   {9, 7, 6, 5},     {17, 18, 19, 20}, {11, 1, 0, 10},
           {9, 1, 13, 12},  {1, 11, 14, 13},  {11, 16, 15, 14}, {16, 9, 12, 15},  {16, 11, 7, 9},
           {10, 0, 18, 17}, {0, 21, 19, 18},  {21, 4, 20, 19},  {4, 10, 17, 20},  {21, 0, 8, 4}});
}
stc::QuadSurface shape377() {  // blocks under extended
  return surface_of(
      22, {{10, 0, 1, 2},   {11, 1, 0, 9},   {14, 2, 3, 4},    {11, 3, 2, 1},    {14, 4, 5, 6},
           {11, 5, 4, 3},   {12, 6, 7, 8},   {11, 7, 6, 5},    {12, 8, 9, 13},   {11, 9, 8, 7},
           {12, 20, 14, 6}, {13, 9, 0, 19},  {15, 16, 17, 18}, {14, 20, 16, 15}, {13, 19, 21, 16},
           {10, 2, 18, 17}, {2, 14, 15, 18}, {19, 0, 10, 21},  {20, 12, 13, 16}, {21, 10, 17, 16}});
}
stc::QuadSurface shape158() {  // extended runs away (the rule budget), the fill stalls
  return surface_of(
      22, {{12, 13, 14, 15}, {11, 1, 0, 9},   {10, 2, 3, 4},    {11, 3, 2, 1},    {10, 4, 5, 6},
           {11, 5, 4, 3},    {10, 6, 7, 8},   {17, 18, 19, 20}, {10, 8, 9, 0},    {11, 9, 8, 7},
           {10, 16, 13, 12}, {16, 1, 14, 13}, {1, 2, 15, 14},   {2, 10, 12, 15},  {16, 10, 0, 1},
           {11, 7, 18, 17},  {7, 6, 19, 18},  {6, 21, 20, 19},  {21, 11, 17, 20}, {21, 6, 5, 11}});
}

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
  const WeaveResult r = woven_by_the_last_ways(shape170(), RuleSet::Reliable);
  EXPECT_EQ(r.stats.fill_hexes, 21U);
  EXPECT_EQ(r.complex.hexes.size(), 21U) << "the input's front filled before any rule";
  EXPECT_EQ(std::count(r.hex_rule.begin(), r.hex_rule.end(), "fill"), 21);
  EXPECT_EQ(r.stats.reliable_from_start, 0U);
  EXPECT_EQ(r.stats.recoveries, 0U) << "the kept weave is the fill, not a recovered one";
}

TEST(Fill, CompletesAnExtendedWeaveWithHexesThatJoinTheWovenComplex) {
  // Without `strict_contacts` the fill's fourth hex would share five nodes with its first one
  // (the weave's check refuses it), and the reliable weave from the start makes 63 hexes.
  const WeaveResult r = woven_by_the_last_ways(shape377(), RuleSet::Extended);
  EXPECT_EQ(r.stats.fill_hexes, 13U);
  EXPECT_EQ(r.complex.hexes.size(), 13U);
  EXPECT_EQ(r.stats.reliable_from_start, 0U);
  EXPECT_EQ(r.stats.recoveries, 0U) << "the kept weave is the fill, not a recovered one";
}

TEST(Fill, ExtendedWeavesWithTheReliableRulesFromTheStartWhenTheFillStalls) {
  const WeaveResult r = woven_by_the_last_ways(shape158(), RuleSet::Extended);
  EXPECT_EQ(r.stats.fill_hexes, 0U);
  EXPECT_EQ(r.stats.reliable_from_start, 1U);
  // The same complex as the reliable weave of the shape.
  const WeaveResult reliable = weave(shape158(), options_for(RuleSet::Reliable, false));
  EXPECT_EQ(r.complex.hexes, reliable.complex.hexes);
}

TEST(Fill, IsNotTriedUnderReliableFromStartOrWithTheRecoveryOff) {
  WeaveOptions o = options_for(RuleSet::Reliable, true);
  o.block_recovery = BlockRecovery::Off;
  EXPECT_THROW((void)weave(shape170(), o), WeaveError);
  WeaveOptions e = options_for(RuleSet::Extended, true);
  e.fill_up_to = 0;
  e.reliable_from_start = false;
  EXPECT_THROW((void)weave(shape158(), e), WeaveError);
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

}  // namespace
}  // namespace stcweave::weave
