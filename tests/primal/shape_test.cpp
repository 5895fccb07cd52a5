// The shape phase after untangling (`improve_shape`) and the early stop on a good start.
#include <gtest/gtest.h>

#include "position_helpers.hpp"
#include "stcweave/primal/position.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

/// A 4x4x4 box, boundary first, with its interior scrambled by `fraction` (seeded).
HexMesh scrambled_box(double fraction, std::size_t* num_fixed) {
  HexMesh mesh = test::box_hexes(4, 4, 4);
  *num_fixed = test::boundary_first(mesh);
  std::vector<bool> fixed(static_cast<std::size_t>(mesh.points.rows()), false);
  for (std::size_t v = 0; v < *num_fixed; ++v) fixed[v] = true;
  test::scramble(mesh, fixed, fraction, 7);
  return mesh;
}

std::vector<bool> first_fixed(const HexMesh& mesh, std::size_t num_fixed) {
  std::vector<bool> fixed(static_cast<std::size_t>(mesh.points.rows()), false);
  for (std::size_t v = 0; v < num_fixed; ++v) fixed[v] = true;
  return fixed;
}

TEST(Shape, RaisesTheWorstHexAndNeverLowersIt) {
  std::size_t num_fixed = 0;
  HexMesh mesh = scrambled_box(0.45, &num_fixed);
  const QualitySummary before = summarize_quality(mesh, 0);
  ASSERT_EQ(before.inverted, 0u) << "the test needs a valid, distorted start";
  ASSERT_LT(before.min_scaled_jacobian, 0.6);
  const Points start = mesh.points;
  PositionOptions options;
  options.barrier_rounds = 0;  // the local moves alone (the barrier: shape_barrier_test.cpp)
  const ShapeReport r = improve_shape(mesh, first_fixed(mesh, num_fixed), options);
  EXPECT_TRUE(r.ran);
  EXPECT_GT(r.moves, 0u);
  EXPECT_GE(r.sweeps, 1u);
  EXPECT_DOUBLE_EQ(r.min_scaled_jacobian_before, before.min_scaled_jacobian);
  const QualitySummary after = summarize_quality(mesh, 0);
  EXPECT_DOUBLE_EQ(r.min_scaled_jacobian_after, after.min_scaled_jacobian);
  EXPECT_GT(after.min_scaled_jacobian, before.min_scaled_jacobian + 0.05)
      << "worst " << before.min_scaled_jacobian << " -> " << after.min_scaled_jacobian;
  EXPECT_EQ(after.inverted, 0u);
  EXPECT_TRUE(r.stop == "target reached" || r.stop == "settled" || r.stop == "sweep limit")
      << r.stop;
  for (Eigen::Index v = 0; v < static_cast<Eigen::Index>(num_fixed); ++v)
    EXPECT_EQ(mesh.points.row(v), start.row(v)) << "boundary node n" << v << " moved";
}

TEST(Shape, IsDeterministic) {
  std::size_t num_fixed = 0;
  HexMesh a = scrambled_box(0.3, &num_fixed);
  HexMesh b = a;
  (void)improve_shape(a, first_fixed(a, num_fixed), {});
  (void)improve_shape(b, first_fixed(b, num_fixed), {});
  EXPECT_EQ(a.points, b.points);
}

TEST(Shape, SkipsATangledMeshAndCanBeSwitchedOff) {
  std::size_t num_fixed = 0;
  HexMesh mesh = scrambled_box(3.0, &num_fixed);
  ASSERT_GT(summarize_quality(mesh, 0).inverted, 0u);
  const Points start = mesh.points;
  ShapeReport r = improve_shape(mesh, first_fixed(mesh, num_fixed), {});
  EXPECT_FALSE(r.ran);
  EXPECT_EQ(r.stop, "inverted hexes: skipped");
  EXPECT_EQ(mesh.points, start);

  HexMesh valid = scrambled_box(0.3, &num_fixed);
  const Points valid_start = valid.points;
  PositionOptions off;
  off.max_shape_sweeps = 0;
  r = improve_shape(valid, first_fixed(valid, num_fixed), off);
  EXPECT_EQ(r.stop, "off");
  EXPECT_EQ(valid.points, valid_start);
}

TEST(Shape, RejectsAWrongMask) {
  std::size_t num_fixed = 0;
  HexMesh mesh = scrambled_box(0.3, &num_fixed);
  EXPECT_THROW((void)improve_shape(mesh, std::vector<bool>(3, false), {}), InvalidInput);
}

TEST(GoodStart, AValidGoodStartIsKeptWithoutUntanglingRounds) {
  HexMesh mesh = test::box_hexes(4, 4, 4);
  PositionOptions options;
  options.num_fixed = test::boundary_first(mesh);
  const Points start = mesh.points;
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_TRUE(r.good_start);
  EXPECT_EQ(r.outer_iterations, 0u);
  EXPECT_EQ(r.iterations, 0u);
  EXPECT_TRUE(r.converged);
  EXPECT_NE(r.stop.find("good start"), std::string::npos) << r.stop;
  EXPECT_EQ(mesh.points, start) << "a perfect grid stays as it is";
  EXPECT_NEAR(r.min_scaled_jacobian_after, 1.0, 1e-12);
}

