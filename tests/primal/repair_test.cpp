// The repair of hexes the untangling leaves inverted (`repair_inverted`, docs/geometry.md
// "Repair"): local max-min moves on the scaled Jacobian around the inverted hexes.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include "position_helpers.hpp"
#include "stcweave/primal/position.hpp"
#include "stcweave/primal/quality.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

/// A 5x5x5 box, boundary first, its interior scrambled by `fraction` of the shortest edge.
HexMesh tangled_box(double fraction, std::vector<bool>* fixed) {
  HexMesh mesh = test::box_hexes(5, 5, 5);
  const std::size_t num_fixed = test::boundary_first(mesh);
  fixed->assign(static_cast<std::size_t>(mesh.points.rows()), false);
  for (std::size_t v = 0; v < num_fixed; ++v) (*fixed)[v] = true;
  test::scramble(mesh, *fixed, fraction, 11);
  return mesh;
}

TEST(Repair, RaisesInvertedHexesWithFreeNodesToValid) {
  std::vector<bool> fixed;
  HexMesh mesh = tangled_box(0.9, &fixed);
  const QualitySummary before = summarize_quality(mesh, 0);
  ASSERT_GT(before.inverted, 0u) << "the test needs a tangled start";
  const Points start = mesh.points;
  const RepairReport r = repair_inverted(mesh, fixed, {});
  EXPECT_TRUE(r.ran);
  EXPECT_EQ(r.inverted_before, before.inverted);
  EXPECT_EQ(r.stop, "repaired");
  const QualitySummary after = summarize_quality(mesh, 0);
  EXPECT_EQ(after.inverted, 0u);
  EXPECT_EQ(r.inverted_after, 0u);
  EXPECT_GT(after.min_scaled_jacobian, 0.0);
  EXPECT_DOUBLE_EQ(r.min_scaled_jacobian_after, after.min_scaled_jacobian);
  for (std::size_t v = 0; v < fixed.size(); ++v)
    if (fixed[v])
      EXPECT_EQ(mesh.points.row(static_cast<Eigen::Index>(v)),
                start.row(static_cast<Eigen::Index>(v)))
          << "fixed node n" << v << " moved";
}

TEST(Repair, NeverRaisesTheInvertedCountNorLowersTheWorstHex) {
  // Only the nodes of the inverted hexes may move (0 rings) and each sweep is one: whatever
  // is left, the count never grows and, at the same count, the minimum never drops.
  for (const int sweeps : {1, 2, 5}) {
    std::vector<bool> fixed;
    HexMesh mesh = tangled_box(0.9, &fixed);
    const QualitySummary before = summarize_quality(mesh, 0);
    PositionOptions options;
    options.max_repair_sweeps = sweeps;
    options.repair_rings = 0;
    const RepairReport r = repair_inverted(mesh, fixed, options);
    const QualitySummary after = summarize_quality(mesh, 0);
    EXPECT_LE(after.inverted, before.inverted) << sweeps;
    if (after.inverted == before.inverted) {
      EXPECT_GE(after.min_scaled_jacobian, before.min_scaled_jacobian) << sweeps;
    }
    EXPECT_LE(r.sweeps, static_cast<std::size_t>(sweeps));
  }
}

TEST(Repair, CannotMoveAHexWhoseNodesAreAllFixed) {
  // One hex with its top face pushed through the bottom: inverted, every node fixed.
  HexMesh mesh = test::box_hexes(1, 1, 1);
  for (Eigen::Index v = 0; v < mesh.points.rows(); ++v)
    if (mesh.points(v, 2) > 0.5) mesh.points(v, 2) = -1.0;
  ASSERT_EQ(summarize_quality(mesh, 0).inverted, 1u);
  const Points start = mesh.points;
  const RepairReport r = repair_inverted(
      mesh, std::vector<bool>(static_cast<std::size_t>(mesh.points.rows()), true), {});
  EXPECT_FALSE(r.ran);
  EXPECT_EQ(r.inverted_after, 1u);
  EXPECT_EQ(mesh.points, start);
}

TEST(Repair, NothingToDoOnAValidMesh) {
  HexMesh mesh = test::box_hexes(3, 3, 3);
  const Points start = mesh.points;
  const RepairReport r = repair_inverted(
      mesh, std::vector<bool>(static_cast<std::size_t>(mesh.points.rows()), false), {});
  EXPECT_FALSE(r.ran);
  EXPECT_EQ(r.stop, "nothing inverted");
  EXPECT_EQ(mesh.points, start);
}

TEST(Repair, PositionNodesRepairsWhatAnEarlyStopLeaves) {
  // An untangling cut short (no round at all) leaves the tangled start; the repair after it
  // makes every hex valid, and the shape phase then runs on a valid mesh.
  std::vector<bool> fixed;
  HexMesh mesh = tangled_box(0.9, &fixed);
  ASSERT_GT(summarize_quality(mesh, 0).inverted, 0u);
  PositionOptions options;
  options.fixed = fixed;
  options.start = StartPosition::Keep;
  options.max_outer_iterations = 0;
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_GT(r.inverted_before, 0u);
  EXPECT_TRUE(r.repair.ran) << r.repair.stop;
  EXPECT_EQ(r.repair.inverted_after, 0u) << r.repair.stop;
  EXPECT_EQ(r.inverted_after, 0u) << r.stop;
  EXPECT_TRUE(r.untangled) << r.stop;
  EXPECT_NE(r.stop.find("repair: "), std::string::npos) << r.stop;
  EXPECT_NE(r.shape.stop, "inverted hexes: skipped");
  // The same without the repair (and without the local untangling after it, which would
  // untangle this box too): the early stop keeps its inverted hexes.
  HexMesh plain = tangled_box(0.9, &fixed);
  options.max_repair_sweeps = 0;
  options.cluster_passes = 0;
  const PositionReport s = position_nodes(plain, options);
  EXPECT_GT(s.inverted_after, 0u);
  EXPECT_EQ(s.repair.stop, "off");
}

