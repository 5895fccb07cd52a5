// The thresholded second convex filter (stcweave/weave/second_convex_threshold.hpp): the
// filter alone on hand-made candidates, and the structured boxes under both readings of the
// rule (the seed's, min weight 0, and the threshold).
#include "stcweave/weave/second_convex_threshold.hpp"

#include <gtest/gtest.h>

#include <tuple>

#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/validate.hpp"
#include "stcweave/weave/weave.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

TraceCandidate candidate(std::int32_t loop, std::size_t side_sharp, std::size_t length) {
  TraceCandidate c;
  c.loop = loop;
  c.side_sharp = side_sharp;
  c.length = length;
  return c;
}

Selection only(Filter filter) {
  Selection s = extended_selection(ExtendedParameters{});
  s.filters = {std::move(filter)};
  return s;
}

TEST(SecondConvexThreshold, AStrayRimEdgeWeighsNothing) {
  // The triangle-split cylinder: the far side of a loop around a vertex has 2 of its 8 side
  // edges on the rim. The seed's rule keeps that side; the threshold keeps both.
  const std::vector<TraceCandidate> all{candidate(0, 0, 8), candidate(1, 2, 8)};
  const Ranking seed = rank(only(second_convex_filter()), all);
  EXPECT_EQ(seed.filters.front(), "second_convex:2->1");
  EXPECT_EQ(seed.order.front().loop, 1);
  const Ranking ours = rank(only(second_convex_threshold_filter(0.75)), all);
  EXPECT_EQ(ours.filters.front(), "second_convex:2->2");
}

TEST(SecondConvexThreshold, ASideAlongARimStillWins) {
  // A box's layer loop: every side edge toward the face is sharp (weight 1).
  const std::vector<TraceCandidate> all{candidate(0, 0, 8), candidate(1, 8, 8), candidate(2, 7, 8)};
  const Ranking r = rank(only(second_convex_threshold_filter(0.75)), all);
  EXPECT_EQ(r.filters.front(), "second_convex:3->1");
  EXPECT_EQ(r.order.front().loop, 1);
  EXPECT_EQ(r.decided_by, "second_convex");
}

TEST(SecondConvexThreshold, TheDefaultDropsFewerThanOneSharpEdgeInTen) {
  // The kitty's cut ball: sides with 3 sharp edges along a loop of 40 (weight 0.075) won
  // the seed's rule over the cheaper sides with none. By default they weigh 0; 3 of 10 counts.
  const ExtendedParameters defaults;
  EXPECT_DOUBLE_EQ(defaults.second_convex_min_weight, 0.1);
  const Filter f =
      second_convex_filter(defaults.second_convex_min_weight, defaults.second_convex_smaller_side);
  const std::vector<TraceCandidate> stray{candidate(0, 0, 40), candidate(1, 3, 40)};
  EXPECT_EQ(rank(only(f), stray).filters.front(), "second_convex:2->2");
  EXPECT_EQ(rank(only(second_convex_filter()), stray).filters.front(), "second_convex:2->1");
  const std::vector<TraceCandidate> counts{candidate(0, 0, 10), candidate(1, 3, 10)};
  const Ranking r = rank(only(f), counts);
  EXPECT_EQ(r.filters.front(), "second_convex:2->1");
  EXPECT_EQ(r.order.front().loop, 1);
}

TEST(SecondConvexThreshold, OutOfRangeIsRefused) {
  const auto box = test::box_surface(1, 1, 1);
  WeaveOptions o;
  o.rules = RuleSet::Extended;
  o.extended.second_convex_min_weight = 1.5;
  EXPECT_THROW((void)weave(box.surface, o, primal::dihedral_angles(box)), InvalidInput);
  o.extended.second_convex_min_weight = -0.1;
  EXPECT_THROW((void)weave(box.surface, o, primal::dihedral_angles(box)), InvalidInput);
}

class SecondConvexBoxes
    : public ::testing::TestWithParam<std::tuple<double, std::tuple<int, int, int>>> {};

TEST_P(SecondConvexBoxes, GiveTheStructuredMesh) {
  const auto [w, dims] = GetParam();
  const auto [a, b, c] = dims;
  const auto box = test::box_surface(a, b, c);
  WeaveOptions o;
  o.rules = RuleSet::Extended;
  o.check = true;
  o.extended.second_convex_min_weight = w;
  const WeaveResult r = weave(box.surface, o, primal::dihedral_angles(box));
  EXPECT_EQ(r.complex.hexes.size(), static_cast<std::size_t>(a * b * c));
  EXPECT_EQ(r.complex.num_nodes, static_cast<std::size_t>((a + 1) * (b + 1) * (c + 1)));
  const auto report = stc::validate_hex_complex(r.complex, &box.surface);
  EXPECT_TRUE(report.valid) << report.summary();
}

INSTANTIATE_TEST_SUITE_P(
    SeedAndThreshold, SecondConvexBoxes,
    ::testing::Combine(::testing::Values(0.0, 0.1, 0.75),
                       ::testing::Values(std::make_tuple(1, 1, 1), std::make_tuple(2, 2, 2),
                                         std::make_tuple(3, 3, 3), std::make_tuple(2, 3, 4),
                                         std::make_tuple(4, 2, 1), std::make_tuple(5, 1, 1),
                                         std::make_tuple(4, 4, 4))));

}  // namespace
}  // namespace stcweave::weave
