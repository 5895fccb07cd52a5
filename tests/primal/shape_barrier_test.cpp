// The barrier pass of the shape phase (`raise_worst_corners`), the two orders of
// `improve_shape`, and auto pillowing's comparison (`choose_pillowed`).
#include <gtest/gtest.h>

#include <algorithm>

#include "position_helpers.hpp"
#include "stcweave/primal/pillow.hpp"
#include "stcweave/primal/position.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

/// A 4x4x4 box, boundary first, interior scrambled by `fraction` (seeded); `fixed` marks the
/// boundary.
HexMesh scrambled_box(double fraction, std::vector<bool>* fixed) {
  HexMesh mesh = test::box_hexes(4, 4, 4);
  const std::size_t num_fixed = test::boundary_first(mesh);
  fixed->assign(static_cast<std::size_t>(mesh.points.rows()), false);
  for (std::size_t v = 0; v < num_fixed; ++v) (*fixed)[v] = true;
  test::scramble(mesh, *fixed, fraction, 7);
  return mesh;
}

double min_corner(const HexMesh& mesh) {
  double best = 1.0;
  for (const stc::Hex& h : mesh.complex.hexes)
    best = std::min(best, hex_corner_scaled_jacobian(mesh.points, h));
  return best;
}

TEST(ShapeBarrier, RaisesTheWorstCornerAndKeepsTheBoundary) {
  std::vector<bool> fixed;
  HexMesh mesh = scrambled_box(0.45, &fixed);
  const QualitySummary before = summarize_quality(mesh, 0);
  ASSERT_EQ(before.inverted, 0u) << "the test needs a valid, distorted start";
  ASSERT_LT(before.min_scaled_jacobian, 0.5);
  const Points start = mesh.points;
  const BarrierReport r = raise_worst_corners(mesh, fixed, {});
  EXPECT_TRUE(r.ran) << r.stop;
  EXPECT_GE(r.rounds, 1u);
  EXPECT_GT(r.iterations, 0u);
  EXPECT_DOUBLE_EQ(r.min_scaled_jacobian_before, before.min_scaled_jacobian);
  const QualitySummary after = summarize_quality(mesh, 0);
  EXPECT_DOUBLE_EQ(r.min_scaled_jacobian_after, after.min_scaled_jacobian);
  EXPECT_GT(after.min_scaled_jacobian, before.min_scaled_jacobian + 0.05)
      << before.min_scaled_jacobian << " -> " << after.min_scaled_jacobian;
  EXPECT_GT(r.min_corner_after, r.min_corner_before);
  EXPECT_EQ(after.inverted, 0u);
  for (std::size_t v = 0; v < fixed.size(); ++v) {
    if (fixed[v]) {
      EXPECT_EQ(mesh.points.row(static_cast<Eigen::Index>(v)),
                start.row(static_cast<Eigen::Index>(v)))
          << "boundary node n" << v << " moved";
    }
  }
}

TEST(ShapeBarrier, NeverLowersTheWorstHexOverManyStarts) {
  int valid_starts = 0;
  for (const double fraction : {0.2, 0.3, 0.4, 0.45}) {
    std::vector<bool> fixed;
    HexMesh mesh = scrambled_box(fraction, &fixed);
    const QualitySummary before = summarize_quality(mesh, 0);
    if (before.inverted > 0) continue;
    ++valid_starts;
    const double corner_before = min_corner(mesh);
    (void)raise_worst_corners(mesh, fixed, {});
    const QualitySummary after = summarize_quality(mesh, 0);
    EXPECT_GE(after.min_scaled_jacobian, before.min_scaled_jacobian) << "fraction " << fraction;
    EXPECT_GE(min_corner(mesh), corner_before - 1e-12) << "fraction " << fraction;
    EXPECT_EQ(after.inverted, 0u);
  }
  EXPECT_GE(valid_starts, 3) << "the test needs valid starts";
}

TEST(ShapeBarrier, IsDeterministic) {
  std::vector<bool> fixed;
  HexMesh a = scrambled_box(0.4, &fixed);
  HexMesh b = a;
  (void)improve_shape(a, fixed, {});
  (void)improve_shape(b, fixed, {});
  EXPECT_EQ(a.points, b.points);
}

