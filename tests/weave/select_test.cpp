// Loop selection as data (weave/include/stcweave/weave/select.hpp): each filter of Fig. 15
// alone on hand-made candidates, the two rule sets' lists, a user's own list, the candidate
// properties on a hand-built front, and the edge classes.
#include "stcweave/weave/select.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

TraceCandidate candidate(std::int32_t loop, int side) {
  TraceCandidate c;
  c.loop = loop;
  c.side = side;
  c.length = 4;
  return c;
}

/// A selection of `filter` alone, the extended order and trace.
Selection only(Filter filter) {
  Selection s = extended_selection(ExtendedParameters{});
  s.filters = {std::move(filter)};
  return s;
}

std::vector<std::int32_t> chosen_loops(const Ranking& r, std::size_t kept) {
  std::vector<std::int32_t> out;
  for (std::size_t i = 0; i < kept && i < r.order.size(); ++i) out.push_back(r.order[i].loop);
  return out;
}

TEST(Filters, NonConvexKeepsSidesWithoutNonConvexEdges) {
  std::vector<TraceCandidate> all{candidate(0, 0), candidate(1, 0), candidate(2, 0)};
  all[0].nonconvex_on_side = 2;
  all[2].nonconvex_on_side = 1;
  const Ranking r = rank(only(nonconvex_filter()), all);
  EXPECT_EQ(r.filters.front(), "nonconvex:3->1");
  EXPECT_EQ(r.decided_by, "nonconvex");
  EXPECT_EQ(r.order.front().loop, 1);
  EXPECT_EQ(r.order.size(), 3u) << "the others follow, to fall back on";
}

TEST(Filters, NonConvexIsRelaxedWhenNoneWouldBeLeft) {
  std::vector<TraceCandidate> all{candidate(0, 0), candidate(1, 1)};
  all[0].nonconvex_on_side = 1;
  all[1].nonconvex_on_side = 1;
  EXPECT_TRUE(nonconvex_filter().may_relax);
  const Ranking r = rank(only(nonconvex_filter()), all);
  EXPECT_EQ(r.filters.front(), "nonconvex:2->relaxed");
  EXPECT_EQ(r.decided_by, "topological");
}

TEST(Filters, NonConvexKeepsTheFewestWhenEverySideHasOneWithOurRelaxation) {
  std::vector<TraceCandidate> all{candidate(0, 0), candidate(1, 0), candidate(2, 0),
                                  candidate(3, 0)};
  all[0].nonconvex_on_side = 3;
  all[1].nonconvex_on_side = 1;
  all[2].nonconvex_on_side = 2;
  all[3].nonconvex_on_side = 1;
  Ranking r = rank(only(nonconvex_filter(true)), all);
  EXPECT_EQ(r.filters.front(), "nonconvex:4->least:2");
  EXPECT_EQ(chosen_loops(r, 2), (std::vector<std::int32_t>{1, 3}));
  r = rank(only(nonconvex_filter(false)), all);
  EXPECT_EQ(r.filters.front(), "nonconvex:4->relaxed") << "the relaxation of before";
  all[2].nonconvex_on_side = 0;
  r = rank(only(nonconvex_filter(true)), all);
  EXPECT_EQ(r.filters.front(), "nonconvex:4->1") << "a side without any: the seed's rule";
  EXPECT_EQ(r.order.front().loop, 2);
  EXPECT_EQ(r.decided_by, "nonconvex");
  all[2].nonconvex_on_side = 2;
  all[3].nonconvex_on_side = 4;
  r = rank(only(nonconvex_filter(true)), all);
  EXPECT_EQ(r.filters.front(), "nonconvex:4->least:1");
  EXPECT_EQ(r.order.front().loop, 1);
  EXPECT_EQ(r.decided_by, "nonconvex") << "one left by the relaxation: it decided";
  // The default list has the relaxation; `nonconvex_least = false` removes it.
  const auto nonconvex_of = [](const ExtendedParameters& p) {
    for (const Filter& f : extended_selection(p).filters)
      if (f.name == "nonconvex") return f;
    return Filter{};
  };
  EXPECT_TRUE(static_cast<bool>(nonconvex_of(ExtendedParameters{}).relax_cost));
  ExtendedParameters p;
  p.nonconvex_least = false;
  EXPECT_FALSE(static_cast<bool>(nonconvex_of(p).relax_cost));
}