TEST(GoodStart, AValidStartWithOneBadSpotIsKeptAndItsWorstHexRaised) {
  // An 8x8x8 grid with one interior node pushed along the diagonal: valid, mean near 1, a
  // few hexes around the node well below 0.5. By default no untangling round runs and the
  // shape phase raises the worst hex; asking for a min of 0.5 sends it through the rounds.
  HexMesh mesh = test::box_hexes(8, 8, 8);
  PositionOptions options;
  options.num_fixed = test::boundary_first(mesh);
  const auto v = static_cast<Eigen::Index>(options.num_fixed);
  const double cell = (mesh.points.colwise().maxCoeff() - mesh.points.colwise().minCoeff())(0) / 8;
  mesh.points.row(v) += Eigen::RowVector3d(0.3, 0.3, 0.3) * cell;
  const QualitySummary start = summarize_quality(mesh, 0);
  ASSERT_EQ(start.inverted, 0u) << "the test needs a valid start (cell " << cell << ", min "
                                << start.min_scaled_jacobian << ")";
  ASSERT_LT(start.min_scaled_jacobian, 0.5);
  ASSERT_GE(start.mean_scaled_jacobian, options.good_start_mean);
  HexMesh strict = mesh;
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_TRUE(r.good_start) << r.stop;
  EXPECT_EQ(r.iterations, 0u);
  EXPECT_TRUE(r.shape.ran);
  EXPECT_GT(r.min_scaled_jacobian_after, start.min_scaled_jacobian + 0.1);
  EXPECT_EQ(r.inverted_after, 0u);

  PositionOptions half = options;
  half.good_start = 0.5;
  const PositionReport h = position_nodes(strict, half);
  EXPECT_FALSE(h.good_start);
  EXPECT_GT(h.iterations, 0u);
}

TEST(GoodStart, ADistortedStartIsStillOptimised) {
  std::size_t num_fixed = 0;
  HexMesh mesh = scrambled_box(0.45, &num_fixed);
  const double before = summarize_quality(mesh, 0).min_scaled_jacobian;
  PositionOptions options;
  options.num_fixed = num_fixed;
  options.good_start = std::max(before + 0.01, 0.5);
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_FALSE(r.good_start);
  EXPECT_GT(r.outer_iterations, 0u);
  EXPECT_GE(r.min_scaled_jacobian_after, r.min_scaled_jacobian_untangled)
      << "the shape phase never lowers the worst hex";
  // The shape phase ran, or found every hex at its target already (nothing to run).
  EXPECT_TRUE(r.shape.ran || r.shape.stop == "target reached") << r.shape.stop;
  EXPECT_EQ(r.inverted_after, 0u);

  // Above 1, never early: the same perfect box goes through the rounds.
  HexMesh box = test::box_hexes(3, 3, 3);
  PositionOptions never;
  never.num_fixed = test::boundary_first(box);
  never.good_start = 1.5;
  const PositionReport n = position_nodes(box, never);
  EXPECT_FALSE(n.good_start);
  EXPECT_GT(n.outer_iterations, 0u);
}

// A good start with no hex below the shape target is left exactly as it was: the shape phase
// finds nothing to raise ("target reached", nothing ran) and the figures are the start's.
TEST(GoodStart, AStartAtTheShapeTargetIsLeftAsItIs) {
  HexMesh box = test::box_hexes(3, 3, 3, 1.0, 2.0, 0.5);
  PositionOptions options;
  options.num_fixed = test::boundary_first(box);
  const Points start = box.points;
  const PositionReport r = position_nodes(box, options);
  EXPECT_TRUE(r.good_start) << r.stop;
  EXPECT_FALSE(r.shape.ran);
  EXPECT_EQ(r.shape.stop, "target reached");
  EXPECT_EQ(r.shape.barrier.stop, "target reached");
  EXPECT_EQ(r.shape.moves, 0u);
  EXPECT_DOUBLE_EQ(r.shape.min_scaled_jacobian_before, 1.0);
  EXPECT_DOUBLE_EQ(r.shape.min_scaled_jacobian_after, 1.0);
  EXPECT_DOUBLE_EQ(r.min_scaled_jacobian_after, 1.0);
  EXPECT_EQ(r.corners_inverted_after, 0u);
  EXPECT_TRUE(r.untangled);
  EXPECT_EQ(box.points, start);

  // With the shape phase off it says so, whatever the quality.
  HexMesh off_box = test::box_hexes(3, 3, 3);
  PositionOptions off = options;
  off.num_fixed = test::boundary_first(off_box);
  off.max_shape_sweeps = 0;
  EXPECT_EQ(position_nodes(off_box, off).shape.stop, "off");

  // A hex below the target: the phase runs (and raises it).
  HexMesh bent = test::box_hexes(3, 3, 3);
  PositionOptions bent_options;
  bent_options.num_fixed = test::boundary_first(bent);
  bent_options.good_start = 0.0;
  bent_options.good_start_mean = 0.0;
  // One interior node pushed towards a corner of its cell: the hexes around it are sheared.
  bent.points.row(static_cast<Eigen::Index>(bent_options.num_fixed)) +=
      Eigen::RowVector3d(0.3, 0.3, 0.3);
  const double below = summarize_quality(bent, 0).min_scaled_jacobian;
  ASSERT_GT(below, 0.0);
  ASSERT_LT(below, bent_options.shape_target);
  const PositionReport b = position_nodes(bent, bent_options);
  EXPECT_TRUE(b.good_start) << b.stop;
  EXPECT_TRUE(b.shape.ran) << b.shape.stop;
  EXPECT_GT(b.min_scaled_jacobian_after, below);
}

}  // namespace
}  // namespace stcweave::primal