TEST(ShapeBarrier, SkipsTangledMeshesSwitchesOffAndRefusesBadOptions) {
  std::vector<bool> fixed;
  HexMesh tangled = scrambled_box(3.0, &fixed);
  ASSERT_GT(summarize_quality(tangled, 0).inverted, 0u);
  const Points start = tangled.points;
  BarrierReport r = raise_worst_corners(tangled, fixed, {});
  EXPECT_FALSE(r.ran);
  EXPECT_EQ(r.stop, "inverted hexes: skipped");
  EXPECT_EQ(tangled.points, start);

  HexMesh valid = scrambled_box(0.3, &fixed);
  const Points valid_start = valid.points;
  PositionOptions off;
  off.barrier_rounds = 0;
  r = raise_worst_corners(valid, fixed, off);
  EXPECT_EQ(r.stop, "off");
  EXPECT_EQ(valid.points, valid_start);
  const ShapeReport local = improve_shape(valid, fixed, off);
  EXPECT_EQ(local.barrier.stop, "off");
  EXPECT_TRUE(local.order.empty());

  PositionOptions bad;
  bad.barrier_margin = 1.0;
  EXPECT_THROW((void)raise_worst_corners(valid, fixed, bad), InvalidInput);
  bad = {};
  bad.barrier_softness = 0.0;
  EXPECT_THROW((void)raise_worst_corners(valid, fixed, bad), InvalidInput);
  std::vector<bool> short_mask(3, false);
  EXPECT_THROW((void)raise_worst_corners(valid, short_mask, {}), InvalidInput);
}

TEST(ShapeBarrier, BothOrdersAtLeastAsGoodAsTheLocalMovesAlone) {
  for (const double fraction : {0.3, 0.45}) {
    std::vector<bool> fixed;
    HexMesh with = scrambled_box(fraction, &fixed);
    if (summarize_quality(with, 0).inverted > 0) continue;
    HexMesh without = with;
    PositionOptions local_only;
    local_only.barrier_rounds = 0;
    const ShapeReport l = improve_shape(without, fixed, local_only);
    const ShapeReport b = improve_shape(with, fixed, {});
    EXPECT_TRUE(b.order == "barrier first" || b.order == "local first") << b.order;
    // "local first" starts with exactly the local moves and only raises the minimum after.
    EXPECT_GE(b.min_scaled_jacobian_after, l.min_scaled_jacobian_after - 1e-12)
        << "fraction " << fraction;
    EXPECT_DOUBLE_EQ(b.min_scaled_jacobian_after, summarize_quality(with, 0).min_scaled_jacobian);
  }
}

TEST(PillowSelect, FewerInvertedThenLargerMinimumThenThePillow) {
  const PillowCandidate good{0, 0.30, 0.5, 100};
  const PillowCandidate worse{0, 0.10, 0.8, 14};
  const PillowCandidate tangled{3, 0.90, 0.9, 50};
  EXPECT_TRUE(choose_pillowed(good, worse));
  EXPECT_FALSE(choose_pillowed(worse, good));
  EXPECT_FALSE(choose_pillowed(tangled, worse)) << "inverted hexes lose whatever the minimum";
  EXPECT_TRUE(choose_pillowed(worse, tangled));
  EXPECT_TRUE(choose_pillowed(good, good)) << "a tie keeps the pillow";
}

TEST(PillowSelect, ComparedReportSaysWhatWasKept) {
  PillowReport r;
  r.mode = PillowMode::Auto;
  r.applied = true;
  r.shells = 1;
  r.shells_pillowed = 1;
  r.nodes_added = 8;
  r.hexes_added = 6;
  r.worst_fixed_corner = 0.1;
  r.reason = "auto: pillowed";
  PillowOptions options;
  EXPECT_TRUE(pillow_worth_comparing(r, options));
  options.compare = false;
  EXPECT_FALSE(pillow_worth_comparing(r, options));
  options.compare = true;
  PillowReport flat = r;
  flat.worst_fixed_corner = 0.0;
  EXPECT_FALSE(pillow_worth_comparing(flat, options)) << "a flat fixed corner needs the pillow";

  const PillowCandidate with{0, 0.05, 0.4, 7};
  const PillowCandidate without{0, 0.1, 0.8, 1};
  const PillowReport dropped = compared_pillow_report(r, false, with, without);
  EXPECT_TRUE(dropped.compared);
  EXPECT_FALSE(dropped.applied);
  EXPECT_EQ(dropped.shells_pillowed, 0u);
  EXPECT_EQ(dropped.nodes_added, 0u);
  EXPECT_EQ(dropped.hexes_added, 0u);
  EXPECT_NE(dropped.reason.find("not pillowed"), std::string::npos) << dropped.reason;
  const PillowReport kept = compared_pillow_report(r, true, without, with);
  EXPECT_TRUE(kept.applied);
  EXPECT_EQ(kept.hexes_added, 6u);
  EXPECT_NE(kept.reason.find("pillow kept"), std::string::npos) << kept.reason;
}

}  // namespace
}  // namespace stcweave::primal