TEST(Repair, ProgressIsToldEverySweep) {
  std::vector<bool> fixed;
  HexMesh mesh = tangled_box(0.9, &fixed);
  const std::size_t start = summarize_quality(mesh, 0).inverted;
  ASSERT_GT(start, 0u);
  PositionOptions options;
  options.fixed = fixed;
  options.start = StartPosition::Keep;
  options.max_outer_iterations = 0;
  std::vector<PositionProgress> sweeps;
  options.progress = [&sweeps](const PositionProgress& p) {
    if (p.phase == PositionProgress::Phase::Repair) sweeps.push_back(p);
  };
  const PositionReport r = position_nodes(mesh, options);
  ASSERT_TRUE(r.repair.ran) << r.repair.stop;
  ASSERT_EQ(sweeps.size(), r.repair.sweeps);
  for (std::size_t i = 0; i < sweeps.size(); ++i) {
    EXPECT_EQ(sweeps[i].step, i + 1);
    EXPECT_EQ(sweeps[i].limit, static_cast<std::size_t>(options.max_repair_sweeps));
    EXPECT_LE(sweeps[i].inverted, i == 0 ? start : sweeps[i - 1].inverted);
  }
  EXPECT_EQ(sweeps.back().inverted, r.repair.inverted_after);
  EXPECT_EQ(sweeps.back().min_scaled_jacobian, r.repair.min_scaled_jacobian_after);
}

TEST(Repair, TheUntangledPositionsAndTheStartAreBothRepairedAndTheBetterKept) {
  // A short untangling and a three-sweep repair leave hexes inverted: position_nodes then
  // repairs the start as well and keeps whichever has fewer inverted hexes (then the larger
  // minimum; a tie keeps the untangled positions). Recomputed here by hand from the same
  // untangled positions and the same start.
  std::size_t checked = 0;
  std::size_t start_kept = 0;
  for (const std::uint32_t seed : {1U, 2U, 3U, 4U, 5U, 6U, 7U, 8U, 9U, 10U}) {
    HexMesh start = test::box_hexes(5, 5, 5);
    const std::vector<bool> fixed = test::boundary_nodes(start);
    test::scramble(start, fixed, 3.0, seed);
    PositionOptions o;
    o.fixed = fixed;
    o.start = StartPosition::Keep;
    o.max_outer_iterations = 1;
    o.max_inner_iterations = 5;
    o.max_repair_sweeps = 3;
    o.max_shape_sweeps = 0;
    o.barrier_rounds = 0;
    o.cluster_passes = 0;  // the two repairs alone (the local untangling comes after them)
    HexMesh mesh = start;
    const PositionReport r = position_nodes(mesh, o);
    EXPECT_EQ(summarize_quality(mesh, 0).inverted, r.inverted_after) << "seed " << seed;
    // By hand: the untangled positions without a repair, then each one repaired.
    PositionOptions untangle_only = o;
    untangle_only.max_repair_sweeps = 0;
    HexMesh untangled = start;
    const PositionReport u = position_nodes(untangled, untangle_only);
    if (u.inverted_after == 0 || u.kept_start) continue;  // nothing left, or the guard's case
    repair_inverted(untangled, fixed, o);
    const QualitySummary qu = summarize_quality(untangled, 0);
    if (qu.inverted == 0) {
      EXPECT_FALSE(r.other_repair.ran) << "seed " << seed << ": " << r.stop;
      continue;
    }
    HexMesh from_start = start;
    repair_inverted(from_start, fixed, o);
    const QualitySummary qs = summarize_quality(from_start, 0);
    ++checked;
    ASSERT_TRUE(r.other_repair.ran) << "seed " << seed << ": " << r.stop;
    const bool start_better =
        qs.inverted < qu.inverted ||
        (qs.inverted == qu.inverted && qs.min_scaled_jacobian > qu.min_scaled_jacobian);
    EXPECT_EQ(r.repaired_from, start_better ? "start" : "untangled") << "seed " << seed;
    EXPECT_EQ(r.kept_start, start_better) << "seed " << seed;
    EXPECT_EQ(r.inverted_after, std::min(qs.inverted, qu.inverted)) << "seed " << seed;
    EXPECT_EQ(mesh.points, start_better ? from_start.points : untangled.points) << "seed " << seed;
    EXPECT_NE(r.stop.find(std::string("), ") + (start_better ? "kept" : "not kept")),
              std::string::npos)
        << r.stop;
    start_kept += start_better;
  }
  // Both ways are exercised (measured with these settings: 8 of the 10 seeds are compared,
  // the start is kept on 4).
  EXPECT_GT(start_kept, 0u);
  EXPECT_LT(start_kept, checked);
  std::cout << checked << " seeds compared, the start kept on " << start_kept << "\n";
}

TEST(Repair, IsDeterministic) {
  std::vector<bool> fixed;
  HexMesh a = tangled_box(0.9, &fixed);
  HexMesh b = a;
  (void)repair_inverted(a, fixed, {});
  (void)repair_inverted(b, fixed, {});
  EXPECT_EQ(a.points, b.points);
}

}  // namespace
}  // namespace stcweave::primal
