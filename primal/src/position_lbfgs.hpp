#pragma once
/// \file
/// L-BFGS with the graph Laplacian of the hex edges as its initial inverse Hessian
/// (docs/geometry.md, "Preconditioned L-BFGS"): the two-loop recursion with H0 = gamma M^-1,
/// M^-1 one V-cycle of the aggregation multigrid of laplacian_solve.hpp and gamma =
/// s.y / y.(M^-1 y) of the newest correction. The loop, its stopping rules and its line
/// search are those of LBFGS++'s LBFGSSolver for the parameters the untangling uses (`past`
/// 0 or 1, `epsilon_rel` 0; others are refused), so that only the direction differs from the
/// unpreconditioned solver. One difference: after a step that falls back to the gradient (or
/// skips every correction pair), the trial step is 1 / |d| as at the first iteration, not 1.

#include <LBFGS.h>  // LBFGSpp's parameters and line search, in the order they need

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <deque>
#include <stdexcept>
#include <vector>

#include "laplacian_solve.hpp"

namespace stcweave::primal {

class PreconditionedLbfgs {
 public:
  PreconditionedLbfgs(const LBFGSpp::LBFGSParam<double>& param, LaplacianPreconditioner& m)
      : param_(param), m_(m) {
    param_.check_param();
    if (param_.past > 1 || param_.epsilon_rel != 0.0)
      throw std::invalid_argument("PreconditionedLbfgs: only past <= 1 and epsilon_rel = 0");
  }

  /// Minimises f from x; returns the iterations used. `f(x, grad)` returns the energy and
  /// writes the gradient. Throws std::runtime_error when the line search fails (as LBFGS++);
  /// `iterations()` then says how many iterations had begun, the failed one included.
  template <typename F>
  int minimize(F& f, Eigen::VectorXd& x, double& fx) {
    history_.clear();
    iterations_ = 0;
    Eigen::VectorXd grad(x.size());
    fx = f(x, grad);
    double previous = fx;
    if (grad.norm() <= param_.epsilon) return 1;
    Eigen::VectorXd drt = direction(grad);
    // A direction of no finite length (a non-finite gradient) gives no step to try.
    double length = drt.norm();
    if (!(std::isfinite(length) && length > 0.0)) return 1;
    double step = 1.0 / length;
    Eigen::VectorXd xp(x.size());
    Eigen::VectorXd gradp(x.size());
    for (int k = 1;; ++k) {
      iterations_ = k;
      xp = x;
      gradp = grad;
      LBFGSpp::LineSearchBacktracking<double>::LineSearch(f, fx, x, grad, step, drt, xp, param_);
      if (grad.norm() <= param_.epsilon) return k;
      if (param_.past > 0 && std::abs(previous - fx) <=
                                 param_.delta * std::max({std::abs(fx), std::abs(previous), 1.0})) {
        return k;
      }
      previous = fx;
      if (param_.max_iterations != 0 && k >= param_.max_iterations) return k;
      add_correction(x - xp, grad - gradp);
      drt = direction(grad);
      length = drt.norm();
      if (!(std::isfinite(length) && length > 0.0)) return k;
      step = history_.empty() ? 1.0 / length : 1.0;
    }
  }

  /// The iterations the last `minimize` began (also when its line search failed).
  [[nodiscard]] int iterations() const { return iterations_; }

 private:
  struct Pair {
    Eigen::VectorXd s, y;
    double rho;  ///< 1 / s.y
  };
  int iterations_ = 0;

  /// z = M^-1 v, through the preconditioner's one-row-per-node layout.
  void precondition(const Eigen::VectorXd& v, Eigen::VectorXd& z) {
    const std::size_t n = m_.size();
    rows_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) rows_[i][c] = v(static_cast<Eigen::Index>(3 * i + c));
    m_.apply(rows_, out_);
    z.resize(v.size());
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) z(static_cast<Eigen::Index>(3 * i + c)) = out_[i][c];
  }

  void add_correction(const Eigen::VectorXd& s, const Eigen::VectorXd& y) {
    const double sy = s.dot(y);
    // The Wolfe condition makes s.y > 0; a pair without positive curvature is skipped.
    if (!(sy > 1e-16 * s.norm() * y.norm())) return;
    if (history_.size() == static_cast<std::size_t>(param_.m)) history_.pop_front();
    history_.push_back(Pair{s, y, 1.0 / sy});
    Eigen::VectorXd my;
    precondition(y, my);
    const double ymy = y.dot(my);
    gamma_ = ymy > 0.0 ? sy / ymy : 1.0;
  }

  /// -H g by the two-loop recursion; -M^-1 g before any correction; -g when rounding makes
  /// the result point uphill.
  Eigen::VectorXd direction(const Eigen::VectorXd& g) {
    Eigen::VectorXd q = g;
    std::vector<double> alpha(history_.size());
    for (std::size_t i = history_.size(); i-- > 0;) {
      alpha[i] = history_[i].rho * history_[i].s.dot(q);
      q -= alpha[i] * history_[i].y;
    }
    Eigen::VectorXd r;
    precondition(q, r);
    if (!history_.empty()) r *= gamma_;
    for (std::size_t i = 0; i < history_.size(); ++i) {
      const double beta = history_[i].rho * history_[i].y.dot(r);
      r += (alpha[i] - beta) * history_[i].s;
    }
    if (!(g.dot(r) > 0.0)) {
      history_.clear();
      return -g;
    }
    return -r;
  }

  LBFGSpp::LBFGSParam<double> param_;
  LaplacianPreconditioner& m_;
  std::deque<Pair> history_;
  double gamma_ = 1.0;
  std::vector<Row3> rows_, out_;
};

}  // namespace stcweave::primal