TEST(Filters, DepthKeepsTheLeastDepth) {
  std::vector<TraceCandidate> all{candidate(0, 0), candidate(1, 0), candidate(2, 0)};
  all[0].depth = 3;
  all[1].depth = 2;
  all[2].depth = 2;
  EXPECT_FALSE(depth_filter().may_relax);
  const Ranking r = rank(only(depth_filter()), all);
  EXPECT_EQ(r.filters.front(), "depth:3->2");
  EXPECT_EQ(chosen_loops(r, 2), (std::vector<std::int32_t>{1, 2}));
  EXPECT_EQ(r.decided_by, "topological") << "two left: the topological rule decides";
}

TEST(Filters, FirstConvexKeepsLoopsCrossingASharpEdgeAndMayRelax) {
  std::vector<TraceCandidate> all{candidate(0, 0), candidate(1, 0)};
  all[1].crossed_sharp = 2;
  Ranking r = rank(only(first_convex_filter()), all);
  EXPECT_EQ(r.filters.front(), "first_convex:2->1");
  EXPECT_EQ(r.order.front().loop, 1);
  all[1].crossed_sharp = 0;
  r = rank(only(first_convex_filter()), all);
  EXPECT_EQ(r.filters.front(), "first_convex:2->relaxed");
}

TEST(Filters, FirstConvexKeepsASideAlongASharpRimOnlyWithOurCondition) {
  // Loop 1 crosses no sharp edge, but every edge along its side is sharp (the first ring of a
  // paved face); loop 2 crosses one; loop 0 neither.
  std::vector<TraceCandidate> all{candidate(0, 0), candidate(1, 0), candidate(2, 0)};
  all[0].side_sharp = 3;  // 3 of 4: not the whole side
  all[1].side_sharp = 4;
  all[2].crossed_sharp = 1;
  Ranking r = rank(only(first_convex_filter(true)), all);
  EXPECT_EQ(r.filters.front(), "first_convex:3->2");
  EXPECT_EQ(chosen_loops(r, 2), (std::vector<std::int32_t>{1, 2}));
  r = rank(only(first_convex_filter(false)), all);
  EXPECT_EQ(r.filters.front(), "first_convex:3->1") << "the seed's rule keeps loop 2 alone";
  EXPECT_EQ(r.order.front().loop, 2);
  const Selection by_default = extended_selection(ExtendedParameters{});
  const auto first = std::find_if(by_default.filters.begin(), by_default.filters.end(),
                                  [](const Filter& f) { return f.name == "first_convex"; });
  ASSERT_NE(first, by_default.filters.end());
  EXPECT_TRUE(first->keep(all[1])) << "our condition is the default";
  ExtendedParameters seed;
  seed.first_convex_rim = false;
  const Selection seeds = extended_selection(seed);
  const auto seed_first = std::find_if(seeds.filters.begin(), seeds.filters.end(),
                                       [](const Filter& f) { return f.name == "first_convex"; });
  ASSERT_NE(seed_first, seeds.filters.end());
  EXPECT_FALSE(seed_first->keep(all[1]));
}

TEST(Filters, SecondConvexKeepsTheHighestSideEliminationWeight) {
  std::vector<TraceCandidate> all{candidate(0, 0), candidate(1, 0), candidate(2, 0)};
  all[0].side_sharp = 2;  // 2 / 4
  all[1].side_sharp = 3;  // 3 / 4
  all[2].side_sharp = 6;
  all[2].length = 8;  // 6 / 8 = 3 / 4 too
  const Ranking r = rank(only(second_convex_filter()), all);
  EXPECT_EQ(r.filters.front(), "second_convex:3->2");
  EXPECT_EQ(chosen_loops(r, 2), (std::vector<std::int32_t>{1, 2}));
}

TEST(Filters, ParallelCrossingDecidesAndSkipsTheRest) {
  std::vector<TraceCandidate> all{candidate(0, 0), candidate(1, 1), candidate(2, 0)};
  all[1].parallel_to = 5;
  all[0].nonconvex_on_side = 0;
  all[1].nonconvex_on_side = 3;  // the non-convex filter would drop it, but comes later
  Selection s = extended_selection(ExtendedParameters{});
  const Ranking r = rank(s, all);
  EXPECT_EQ(r.filters, (std::vector<std::string>{"parallel_crossing:1"}));
  EXPECT_EQ(r.decided_by, "parallel_crossing");
  EXPECT_EQ(r.order.front().loop, 1);
  EXPECT_NE(r.reason.find("runs along loop 5"), std::string::npos) << r.reason;
}

