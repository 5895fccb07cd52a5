#include "stcweave/stc/loop_moves.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <memory>
#include <optional>

#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/loops.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/quadrangulations.hpp"
#include "support/shapes.hpp"

namespace stcweave::stc {
namespace {

/// The generated sphere of `seed` (`base + seed % spread` quads, `rotations` edge rotations;
/// tests/support/quadrangulations.hpp) when it is even and some loop crosses itself.
std::optional<QuadSurface> even_self_crossing(std::uint32_t seed, int base, int spread,
                                              int rotations) {
  const auto mesh =
      test::random_quadrangulation(seed, base + static_cast<int>(seed % spread), rotations);
  if (!mesh || mesh->surface.quads.size() % 2 == 1) return std::nullopt;
  if (find_loops(mesh->surface, {.sides = false}).num_self_intersecting() == 0) return std::nullopt;
  return mesh->surface;
}

TEST(LoopMoves, BoxesAreFilledByMovesAloneWithTheirStructuredHexes) {
  for (const auto& [a, b, c] :
       std::vector<std::array<int, 3>>{{1, 1, 1}, {2, 1, 1}, {3, 1, 1}, {2, 2, 1}, {2, 2, 2}}) {
    const QuadSurface s = test::box_surface(a, b, c).surface;
    const LoopMoveResult r = fill_front(untangle_loops(s));
    ASSERT_TRUE(r.simple) << a << "x" << b << "x" << c << ": " << r.stop_reason;
    EXPECT_TRUE(r.front.quads.empty());
    EXPECT_EQ(r.hexes.hexes.size(), static_cast<std::size_t>(a * b * c));
    const ValidationReport v = validate_hex_complex(r.hexes, &s);
    EXPECT_TRUE(v.valid) << v.summary();
  }
}

TEST(LoopMoves, ASurfaceWithSimpleLoopsIsLeftAsItIs) {
  const QuadSurface s = test::box_surface(3, 2, 2).surface;
  const LoopMoveResult r = untangle_loops(s);
  EXPECT_TRUE(r.simple);
  EXPECT_EQ(r.stop_reason, "simple");
  EXPECT_TRUE(r.moves.empty());
  EXPECT_EQ(r.front.quads, s.quads);
  EXPECT_EQ(r.front_input.size(), s.quads.size());
}

TEST(LoopMoves, RefusesAnOpenSurface) {
  QuadSurface s = test::box_surface(1, 1, 1).surface;
  s.quads.pop_back();
  EXPECT_THROW((void)untangle_loops(s), InvalidInput);
}

// After the moves, on every generated sphere with self-crossing loops: the front is a strong
// quad surface (closed, oriented, valence >= 3, no repeated face, no two faces on two edges),
// the attached hexes have 8 distinct nodes each, no face in three hexes, no two hexes sharing
// two faces, matching face orientations, closed cycles around their interior edges, and the
// covered input quads plus the front's hex faces as the faces they use once, (loops crossing
// themselves an odd number of times, self-crossing quads) never grows, and `simple` tells the
// truth.
TEST(LoopMoves, MovesKeepTheFrontAndTheAttachedHexesValid) {
  std::size_t checked = 0, with_moves = 0, simple = 0;
  LoopMoveOptions options;
  options.max_evaluations = 5000;
  for (std::uint32_t seed = 0; seed < 200; ++seed) {
    const auto surface = even_self_crossing(seed, 8, 14, 40);
    if (!surface) continue;
    const QuadSurface& s = *surface;
    const LoopMoveResult r = untangle_loops(s, options);
    ++checked;
    EXPECT_TRUE(test::is_strong_quadrangulation(r.front)) << "seed " << seed;
    const LoopSet loops = find_loops(r.front, {.sides = false});
    const auto odd_loops = [](const LoopSet& set) {
      std::size_t n = 0;
      for (const Loop& l : set.loops) n += l.self_crossing_quads.size() % 2;
      return n;
    };
    const LoopSet input_loops = find_loops(s, {.sides = false});
    EXPECT_LE(std::make_pair(odd_loops(loops), r.self_crossing_quads_after),
              std::make_pair(odd_loops(input_loops), r.self_crossing_quads_before))
        << "seed " << seed;
    EXPECT_EQ(r.simple, loops.num_self_intersecting() == 0) << "seed " << seed;
    EXPECT_EQ(r.self_crossing_quads_after, loops.num_self_crossing_quads());
    simple += r.simple ? 1 : 0;
    if (r.hexes.hexes.empty()) continue;
    ++with_moves;
    QuadSurface boundary;
    boundary.num_nodes = r.hexes.num_nodes;
    std::vector<bool> on_front(s.quads.size(), false);
    for (std::size_t q = 0; q < r.front.quads.size(); ++q) {
      if (r.front_input[q] >= 0) {
        on_front[static_cast<std::size_t>(r.front_input[q])] = true;
      } else {
        boundary.quads.push_back(reversed(r.front.quads[q]));
      }
    }
    for (std::size_t q = 0; q < s.quads.size(); ++q)
      if (!on_front[q]) boundary.quads.push_back(s.quads[q]);
    // The attached hexes alone may touch themselves along an edge or at a node (two bumps on
    // quads sharing an edge): only the whole complex must be a manifold. Every other
    // invariant holds for them.
    const ValidationReport v = validate_hex_complex(r.hexes, &boundary);
    for (const Violation& x : v.violations) {
      const bool whole_only = x.invariant == Invariant::BoundaryEdgeFan ||
                              x.invariant == Invariant::VertexLink ||
                              x.invariant == Invariant::EulerCharacteristic;
      EXPECT_TRUE(whole_only) << "seed " << seed << ": " << x.name() << " " << x.count;
    }
  }
  EXPECT_GT(checked, 20U);
  EXPECT_GT(with_moves, 10U);
  // With `strict_contacts` (the default since 2026-12-07: no two attached hexes share four
  // nodes off a face) the search leaves 3 of these fronts simple; without it, more than 10,
  // but with attached hexes that no valid complex can hold.
  EXPECT_GE(simple, 3U);
}

// The search updates a front's score after each candidate move by re-tracing only the loops
// the move changed. With `check_scores` it also traces the whole front and throws when the
// two disagree (score, or which strands share a loop and how often it crosses itself); the
// search itself must be the same with and without the check.
TEST(LoopMoves, ScoresUpdatedFromTheChangedLoopsMatchAFullTrace) {
  std::size_t checked = 0;
  std::size_t evaluations = 0;
  for (std::uint32_t seed = 0; seed < 200 && checked < 30; ++seed) {
    const auto surface = even_self_crossing(seed, 8, 24, 40);
    if (!surface) continue;
    const QuadSurface& s = *surface;
    LoopMoveOptions options;
    options.max_evaluations = 3000;
    const LoopMoveResult plain = untangle_loops(s, options);
    options.check_scores = true;
    LoopMoveResult checked_run;
    ASSERT_NO_THROW(checked_run = untangle_loops(s, options)) << "seed " << seed;
    ++checked;
    evaluations += checked_run.evaluations;
    EXPECT_EQ(checked_run.evaluations, plain.evaluations) << "seed " << seed;
    EXPECT_EQ(checked_run.hexes.hexes, plain.hexes.hexes) << "seed " << seed;
    EXPECT_EQ(checked_run.front.quads, plain.front.quads) << "seed " << seed;
    EXPECT_EQ(checked_run.self_crossing_quads_after, plain.self_crossing_quads_after);
  }
  EXPECT_GE(checked, 10U);
  EXPECT_GT(evaluations, 10000U);  // the check ran on many moves, not a handful
}

// The same check while fronts are filled by moves alone (`fill_front`, the goal of an empty
// front): there the caps and closes happen, the moves that leave one new face or none, and a
// loop can vanish with the faces it lies on. Boxes and the small generated spheres; each fill
// with the check gives what it gives without.
TEST(LoopMoves, ScoresStayRightWhileFillingAFront) {
  std::vector<QuadSurface> surfaces;
  for (const auto& [a, b, c] : std::vector<std::array<int, 3>>{{1, 1, 1}, {2, 1, 1}, {2, 2, 2}})
    surfaces.push_back(test::box_surface(a, b, c).surface);
  for (std::uint32_t seed = 0; seed < 200; ++seed) {
    const auto mesh = test::random_quadrangulation(seed, 8 + static_cast<int>(seed % 8), 20);
    if (mesh && mesh->surface.quads.size() % 2 == 0) surfaces.push_back(mesh->surface);
  }
  ASSERT_GE(surfaces.size(), 20U);
  std::size_t filled = 0;
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    LoopMoveOptions options;
    options.max_evaluations = 3000;
    const LoopMoveResult plain = fill_front(untangle_loops(surfaces[i], options), options);
    options.check_scores = true;
    LoopMoveResult checked_run;
    ASSERT_NO_THROW(checked_run = fill_front(untangle_loops(surfaces[i], options), options))
        << "surface " << i;
    EXPECT_EQ(checked_run.hexes.hexes, plain.hexes.hexes) << "surface " << i;
    EXPECT_EQ(checked_run.front.quads, plain.front.quads) << "surface " << i;
    filled += checked_run.front.quads.empty() ? 1 : 0;
  }
  EXPECT_GE(filled, 3U);  // the boxes at least: fills that ran to the end, closes included
}

// The progress callback: called every 10th attached hex and every `progress_every`
// evaluations, with figures that never go back (hexes and evaluations), the last no further
// than the result; the search is the same with and without it.
TEST(LoopMoves, ProgressIsReportedAndChangesNothing) {
  std::size_t searched = 0;
  std::size_t reports = 0;
  for (std::uint32_t seed = 0; seed < 200 && searched < 10; ++seed) {
    const auto surface = even_self_crossing(seed, 16, 10, 60);
    if (!surface) continue;
    LoopMoveOptions options;
    options.max_evaluations = 3000;
    const LoopMoveResult plain = untangle_loops(*surface, options);
    std::vector<LoopMoveProgress> seen;
    options.progress = [&](const LoopMoveProgress& p) { seen.push_back(p); };
    options.progress_every = 200;
    const LoopMoveResult reported = untangle_loops(*surface, options);
    ++searched;
    EXPECT_EQ(reported.hexes.hexes, plain.hexes.hexes) << "seed " << seed;
    EXPECT_EQ(reported.evaluations, plain.evaluations) << "seed " << seed;
    if (plain.evaluations >= 200 || plain.hexes.hexes.size() >= 10) {
      EXPECT_FALSE(seen.empty()) << "seed " << seed;
    }
    for (std::size_t i = 0; i < seen.size(); ++i) {
      EXPECT_FALSE(seen[i].filling);
      EXPECT_LE(seen[i].hexes, reported.hexes.hexes.size());
      EXPECT_LE(seen[i].evaluations, reported.evaluations);
      if (i > 0) {
        EXPECT_GE(seen[i].hexes, seen[i - 1].hexes) << "seed " << seed;
        EXPECT_GE(seen[i].evaluations, seen[i - 1].evaluations) << "seed " << seed;
      }
    }
    reports += seen.size();
  }
  EXPECT_GE(searched, 5U);
  EXPECT_GT(reports, 10U);
}

// Seed 120 of the generated catalogue (16 quads, two loops with one curl each): every
// look-ahead of the search stalls with two self-crossing quads left, and the iterative
// deepening over every move of the tiny front (`LoopMoveOptions::tiny_front`) finds a
// sequence that leaves the loops simple. The moves keep the front and the hexes valid. (The
// search without `strict_contacts`, as when this surface was picked: with it, the look-aheads
// alone untangle this front.)
TEST(LoopMoves, TheDeepeningUntanglesATinyFrontTheLookAheadsLeave) {
  const auto mesh = test::random_quadrangulation(120, 8 + 120 % 14, 40);
  ASSERT_TRUE(mesh.has_value());
  const QuadSurface& s = mesh->surface;
  ASSERT_EQ(s.quads.size(), 16U);
  ASSERT_GT(find_loops(s, {.sides = false}).num_self_intersecting(), 0U);

  LoopMoveOptions loose;
  loose.strict_contacts = false;
  LoopMoveOptions without = loose;
  without.tiny_depth = 0;
  const LoopMoveResult stalled = untangle_loops(s, without);
  EXPECT_FALSE(stalled.simple) << "the look-aheads alone untangle it now: pick another surface";
  EXPECT_EQ(stalled.deepenings, 0U);
  EXPECT_NE(stalled.stop_reason.find("no sequence"), std::string::npos) << stalled.stop_reason;

  const LoopMoveResult r = untangle_loops(s, loose);
  ASSERT_TRUE(r.simple) << r.stop_reason;
  EXPECT_GE(r.deepenings, 1U);
  EXPECT_EQ(r.self_crossing_quads_after, 0U);
  EXPECT_EQ(find_loops(r.front, {.sides = false}).num_self_intersecting(), 0U);
  EXPECT_TRUE(test::is_strong_quadrangulation(r.front));
  // One hex per move, eight distinct nodes each (the whole stage's complex is certified by
  // SelfCrossing.GeneratedSpheresGiveCertifiedComplexesOrCleanRefusals).
  EXPECT_EQ(r.hexes.hexes.size(), r.moves.size());
  for (const Hex& h : r.hexes.hexes) {
    std::array<NodeId, 8> nodes = h;
    std::sort(nodes.begin(), nodes.end());
    EXPECT_EQ(std::adjacent_find(nodes.begin(), nodes.end()), nodes.end());
  }

  // Same answer twice (determinism), and a deepening bounded to no evaluation finds nothing.
  const LoopMoveResult again = untangle_loops(s, loose);
  EXPECT_EQ(again.hexes.hexes, r.hexes.hexes);
  EXPECT_EQ(again.front.quads, r.front.quads);
  LoopMoveOptions starved = loose;
  starved.tiny_evaluations = 0;
  EXPECT_FALSE(untangle_loops(s, starved).simple);
}

// A pool of evaluations shared by searches (`LoopMoveOptions::shared_evaluations`, what
// primal's SharedSearchBudget gives every search of a solid's balls): each search takes its
// evaluations from it as well as from its own bound, copies of the options share it, and a
// search run with an empty pool evaluates nothing and says why. The searches are the same as
// without a pool until it runs dry.
TEST(LoopMoves, SearchesSharingAPoolOfEvaluationsStopWhenItIsEmpty) {
  std::vector<QuadSurface> surfaces;
  for (std::uint32_t seed = 0; seed < 200 && surfaces.size() < 4; ++seed)
    if (auto s = even_self_crossing(seed, 16, 10, 60)) surfaces.push_back(std::move(*s));
  ASSERT_EQ(surfaces.size(), 4U);
  LoopMoveOptions alone;
  alone.max_evaluations = 3000;
  std::vector<std::size_t> used;
  for (const QuadSurface& s : surfaces) used.push_back(untangle_loops(s, alone).evaluations);
  ASSERT_GT(used[0], 0U);

  // A pool that holds exactly the first search's evaluations: that search is unchanged, the
  // next one evaluates nothing.
  LoopMoveOptions pooled = alone;
  pooled.shared_evaluations = std::make_shared<std::size_t>(used[0]);
  const LoopMoveResult first = untangle_loops(surfaces[0], pooled);
  EXPECT_EQ(first.evaluations, used[0]);
  EXPECT_EQ(first.hexes.hexes, untangle_loops(surfaces[0], alone).hexes.hexes);
  EXPECT_EQ(*pooled.shared_evaluations, 0U);
  const LoopMoveOptions copy = pooled;  // shares the pool
  const LoopMoveResult second = untangle_loops(surfaces[1], copy);
  EXPECT_EQ(second.evaluations, 0U);
  if (used[1] > 0) {
    EXPECT_FALSE(second.simple);
    EXPECT_NE(second.stop_reason.find("shared pool"), std::string::npos) << second.stop_reason;
  }

  // A pool large enough for all four: they take exactly their evaluations from it.
  std::size_t total = 0;
  for (const std::size_t u : used) total += u;
  pooled.shared_evaluations = std::make_shared<std::size_t>(total + 5);
  for (std::size_t i = 0; i < surfaces.size(); ++i)
    EXPECT_EQ(untangle_loops(surfaces[i], pooled).evaluations, used[i]) << "surface " << i;
  EXPECT_EQ(*pooled.shared_evaluations, 5U);
}

TEST(LoopMoves, FillFrontRefusesAttachedHexesWithNodesOutOfRange) {
  const QuadSurface s = test::box_surface(1, 1, 1).surface;
  LoopMoveResult start = untangle_loops(s);
  Hex h{};
  for (std::size_t k = 0; k < 8; ++k) h[k] = NodeId(start.hexes.num_nodes + k);
  start.hexes.hexes.push_back(h);
  EXPECT_THROW((void)fill_front(start), InvalidInput);
}

}  // namespace
}  // namespace stcweave::stc
