// The projected Newton step of position_nodes: the corner Hessian against finite
// differences of the analytic gradient, and Newton rounds untangling as L-BFGS does.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "primal/position_helpers.hpp"
#include "stcweave/primal/position.hpp"
#include "stcweave/stc/errors.hpp"
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

namespace stcweave::primal {
namespace {

/// `mesh` with its nodes renumbered by a seeded shuffle (so that the free nodes' order and
/// the hexes' local numbering exercise the assembly's index arithmetic).
HexMesh renumbered(const HexMesh& mesh, std::vector<bool>& fixed, std::uint64_t seed) {
  const auto n = static_cast<std::size_t>(mesh.points.rows());
  std::vector<std::int32_t> to(n);
  for (std::size_t v = 0; v < n; ++v) to[v] = static_cast<std::int32_t>(v);
  std::mt19937_64 random(seed);
  for (std::size_t i = n; i > 1; --i) std::swap(to[i - 1], to[random() % i]);
  HexMesh out = mesh;
  std::vector<bool> moved(n);
  for (std::size_t v = 0; v < n; ++v) {
    out.points.row(to[v]) = mesh.points.row(static_cast<Eigen::Index>(v));
    moved[static_cast<std::size_t>(to[v])] = fixed[v];
  }
  for (stc::Hex& h : out.complex.hexes)
    for (NodeId& v : h) v = NodeId(to[v.index()]);
  fixed = moved;
  return out;
}

TEST(PositionEnergy, HessianTimesAVectorMatchesTheGradientsDifference) {
  // 17 x 17 x 16 = 4624 hexes: two assembly chunks, several threads; nodes shuffled.
  HexMesh box = test::box_hexes(17, 17, 16);
  std::vector<bool> fixed = test::boundary_nodes(box);
  test::scramble(box, fixed, 0.4, 3);
  const HexMesh mesh = renumbered(box, fixed, 11);
  const double eps = 0.05;
  const PositionEnergy at = position_energy(mesh, fixed, eps, 0.5, EnergyDerivatives::Hessian, 2);
  ASSERT_EQ(at.gradient.size(), static_cast<Eigen::Index>(3 * at.free_nodes.size()));
  ASSERT_EQ(at.hessian.rows(), at.gradient.size());
  std::mt19937_64 random(5);
  Eigen::VectorXd v(at.gradient.size());
  for (Eigen::Index k = 0; k < v.size(); ++k)
    v(k) = static_cast<double>(random() >> 11) / 9007199254740992.0 - 0.5;
  const double step = 1e-6;
  // The energy and gradient with the free coordinates moved by sign * step * v.
  const auto moved = [&](double sign) {
    HexMesh m = mesh;
    for (std::size_t i = 0; i < at.free_nodes.size(); ++i)
      for (Eigen::Index c = 0; c < 3; ++c)
        m.points(static_cast<Eigen::Index>(at.free_nodes[i].index()), c) +=
            sign * step * v(static_cast<Eigen::Index>(3 * i) + c);
    return position_energy(m, fixed, eps, 0.5, EnergyDerivatives::Gradient, 2);
  };
  const PositionEnergy plus = moved(1.0);
  const PositionEnergy minus = moved(-1.0);
  const Eigen::VectorXd numeric = (plus.gradient - minus.gradient) / (2.0 * step);
  const Eigen::VectorXd analytic = at.hessian * v;
  EXPECT_LE((analytic - numeric).norm(), 1e-5 * numeric.norm())
      << "|Kv| " << analytic.norm() << ", |dg| " << numeric.norm();

  // The energy's own central difference checks the gradient on the same mesh.
  const double slope = at.gradient.dot(v);
  EXPECT_NEAR((plus.energy - minus.energy) / (2.0 * step), slope,
              1e-4 * std::max(1.0, std::abs(slope)));
}

TEST(PositionEnergy, ProjectedHessianIsPositiveSemiDefiniteWhereTheExactOneIsNot) {
  // The tangled harmonic placement of a small bent box: the exact Hessian is indefinite.
  HexMesh mesh = test::box_hexes(4, 4, 4);
  test::bend(mesh, 4.0, 4.0, 0.8, 1.5 * M_PI);
  const std::vector<bool> fixed = test::boundary_nodes(mesh);
  PositionOptions harmonic;
  harmonic.fixed = fixed;
  harmonic.start = StartPosition::Harmonic;
  harmonic.max_outer_iterations = 1;
  harmonic.max_inner_iterations = 1;
  harmonic.max_repair_sweeps = 0;  // keep it tangled: no repair after the early stop,
  harmonic.cluster_passes = 0;     // nor local untangling
  HexMesh tangled = mesh;
  (void)position_nodes(tangled, harmonic);  // one iteration from the harmonic start
  const auto eigenvalues = [&](EnergyDerivatives d) {
    const PositionEnergy e = position_energy(tangled, fixed, 0.1, 0.5, d);
    const Eigen::MatrixXd dense = Eigen::MatrixXd(e.hessian);
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense).eigenvalues();
  };
  const Eigen::VectorXd exact = eigenvalues(EnergyDerivatives::Hessian);
  const Eigen::VectorXd projected = eigenvalues(EnergyDerivatives::ProjectedHessian);
  EXPECT_LT(exact.minCoeff(), -1e-6 * exact.maxCoeff());
  EXPECT_GE(projected.minCoeff(), -1e-10 * projected.maxCoeff());
}

TEST(Newton, ConvergesInFewStepsNearTheMinimum) {
  // A lightly scrambled box: Newton from the first L-BFGS iteration reaches the gradient
  // tolerance in a few steps (L-BFGS alone needs many more iterations).
  HexMesh mesh = test::box_hexes(5, 5, 5);
  PositionOptions options;
  options.fixed = test::boundary_nodes(mesh);
  test::scramble(mesh, options.fixed, 0.2, 9);
  options.newton_after = 1;
  options.max_outer_iterations = 1;
  options.max_newton_steps = 12;
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_GT(r.newton_steps, 0u);
  EXPECT_LT(r.newton_steps, 12u) << "Newton did not converge fast: " << r.stop;
  const PositionEnergy e = position_energy(mesh, options.fixed, r.epsilon, options.theta);
  EXPECT_LE(e.gradient.norm(), 1e-3) << r.newton_steps << " steps";
}

TEST(PositionEnergy, WrongMaskSizeIsRejected) {
  const HexMesh mesh = test::box_hexes(2, 2, 2);
  EXPECT_THROW((void)position_energy(mesh, std::vector<bool>(3, false), 0.1, 0.5), InvalidInput);
}

}  // namespace
}  // namespace stcweave::primal