TEST(Filters, TopologicalOrderIsFewestFacesCollapsedThenWeight) {
  std::vector<TraceCandidate> all{candidate(0, 0), candidate(1, 0), candidate(2, 0)};
  all[0].faces_collapsed = 9;
  all[1].faces_collapsed = 5;
  all[1].weight = 8;
  all[2].faces_collapsed = 5;
  all[2].weight = 6;
  Selection s = extended_selection(ExtendedParameters{});
  s.filters.clear();
  const Ranking r = rank(s, all);
  EXPECT_EQ(chosen_loops(r, 3), (std::vector<std::int32_t>{2, 1, 0}));
  EXPECT_EQ(r.filters, (std::vector<std::string>{"topological:3"}));
  EXPECT_EQ(r.reason, "filters topological:3; fewest faces collapsed");
}

TEST(Selections, ReliableIsTheSmallestWeightAndSelfIntersectingLoopsGoLast) {
  std::vector<TraceCandidate> all{candidate(0, 0), candidate(1, 0), candidate(2, 0)};
  all[0].weight = 1;
  all[0].self_intersecting = true;
  all[1].weight = 5;
  all[2].weight = 3;
  const Ranking r = rank(reliable_selection(), all);
  EXPECT_EQ(chosen_loops(r, 3), (std::vector<std::int32_t>{2, 1, 0}));
  EXPECT_TRUE(r.filters.empty());
  EXPECT_EQ(r.decided_by, "weight");
  EXPECT_EQ(r.reason, "smallest weight (strictly on side + on strip)");
}

TEST(Selections, ExtendedListsTheFiltersOfFigure15InOrder) {
  const Selection s = extended_selection(ExtendedParameters{});
  std::vector<std::string> names;
  for (const Filter& f : s.filters) names.push_back(f.name);
  // Our default order: depth after the convex filters (docs/extended-rules.md).
  EXPECT_EQ(names, (std::vector<std::string>{"parallel_crossing", "nonconvex", "first_convex",
                                             "second_convex", "depth"}));
  EXPECT_TRUE(s.geometric);
  ExtendedParameters seed;
  seed.depth_after_convex = false;
  names.clear();
  for (const Filter& f : extended_selection(seed).filters) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"parallel_crossing", "nonconvex", "depth",
                                             "first_convex", "second_convex"}))
      << "the seed's order of Fig. 15";
  ExtendedParameters p;
  p.depth_filter = false;
  p.parallel_crossing = false;
  EXPECT_EQ(extended_selection(p).filters.size(), 3u) << "a switched-off filter is not listed";
}

TEST(Selections, AUserListReplacesTheRuleSetsAndStillWeaves) {
  // A third list: the largest reliable weight first (the opposite of RWW). It must change
  // the order in which a box's loops are shrunk, and still weave the box.
  auto mine = std::make_shared<Selection>(reliable_selection());
  mine->name = "heaviest-first";
  mine->order = [](const TraceCandidate& p, const TraceCandidate& q) {
    return p.weight > q.weight;
  };
  mine->last_reason = "largest weight";
  const auto box = test::box_surface(3, 2, 2);
  WeaveOptions a;
  a.check = true;
  a.trace = true;
  WeaveOptions b = a;
  b.selection = mine;
  const WeaveResult ra = weave(box.surface, a);
  const WeaveResult rb = weave(box.surface, b);
  EXPECT_EQ(ra.complex.hexes.size(), 12u) << "reliable: the structured box";
  EXPECT_TRUE(stc::validate_hex_complex(rb.complex, &box.surface).valid);
  EXPECT_NE(rb.complex.hexes.size(), 12u) << "heaviest first weaves another complex";
  const auto first_choice = [](const WeaveResult& r) -> const TraceEvent& {
    for (const TraceEvent& e : r.trace)
      if (e.kind == TraceEvent::Kind::Selection) return e;
    throw std::logic_error("no selection");
  };
  const TraceEvent& ea = first_choice(ra);
  const TraceEvent& eb = first_choice(rb);
  EXPECT_EQ(eb.reason, "largest weight");
  EXPECT_LT(ea.candidates[static_cast<std::size_t>(ea.chosen)].weight,
            eb.candidates[static_cast<std::size_t>(eb.chosen)].weight);
}

TEST(Selections, ExperimentalSoftDepthKeepsDepthsWithinOne) {
  std::vector<TraceCandidate> all{candidate(0, 0), candidate(1, 0), candidate(2, 0)};
  all[0].depth = 3;
  all[1].depth = 1;
  all[2].depth = 2;
  const Ranking r = rank(only(experimental::depth_within_one_filter()), all);
  EXPECT_EQ(r.filters.front(), "depth_within_one:3->2");
  const Selection s = experimental::extended_soft_depth_selection(ExtendedParameters{});
  EXPECT_TRUE(std::any_of(s.filters.begin(), s.filters.end(),
                          [](const Filter& f) { return f.name == "depth_within_one"; }));
  EXPECT_TRUE(std::none_of(s.filters.begin(), s.filters.end(),
                           [](const Filter& f) { return f.name == "depth"; }));
}

