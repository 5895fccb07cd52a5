// The shape phase's last pass (`raise_worst_by_hinges`, docs/geometry.md "Shape phase"): the
// worst hexes raised by hinges on a mean-ratio measure over small sub-meshes, a try kept only
// when the sorted scaled Jacobians of its widest sub-mesh get better.
#include <gtest/gtest.h>

#include <vector>

#include "position_helpers.hpp"
#include "stcweave/primal/position.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

/// A 5x5x5 box, boundary first and fixed, with the interior node at (2, 2, 2) pushed by
/// `shift` edge lengths along x, y and z: at 0.3 the hexes around it are skewed but valid
/// (worst scaled Jacobian 0.18), from 0.4 on some fold over.
HexMesh skewed_box(std::vector<bool>* fixed, double shift) {
  HexMesh mesh = test::box_hexes(5, 5, 5);
  const std::size_t num_fixed = test::boundary_first(mesh);
  fixed->assign(static_cast<std::size_t>(mesh.points.rows()), false);
  for (std::size_t v = 0; v < num_fixed; ++v) (*fixed)[v] = true;
  for (std::size_t v = num_fixed; v < fixed->size(); ++v) {
    const Eigen::RowVector3d p = mesh.points.row(static_cast<Eigen::Index>(v));
    if ((p - Eigen::RowVector3d(2, 2, 2)).norm() < 1e-9) {
      mesh.points(static_cast<Eigen::Index>(v), 0) += shift;
      mesh.points(static_cast<Eigen::Index>(v), 1) += shift;
      mesh.points(static_cast<Eigen::Index>(v), 2) += shift;
    }
  }
  return mesh;
}

PositionOptions below(double threshold) {
  PositionOptions o;
  o.hinge_shape_below = threshold;
  return o;
}

TEST(HingeShape, RaisesTheWorstHexWithTheBoundaryHeld) {
  std::vector<bool> fixed;
  HexMesh mesh = skewed_box(&fixed, 0.3);
  const QualitySummary before = summarize_quality(mesh, 0);
  ASSERT_EQ(before.inverted, 0U) << "the test needs a valid start";
  ASSERT_LT(before.min_scaled_jacobian, 0.3) << "the test needs a bad hex";
  const Points start = mesh.points;
  HexMesh again = mesh;
  const HingeShapeReport r = raise_worst_by_hinges(mesh, fixed, below(0.5));
  const QualitySummary after = summarize_quality(mesh, 0);
  EXPECT_TRUE(r.ran);
  EXPECT_GE(r.accepted, 1U);
  EXPECT_GE(r.tries, r.accepted);
  EXPECT_EQ(after.inverted, 0U);
  EXPECT_GT(after.min_scaled_jacobian, before.min_scaled_jacobian + 0.05);
  EXPECT_DOUBLE_EQ(r.min_scaled_jacobian_before, before.min_scaled_jacobian);
  EXPECT_DOUBLE_EQ(r.min_scaled_jacobian_after, after.min_scaled_jacobian);
  for (std::size_t v = 0; v < fixed.size(); ++v) {
    if (fixed[v]) {
      EXPECT_TRUE(mesh.points.row(static_cast<Eigen::Index>(v)) ==
                  start.row(static_cast<Eigen::Index>(v)))
          << "fixed node n" << v << " moved";
    }
  }
  // Deterministic.
  const HingeShapeReport r2 = raise_worst_by_hinges(again, fixed, below(0.5));
  EXPECT_TRUE(again.points == mesh.points);
  EXPECT_EQ(r2.tries, r.tries);
}

TEST(HingeShape, NeverLowersTheMinimumWhateverItIsAskedFor) {
  // Every hex below 0.99 is a seed: the pass works on the good hexes too, and still only
  // keeps tries that raise the sorted qualities, so the worst hex never drops.
  std::vector<bool> fixed;
  HexMesh mesh = skewed_box(&fixed, 0.25);
  const double before = summarize_quality(mesh, 0).min_scaled_jacobian;
  const HingeShapeReport r = raise_worst_by_hinges(mesh, fixed, below(0.99));
  EXPECT_TRUE(r.ran);
  EXPECT_GE(summarize_quality(mesh, 0).min_scaled_jacobian, before);
  EXPECT_EQ(summarize_quality(mesh, 0).inverted, 0U);
}

TEST(HingeShape, LeavesTangledGoodOrExcludedMeshesAlone) {
  std::vector<bool> fixed;
  HexMesh folded = skewed_box(&fixed, 0.6);
  ASSERT_GT(summarize_quality(folded, 0).inverted, 0U) << "the test needs a fold";
  Points start = folded.points;
  HingeShapeReport r = raise_worst_by_hinges(folded, fixed, below(0.5));
  EXPECT_EQ(r.stop, "inverted hexes: skipped");
  EXPECT_FALSE(r.ran);
  EXPECT_TRUE(folded.points == start);

  HexMesh box = skewed_box(&fixed, 0.0);
  start = box.points;
  r = raise_worst_by_hinges(box, fixed, below(0.5));
  EXPECT_EQ(r.stop, "nothing below");
  EXPECT_FALSE(r.ran);
  EXPECT_EQ(r.tries, 0U);
  EXPECT_TRUE(box.points == start);

  HexMesh skewed = skewed_box(&fixed, 0.3);
  start = skewed.points;
  r = raise_worst_by_hinges(skewed, fixed, below(0.0));
  EXPECT_EQ(r.stop, "off");
  EXPECT_TRUE(skewed.points == start);
  // Every node fixed: no hex can change.
  std::vector<bool> all(fixed.size(), true);
  r = raise_worst_by_hinges(skewed, all, below(0.5));
  EXPECT_EQ(r.stop, "nothing below");
  EXPECT_TRUE(skewed.points == start);
}

TEST(HingeShape, KeepsToItsWorkBound) {
  std::vector<bool> fixed;
  HexMesh mesh = skewed_box(&fixed, 0.3);
  PositionOptions o = below(0.99);  // always a hex below: only the bound stops it
  o.hinge_shape_max_work = 1;
  const HingeShapeReport r = raise_worst_by_hinges(mesh, fixed, o);
  EXPECT_EQ(r.tries, 1U);
  EXPECT_EQ(r.stop, "work bound");
}

TEST(HingeShape, RefusesBadArguments) {
  std::vector<bool> fixed;
  HexMesh mesh = skewed_box(&fixed, 0.3);
  std::vector<bool> short_mask(3, false);
  EXPECT_THROW((void)raise_worst_by_hinges(mesh, short_mask, below(0.5)), InvalidInput);
  mesh.complex.hexes.front()[0] = NodeId(static_cast<std::int32_t>(mesh.points.rows()) + 5);
  EXPECT_THROW((void)raise_worst_by_hinges(mesh, fixed, below(0.5)), InvalidInput);
}

}  // namespace
}  // namespace stcweave::primal
