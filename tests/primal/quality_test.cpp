// Quality metrics on elements whose Verdict values are known (research/geometry.md §2.3,
// computed with Verdict 1.4.5), and the exact validity test on a hex that is positive at
// its corners but inverted inside.
#include "stcweave/primal/quality.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

/// A one-hex mesh with the given corners (VTK order).
HexMesh one_hex(const std::array<Eigen::Vector3d, 8>& p) {
  HexMesh m;
  m.points.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.points.row(i) = p[static_cast<std::size_t>(i)].transpose();
  stc::Hex h{};
  for (int i = 0; i < 8; ++i) h[static_cast<std::size_t>(i)] = NodeId(i);
  m.complex.hexes.push_back(h);
  m.complex.num_nodes = 8;
  return m;
}

std::array<Eigen::Vector3d, 8> unit_cube() {
  return {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 0),
          Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 1),
          Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(0, 1, 1)};
}

const stc::Hex& hex0(const HexMesh& m) {
  return m.complex.hexes[0];
}

TEST(Quality, UnitCubeHasPerfectMetrics) {
  const HexMesh m = one_hex(unit_cube());
  EXPECT_DOUBLE_EQ(hex_scaled_jacobian(m.points, hex0(m)), 1.0);
  EXPECT_DOUBLE_EQ(hex_corner_scaled_jacobian(m.points, hex0(m)), 1.0);
  EXPECT_DOUBLE_EQ(hex_jacobian(m.points, hex0(m)), 1.0);
  EXPECT_DOUBLE_EQ(hex_edge_ratio(m.points, hex0(m)), 1.0);
  EXPECT_NEAR(hex_max_aspect_frobenius(m.points, hex0(m)), 1.0, 1e-12);
  for (double d : hex_corner_jacobians(m.points, hex0(m))) EXPECT_DOUBLE_EQ(d, 1.0);
  EXPECT_EQ(hex_bezier_validity(m.points, hex0(m)), Validity::Valid);
}

TEST(Quality, AHexWithACoordinateThatIsNotFiniteIsTheWorstAndCountsAsInverted) {
  // A NaN scaled Jacobian passed every "<= 0" test: the local untangling once kept NaN
  // positions as an untangled try (found by fuzzing a box with one node pulled far out).
  for (const double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    auto p = unit_cube();
    p[6].y() = bad;
    const HexMesh m = one_hex(p);
    EXPECT_EQ(hex_scaled_jacobian(m.points, hex0(m)), -1.0) << bad;
    const QualitySummary s = summarize_quality(m);
    EXPECT_EQ(s.inverted, 1u) << bad;
    EXPECT_EQ(s.min_scaled_jacobian, -1.0) << bad;
  }
  // Finite but beyond the range of the products (an overflow to inf - inf = NaN).
  auto p = unit_cube();
  for (auto& v : p) v *= 1e200;
  const HexMesh huge = one_hex(p);
  const double sj = hex_scaled_jacobian(huge.points, hex0(huge));
  EXPECT_FALSE(std::isnan(sj));
}

TEST(Quality, BoxOneTwoThree) {
  auto p = unit_cube();
  for (auto& v : p) v = Eigen::Vector3d(v.x(), 2 * v.y(), 3 * v.z());
  const HexMesh m = one_hex(p);
  EXPECT_NEAR(hex_scaled_jacobian(m.points, hex0(m)), 1.0, 1e-12);
  EXPECT_NEAR(hex_jacobian(m.points, hex0(m)), 6.0, 1e-12);
  EXPECT_NEAR(hex_edge_ratio(m.points, hex0(m)), 3.0, 1e-12);
  EXPECT_NEAR(hex_max_aspect_frobenius(m.points, hex0(m)), 1.4551, 1e-4);
}

TEST(Quality, ShearedCubeMatchesVerdict) {
  auto p = unit_cube();
  for (auto& v : p) v.x() += 0.5 * v.z();
  const HexMesh m = one_hex(p);
  EXPECT_NEAR(hex_scaled_jacobian(m.points, hex0(m)), 0.8944, 1e-4);
  EXPECT_NEAR(hex_jacobian(m.points, hex0(m)), 1.0, 1e-12);
  EXPECT_NEAR(hex_max_aspect_frobenius(m.points, hex0(m)), 1.0833, 1e-4);
  EXPECT_NEAR(hex_edge_ratio(m.points, hex0(m)), std::sqrt(1.25), 1e-12);
}

