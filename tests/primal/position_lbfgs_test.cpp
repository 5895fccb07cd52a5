// The untangling's preconditioned L-BFGS (primal/src/position_lbfgs.hpp) alone, on the
// quadratic 1/2 x^T L x - b^T x of a lattice's graph Laplacian L (three columns): with the
// exact inverse as preconditioner the second step is Newton's and the minimum is reached in a
// few iterations; with the multigrid V-cycle it needs far fewer iterations than LBFGS++'s plain
// L-BFGS; the parameters it does not implement are refused.
#include "../../primal/src/position_lbfgs.hpp"

#include <LBFGS.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "../../primal/src/laplacian_solve.hpp"
#include "laplacian_grid.hpp"

namespace stcweave::primal {
namespace {

/// The graph Laplacian of the interior nodes of the (k+1)^3 lattice, the boundary fixed.
FreeLaplacian lattice(int k) {
  return test_grid::grid(k).l;
}

/// f(x) = 1/2 x^T (L (x) I3) x - b^T x, variables three per node as the untangling's.
struct Quadratic {
  const FreeLaplacian& l;
  Eigen::VectorXd b;
  int evaluations = 0;

  [[nodiscard]] Eigen::VectorXd apply(const Eigen::VectorXd& x) const {
    Eigen::VectorXd y(x.size());
    for (std::size_t i = 0; i < l.degree.size(); ++i) {
      for (int c = 0; c < 3; ++c) {
        double s = l.degree[i] * x(static_cast<Eigen::Index>(3 * i) + c);
        for (std::size_t e = l.row_start[i]; e < l.row_start[i + 1]; ++e)
          s -= x(static_cast<Eigen::Index>(3 * static_cast<std::size_t>(l.neighbour[e])) + c);
        y(static_cast<Eigen::Index>(3 * i) + c) = s;
      }
    }
    return y;
  }
  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    ++evaluations;
    const Eigen::VectorXd lx = apply(x);
    grad = lx - b;
    return 0.5 * x.dot(lx) - b.dot(x);
  }
};

LBFGSpp::LBFGSParam<double> params(double epsilon = 1e-9) {
  LBFGSpp::LBFGSParam<double> p;
  p.m = 6;
  p.epsilon = epsilon;
  p.epsilon_rel = 0.0;
  p.past = 1;
  p.delta = 1e-15;
  p.max_iterations = 5000;
  p.max_linesearch = 100;
  p.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_WOLFE;
  return p;
}

Eigen::VectorXd right_hand_side(std::size_t nodes) {
  Eigen::VectorXd b(static_cast<Eigen::Index>(3 * nodes));
  for (Eigen::Index i = 0; i < b.size(); ++i) b(i) = std::sin(0.7 * static_cast<double>(i)) + 0.3;
  return b;
}

TEST(PreconditionedLbfgs, WithTheExactInverseReachesTheMinimumInAFewIterations) {
  const FreeLaplacian l = lattice(8);  // 343 nodes: one level, solved exactly
  LaplacianPreconditioner m(l);
  ASSERT_EQ(m.levels(), 1U);
  Quadratic f{l, right_hand_side(l.degree.size())};
  Eigen::VectorXd x = Eigen::VectorXd::Zero(f.b.size());
  double fx = 0.0;
  PreconditionedLbfgs solver(params(), m);
  const int iterations = solver.minimize(f, x, fx);
  // The first step is along -L^-1 g; the second, with gamma = 1 from that exact pair, is the
  // Newton step. A recursion in the wrong order, or a wrong gamma, does not get there.
  EXPECT_LE(iterations, 3) << fx;
  const Eigen::VectorXd residual = f.apply(x) - f.b;
  EXPECT_LT(residual.norm(), 1e-8 * f.b.norm());
}

TEST(PreconditionedLbfgs, WithTheVCycleNeedsFarFewerIterationsThanPlainLbfgs) {
  const FreeLaplacian l = lattice(20);  // 6,859 nodes: several levels
  LaplacianPreconditioner m(l);
  ASSERT_GT(m.levels(), 1U);
  Quadratic fp{l, right_hand_side(l.degree.size())};
  Quadratic fq{l, fp.b};
  Eigen::VectorXd xp = Eigen::VectorXd::Zero(fp.b.size());
  Eigen::VectorXd xq = xp;
  double fxp = 0.0;
  double fxq = 0.0;
  // A gradient tolerance the line search can resolve on 20,577 unknowns (|b| ~ 100); a line
  // search that fails at the rounding floor ends the run as in the untangling (best point).
  // LBFGS++'s solver keeps a reference to its parameters: they must outlive it (a temporary
  // here left it reading a dead object, which passed or failed with the stack's layout).
  const LBFGSpp::LBFGSParam<double> param = params(1e-4);
  LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchBacktracking> plain(param);
  PreconditionedLbfgs preconditioned(param, m);
  try {
    plain.minimize(fp, xp, fxp);
  } catch (const std::runtime_error&) {
  }
  try {
    preconditioned.minimize(fq, xq, fxq);
  } catch (const std::runtime_error&) {
  }
  EXPECT_LT(3 * fq.evaluations, fp.evaluations)
      << "preconditioned " << fq.evaluations << " evaluations, plain " << fp.evaluations;
  EXPECT_LT((fq.apply(xq) - fq.b).norm(), 1e-4);
  EXPECT_LT((fp.apply(xp) - fp.b).norm(), 1e-4);
  Eigen::VectorXd gq;
  Eigen::VectorXd gp;
  const double eq = fq(xq, gq);
  const double ep = fp(xp, gp);
  EXPECT_NEAR(eq, ep, 1e-9 * std::abs(ep));
}

TEST(PreconditionedLbfgs, StopsWithoutAStepOnANonFiniteGradient) {
  // The direction has no finite length: no step is tried and x is left as it was. (Without
  // the check, the line search from a step of 1 / NaN moves x to NaN; an infinite length gives
  // a step of 0, which it refuses with std::invalid_argument, not caught by the untangling.)
  const FreeLaplacian l = lattice(4);
  LaplacianPreconditioner m(l);
  const auto nan_gradient = [](const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    grad = Eigen::VectorXd::Constant(x.size(), std::numeric_limits<double>::quiet_NaN());
    return 1.0;
  };
  Eigen::VectorXd x = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(3 * l.degree.size()));
  const Eigen::VectorXd start = x;
  double fx = 0.0;
  PreconditionedLbfgs solver(params(), m);
  int iterations = -1;
  EXPECT_NO_THROW(iterations = solver.minimize(nan_gradient, x, fx));
  EXPECT_EQ(iterations, 1);
  EXPECT_TRUE(x == start);
}

TEST(PreconditionedLbfgs, RefusesTheParametersItDoesNotImplement) {
  const FreeLaplacian l = lattice(4);
  LaplacianPreconditioner m(l);
  LBFGSpp::LBFGSParam<double> p = params();
  p.past = 3;
  EXPECT_THROW(PreconditionedLbfgs(p, m), std::invalid_argument);
  p = params();
  p.epsilon_rel = 1e-6;
  EXPECT_THROW(PreconditionedLbfgs(p, m), std::invalid_argument);
}

}  // namespace
}  // namespace stcweave::primal
