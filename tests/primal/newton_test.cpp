// The projected Newton step of position_nodes: the corner Hessian against finite
// differences of the analytic gradient, and Newton rounds untangling as L-BFGS does.
#include <gtest/gtest.h>

#include <cmath>

#include "primal/position_helpers.hpp"
#include "stcweave/primal/position.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

using Vector9 = Eigen::Matrix<double, 9, 1>;
using Matrix9 = Eigen::Matrix<double, 9, 9>;

/// Central differences of the analytic gradient, column by column.
Matrix9 numeric_hessian(const Eigen::Matrix3d& edges, double eps, double theta) {
  Matrix9 out;
  const double step = 1e-6;
  for (int k = 0; k < 9; ++k) {
    Eigen::Matrix3d plus = edges;
    Eigen::Matrix3d minus = edges;
    plus(k % 3, k / 3) += step;
    minus(k % 3, k / 3) -= step;
    Vector9 gp;
    Vector9 gm;
    (void)winslow_corner_energy(plus, eps, theta, &gp);
    (void)winslow_corner_energy(minus, eps, theta, &gm);
    out.col(k) = (gp - gm) / (2.0 * step);
  }
  return out;
}

struct CornerCase {
  const char* name;
  Eigen::Matrix3d edges;
  double eps;
};

class CornerHessian : public ::testing::TestWithParam<int> {};

TEST_P(CornerHessian, MatchesFiniteDifferencesOfTheGradient) {
  Eigen::Matrix3d unit = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d sheared;
  sheared << 1.0, 0.4, -0.2, 0.1, 0.8, 0.3, -0.3, 0.2, 1.3;
  Eigen::Matrix3d flat = sheared;
  flat.col(2) = 0.5 * flat.col(0) + 0.25 * flat.col(1);  // det 0
  Eigen::Matrix3d inverted = sheared;
  inverted.col(2) = -inverted.col(2);  // det < 0
  const CornerCase cases[] = {{"unit", unit, 1e-6},
                              {"sheared", sheared, 1e-3},
                              {"flat", flat, 0.1},
                              {"inverted", inverted, 0.2},
                              {"inverted, large eps", inverted, 1.0}};
  const double theta = GetParam() == 0 ? 0.5 : 0.2;
  for (const CornerCase& c : cases) {
    Matrix9 analytic;
    (void)winslow_corner_energy(c.edges, c.eps, theta, nullptr, &analytic);
    const Matrix9 numeric = numeric_hessian(c.edges, c.eps, theta);
    const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
    EXPECT_LE((analytic - numeric).cwiseAbs().maxCoeff(), 1e-5 * scale)
        << c.name << ", theta " << theta << "\nanalytic\n"
        << analytic << "\nnumeric\n"
        << numeric;
    EXPECT_LE((analytic - analytic.transpose()).cwiseAbs().maxCoeff(), 1e-12 * scale) << c.name;
  }
}

INSTANTIATE_TEST_SUITE_P(Thetas, CornerHessian, ::testing::Values(0, 1));

TEST(CornerEnergy, GradientMatchesFiniteDifferences) {
  Eigen::Matrix3d edges;
  edges << 1.0, 0.4, -0.2, 0.1, -0.8, 0.3, -0.3, 0.2, 1.3;  // inverted
  Vector9 gradient;
  (void)winslow_corner_energy(edges, 0.3, 0.5, &gradient);
  for (int k = 0; k < 9; ++k) {
    Eigen::Matrix3d plus = edges;
    Eigen::Matrix3d minus = edges;
    plus(k % 3, k / 3) += 1e-6;
    minus(k % 3, k / 3) -= 1e-6;
    const double numeric =
        (winslow_corner_energy(plus, 0.3, 0.5) - winslow_corner_energy(minus, 0.3, 0.5)) / 2e-6;
    EXPECT_NEAR(gradient(k), numeric, 1e-6 * std::max(1.0, std::abs(numeric))) << "entry " << k;
  }
}

/// The bent box of position_test with the harmonic (tangled) start.
HexMesh bent_box(int n, PositionOptions& options) {
  HexMesh mesh = test::box_hexes(n, n, n);
  test::bend(mesh, n, n, 0.2 * n, 1.5 * M_PI);
  options.num_fixed = test::boundary_first(mesh);
  options.start = StartPosition::Harmonic;
  return mesh;
}

TEST(Newton, UntanglesTheBentBoxWhenEveryRoundSwitchesToIt) {
  PositionOptions options;
  HexMesh mesh = bent_box(6, options);
  options.newton_after = 5;  // L-BFGS is "slow" after 5 iterations: Newton does the rest
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_GT(r.inverted_before, 0u);
  EXPECT_GT(r.newton_steps, 0u);
  EXPECT_EQ(r.inverted_after, 0u) << r.stop;
  EXPECT_EQ(r.certified.valid, mesh.complex.hexes.size());
  EXPECT_TRUE(r.converged) << r.stop;

  // Against L-BFGS alone: the same minimum, so the same quality to a few digits.
  PositionOptions lbfgs;
  HexMesh other = bent_box(6, lbfgs);
  lbfgs.newton_after = 0;
  const PositionReport q = position_nodes(other, lbfgs);
  EXPECT_EQ(q.newton_steps, 0u);
  EXPECT_EQ(q.inverted_after, 0u);
  EXPECT_NEAR(r.min_scaled_jacobian_after, q.min_scaled_jacobian_after, 1e-2);
  EXPECT_LE(r.energy_after, q.energy_after * (1.0 + 1e-4));
}

TEST(Newton, IsDeterministicAndDoesNotDependOnTheThreadCount) {
  // 32 x 64 x 2 = 4096 hexes: the Hessian blocks are computed on several threads; the free
  // nodes form one plane, so the factorisations stay cheap.
  HexMesh a = test::box_hexes(32, 64, 2);
  PositionOptions options;
  options.fixed = test::boundary_nodes(a);
  test::scramble(a, options.fixed, 0.5, 7);
  HexMesh b = a;
  options.newton_after = 2;
  options.max_newton_steps = 3;
  options.max_outer_iterations = 2;
  options.threads = 1;
  const PositionReport ra = position_nodes(a, options);
  options.threads = 3;
  const PositionReport rb = position_nodes(b, options);
  EXPECT_GT(ra.newton_steps, 0u);
  EXPECT_EQ(ra.newton_steps, rb.newton_steps);
  EXPECT_TRUE(a.points == b.points);
  EXPECT_EQ(ra.energy_after, rb.energy_after);
  EXPECT_LT(ra.energy_after, ra.energy_before);
}

TEST(Newton, EachStepLowersTheEnergy) {
  // One round, only Newton after one L-BFGS iteration: the energy falls below the start's.
  PositionOptions options;
  HexMesh mesh = bent_box(4, options);
  options.newton_after = 1;
  options.max_outer_iterations = 1;
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_GT(r.newton_steps, 0u);
  EXPECT_LT(r.energy_after, r.energy_before);
}

}  // namespace
}  // namespace stcweave::primal