// ---------------------------------------------------------------------------------------
// candidate properties on a hand-built front

TEST(Properties, ReliableWeightsOfACubeLoop) {
  // A cube loop's strip holds all 8 nodes; each side has one face and no node off the strip.
  const auto cube = test::box_surface(1, 1, 1);
  const Front front(cube.surface);
  Marks nodes, faces;
  const FrontLoops loops = front_loops(front);
  ASSERT_EQ(loops.strips.size(), 3u);
  const FrontComponents comps = front_components(front, nodes);
  const auto c = weigh(front, loops.strips[0], comps, nodes, faces);
  for (const TraceCandidate& x : c) {
    EXPECT_EQ(x.length, 4u);
    EXPECT_EQ(x.on_strip, 8u);
    EXPECT_EQ(x.strictly_on_side, 0u);
    EXPECT_EQ(x.weight, 8u);
    EXPECT_FALSE(x.self_intersecting);
  }
}

TEST(Properties, ExtendedPropertiesSeeSharpEdgesAndDepth) {
  const auto box = test::box_surface(1, 1, 3);
  Front front(box.surface);
  // every edge taken as a sharp convex box edge (90 degrees)
  for (std::size_t f = 0; f < front.face_capacity(); ++f)
    front.set_side_angles(static_cast<FaceIndex>(f), {90.0F, 90.0F, 90.0F, 90.0F});
  Marks nodes, faces, faces2;
  const FrontLoops loops = front_loops(front);
  const FrontComponents comps = front_components(front, nodes);
  ExtendedParameters p;
  for (const Strip& strip : loops.strips) {
    const auto c = extended_properties(front, strip, comps, p, nodes, faces, faces2);
    for (const TraceCandidate& x : c) {
      EXPECT_EQ(x.crossed_sharp, strip.size()) << "every edge is taken as sharp here";
      EXPECT_EQ(x.side_sharp, strip.size());
      EXPECT_EQ(x.nonconvex_on_side, 0u);
      EXPECT_EQ(x.depth, 0) << "only input faces: depth 0";
    }
    EXPECT_EQ(c[0].faces_collapsed + c[1].faces_collapsed, 14u + strip.size())
        << "both sides together hold every face, the strip counted twice";
  }
}

// ---------------------------------------------------------------------------------------
// edge classes (seed sect. 4.4, Fig. 8)

TEST(ClassifyEdge, FollowsTheFiveIntervalsAndTheirBounds) {
  const ExtendedParameters p;
  EXPECT_EQ(classify_edge(1.0, p), EdgeClass::SharpConvex);
  EXPECT_EQ(classify_edge(120.0, p), EdgeClass::SharpConvex) << "]0, 120]";
  EXPECT_EQ(classify_edge(120.5, p), EdgeClass::LittleSharpConvex);
  EXPECT_EQ(classify_edge(170.0, p), EdgeClass::LittleSharpConvex) << "]120, 170]";
  EXPECT_EQ(classify_edge(170.5, p), EdgeClass::Flat);
  EXPECT_EQ(classify_edge(190.0, p), EdgeClass::Flat) << "]170, 190]";
  EXPECT_EQ(classify_edge(200.0, p), EdgeClass::LittleSharpNonConvex);
  EXPECT_EQ(classify_edge(240.0, p), EdgeClass::LittleSharpNonConvex) << "]190, 240]";
  EXPECT_EQ(classify_edge(240.5, p), EdgeClass::SharpNonConvex);
  EXPECT_EQ(classify_edge(359.0, p), EdgeClass::SharpNonConvex);
}

TEST(ClassifyEdge, ThresholdsAreParameters) {
  ExtendedParameters p;
  p.sharp = 100.0;
  EXPECT_EQ(classify_edge(110.0, p), EdgeClass::LittleSharpConvex);
  p.flat = 200.0;
  p.little_sharp_nonconvex = 250.0;
  EXPECT_EQ(classify_edge(195.0, p), EdgeClass::Flat);
  EXPECT_EQ(to_string(EdgeClass::LittleSharpNonConvex), "a little sharp non-convex");
  p.flat = 160.0;  // below little_sharp
  EXPECT_THROW(check_parameters(p), InvalidInput);
}

}  // namespace
}  // namespace stcweave::weave