TEST(Quality, TwistedTopFacesMatchVerdict) {
  const auto twisted = [](double angle) {
    auto p = unit_cube();
    const double c = std::cos(angle), s = std::sin(angle);
    for (std::size_t i = 4; i < 8; ++i) {
      const double x = p[i].x() - 0.5, y = p[i].y() - 0.5;
      p[i] = Eigen::Vector3d(0.5 + c * x - s * y, 0.5 + s * x + c * y, 1.0);
    }
    return one_hex(p);
  };
  const HexMesh m45 = twisted(M_PI / 4);
  EXPECT_NEAR(hex_scaled_jacobian(m45.points, hex0(m45)), 0.8795, 1e-4);
  EXPECT_NEAR(hex_jacobian(m45.points, hex0(m45)), 0.8536, 1e-4);
  EXPECT_NEAR(hex_max_aspect_frobenius(m45.points, hex0(m45)), 1.0976, 1e-4);
  const HexMesh m90 = twisted(M_PI / 2);
  EXPECT_NEAR(hex_scaled_jacobian(m90.points, hex0(m90)), 0.7071, 1e-4);
  EXPECT_NEAR(hex_jacobian(m90.points, hex0(m90)), 0.5, 1e-4);
  EXPECT_NEAR(hex_max_aspect_frobenius(m90.points, hex0(m90)), 1.3333, 1e-4);
}

TEST(Quality, InvertedCornerIsNegative) {
  auto p = unit_cube();
  p[6] = Eigen::Vector3d(0.3, 0.3, 0.3);
  const HexMesh m = one_hex(p);
  EXPECT_NEAR(hex_scaled_jacobian(m.points, hex0(m)), -0.9938, 1e-4);
  EXPECT_NEAR(hex_jacobian(m.points, hex0(m)), -1.1, 1e-4);
  EXPECT_EQ(hex_max_aspect_frobenius(m.points, hex0(m)), std::numeric_limits<double>::max());
  EXPECT_EQ(hex_bezier_validity(m.points, hex0(m)), Validity::Invalid);
}

TEST(Quality, MirroredCubeIsMinusOne) {
  auto p = unit_cube();
  for (auto& v : p) v.x() = -v.x();
  const HexMesh m = one_hex(p);
  EXPECT_NEAR(hex_scaled_jacobian(m.points, hex0(m)), -1.0, 1e-12);
  EXPECT_NEAR(hex_jacobian(m.points, hex0(m)), -1.0, 1e-12);
  const QualitySummary s = summarize_quality(m);
  EXPECT_EQ(s.inverted, 1u);
  EXPECT_EQ(s.negative, 1u);
  EXPECT_EQ(s.corner_inverted, 1u);
  EXPECT_EQ(s.histogram[0], 1u);
}

TEST(Quality, FlatHexIsZero) {
  auto p = unit_cube();
  p[2] = Eigen::Vector3d(0.5, 0.5, 0.0);
  p[6] = Eigen::Vector3d(0.5, 0.5, 1.0);
  const HexMesh m = one_hex(p);
  EXPECT_NEAR(hex_scaled_jacobian(m.points, hex0(m)), 0.0, 1e-12);
  EXPECT_NEAR(hex_edge_ratio(m.points, hex0(m)), std::sqrt(2.0), 1e-12);
  const QualitySummary s = summarize_quality(m);
  EXPECT_EQ(s.inverted, 1u);  // <= 0
  EXPECT_EQ(s.negative, 0u);  // not < 0
  EXPECT_EQ(s.below_0_2, 1u);
}

TEST(Quality, CentreTermCountsOnlyInTheNinePointVersion) {
  // A hex whose corners are fine but whose principal axes are degenerate cannot exist for
  // a trilinear map; instead check that the nine-point value is never above the corner one.
  auto p = unit_cube();
  p[6] = Eigen::Vector3d(1.4, 1.3, 1.2);
  const HexMesh m = one_hex(p);
  EXPECT_LE(hex_scaled_jacobian(m.points, hex0(m)), hex_corner_scaled_jacobian(m.points, hex0(m)));
}

TEST(Quality, JacobianAtCornersEqualsCornerDeterminants) {
  auto p = unit_cube();
  p[6] = Eigen::Vector3d(1.4, 1.3, 1.2);
  p[1] = Eigen::Vector3d(1.1, -0.2, 0.1);
  const HexMesh m = one_hex(p);
  const auto d = hex_corner_jacobians(m.points, hex0(m));
  const std::array<std::array<double, 3>, 8> uvw = {
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
  for (std::size_t k = 0; k < 8; ++k)
    EXPECT_NEAR(hex_jacobian_at(m.points, hex0(m), uvw[k][0], uvw[k][1], uvw[k][2]), d[k], 1e-12)
        << k;
}

TEST(Quality, BezierCoefficientsBoundTheDeterminantAndAverageToTheVolume) {
  auto p = unit_cube();
  p[6] = Eigen::Vector3d(1.4, 1.3, 1.2);
  p[1] = Eigen::Vector3d(1.1, -0.2, 0.1);
  p[4] = Eigen::Vector3d(0.2, 0.1, 0.9);
  const HexMesh m = one_hex(p);
  const auto b = hex_bezier_coefficients(p);
  const double lo = *std::min_element(b.begin(), b.end());
  const double hi = *std::max_element(b.begin(), b.end());
  double mean = 0.0;
  for (double v : b) mean += v / 27.0;
  // The volume is the integral of det J over [0,1]^3 (midpoint rule on a fine grid).
  double volume = 0.0, sampled_min = 1e300;
  const int n = 24;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double d =
            hex_jacobian_at(m.points, hex0(m), (i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n);
        volume += d / (n * n * n);
        sampled_min = std::min(sampled_min, d);
        EXPECT_LE(d, hi + 1e-12);
      }
  EXPECT_NEAR(mean, volume, 1e-3);
  EXPECT_LE(lo, sampled_min + 1e-12);
}

TEST(Quality, CornerPositiveButInvertedInsideIsCaughtByTheBezierTest) {
  // research/geometry.md §2.5: all corners positive, Verdict SJ about 0.22, det J < 0 inside.
  const std::array<Eigen::Vector3d, 8> p = {
      Eigen::Vector3d(-0.113, 0.565, -0.170), Eigen::Vector3d(0.744, -0.306, 0.309),
      Eigen::Vector3d(1.286, 0.812, -0.199),  Eigen::Vector3d(-0.301, 1.301, -0.610),
      Eigen::Vector3d(0.579, 0.611, 0.985),   Eigen::Vector3d(1.081, 0.685, 1.182),
      Eigen::Vector3d(0.973, 1.493, 1.187),   Eigen::Vector3d(-0.547, 0.830, 1.268)};
  const HexMesh m = one_hex(p);
  for (double d : hex_corner_jacobians(m.points, hex0(m))) EXPECT_GT(d, 0.0);
  EXPECT_NEAR(hex_scaled_jacobian(m.points, hex0(m)), 0.2206, 1e-3);
  const std::array<double, 27> b = hex_bezier_coefficients(p);
  EXPECT_NEAR(*std::min_element(b.begin(), b.end()), -0.43, 0.01);
  EXPECT_EQ(hex_bezier_validity(m.points, hex0(m), 6), Validity::Invalid);
  EXPECT_EQ(hex_bezier_validity(m.points, hex0(m), 0), Validity::Uncertain);
  // and indeed the determinant is negative somewhere inside
  double sampled_min = 1e300;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j)
      for (int k = 0; k <= 20; ++k)
        sampled_min =
            std::min(sampled_min, hex_jacobian_at(m.points, hex0(m), i / 20.0, j / 20.0, k / 20.0));
  EXPECT_LT(sampled_min, 0.0);
}

TEST(Quality, SummaryOfABoxCountsQuantilesAndWorst) {
  HexMesh m = test::box_hexes(3, 2, 2);
  // shear one interior-free corner node of hex 0 to lower its quality
  m.points.row(0) += Eigen::RowVector3d(0.3, 0.3, 0.0);
  const QualitySummary s = summarize_quality(m, 3);
  EXPECT_EQ(s.hexes, 12u);
  EXPECT_EQ(s.per_hex.size(), 12u);
  ASSERT_EQ(s.worst.size(), 3u);
  EXPECT_EQ(s.worst[0], HexId(0));
  EXPECT_DOUBLE_EQ(s.quantiles.front(), s.min_scaled_jacobian);
  EXPECT_DOUBLE_EQ(s.quantiles.back(), 1.0);
  EXPECT_LT(s.min_scaled_jacobian, 1.0);
  EXPECT_GT(s.min_scaled_jacobian, 0.0);
  std::size_t total = 0;
  for (std::size_t c : s.histogram) total += c;
  EXPECT_EQ(total, 12u);
  EXPECT_EQ(s.histogram[19], 11u);
  EXPECT_EQ(count_bezier_validity(m).valid, 12u);
}

}  // namespace
}  // namespace stcweave::primal
