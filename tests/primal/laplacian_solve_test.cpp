// The harmonic placement's solve (primal/src/laplacian_solve.hpp): the multigrid-preconditioned
// conjugate gradients give the known answer on a grid, agree with the Jacobi-preconditioned
// solve on an irregular graph, need far fewer iterations than it, repeat bit for bit, and a
// column with a zero right-hand side stays zero.
#include "../../primal/src/laplacian_solve.hpp"

#include "laplacian_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

namespace stcweave::primal {
namespace {

using test_grid::Grid;
using test_grid::grid;
using test_grid::laplacian_of;

LaplacianSolveOptions multigrid() {
  LaplacianSolveOptions o;
  o.multigrid_from = 0;
  o.coarsest = 200;
  return o;
}

LaplacianSolveOptions jacobi() {
  LaplacianSolveOptions o;
  o.multigrid_from = static_cast<std::size_t>(-1);
  return o;
}

TEST(LaplacianSolve, MultigridGivesTheLinearFieldOnAGrid) {
  const Grid g = grid(24);  // 12,167 unknowns
  std::vector<Row3> x(g.b.size(), Row3{0.0, 0.0, 0.0});
  const SolveOutcome out = solve_laplacian(g.l, g.b, x, 1e-12, 10000, multigrid());
  EXPECT_GT(out.levels, 2U);
  for (std::size_t c = 0; c < 3; ++c) EXPECT_TRUE(out.converged[c]) << c;
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t c = 0; c < 3; ++c) worst = std::max(worst, std::abs(x[i][c] - g.exact[i][c]));
  EXPECT_LT(worst, 1e-8);
}

TEST(LaplacianSolve, MultigridNeedsFarFewerIterationsThanJacobi) {
  const Grid g = grid(32);
  std::vector<Row3> xm(g.b.size(), Row3{0.0, 0.0, 0.0});
  std::vector<Row3> xj = xm;
  const SolveOutcome m = solve_laplacian(g.l, g.b, xm, 1e-10, 10000, multigrid());
  const SolveOutcome j = solve_laplacian(g.l, g.b, xj, 1e-10, 10000, jacobi());
  EXPECT_EQ(j.levels, 1U);
  const std::size_t mi = *std::max_element(m.iterations.begin(), m.iterations.end());
  const std::size_t ji = *std::max_element(j.iterations.begin(), j.iterations.end());
  EXPECT_LT(3 * mi, ji) << "multigrid " << mi << " iterations, Jacobi " << ji;
}

TEST(LaplacianSolve, MultigridAgreesWithJacobiOnAnIrregularGraphAndRepeats) {
  // A grid with extra diagonal edges in a pattern that breaks its regularity, and one node
  // tied to fixed nodes only; a zero right-hand side in the third column.
  Grid g = grid(20);
  std::set<std::pair<std::int32_t, std::int32_t>> edges;
  std::vector<int> ties(g.b.size(), 0);
  for (std::size_t i = 0; i < g.b.size(); ++i) {
    double fixed_part = g.l.degree[i];
    for (std::size_t e = g.l.row_start[i]; e < g.l.row_start[i + 1]; ++e) {
      const auto j = g.l.neighbour[e];
      if (static_cast<std::int32_t>(i) < j) edges.emplace(static_cast<std::int32_t>(i), j);
      fixed_part -= 1.0;
    }
    ties[i] = static_cast<int>(fixed_part);
    const auto far = static_cast<std::int32_t>((i * 7919 + 13) % g.b.size());
    if (i % 5 == 0 && far != static_cast<std::int32_t>(i))
      edges.emplace(std::min<std::int32_t>(static_cast<std::int32_t>(i), far),
                    std::max<std::int32_t>(static_cast<std::int32_t>(i), far));
    g.b[i][2] = 0.0;
  }
  const FreeLaplacian l = laplacian_of(g.b.size(), edges, ties);
  std::vector<Row3> xm(g.b.size(), Row3{1.0, 1.0, 1.0});
  std::vector<Row3> xj = xm;
  std::vector<Row3> again = xm;
  const SolveOutcome m = solve_laplacian(l, g.b, xm, 1e-11, 10000, multigrid());
  const SolveOutcome j = solve_laplacian(l, g.b, xj, 1e-11, 10000, jacobi());
  (void)solve_laplacian(l, g.b, again, 1e-11, 10000, multigrid());
  ASSERT_TRUE(m.converged[0] && m.converged[1] && m.converged[2]);
  ASSERT_TRUE(j.converged[0] && j.converged[1] && j.converged[2]);
  double scale = 0.0;
  double worst = 0.0;
  for (std::size_t i = 0; i < xm.size(); ++i) {
    for (std::size_t c = 0; c < 3; ++c) {
      scale = std::max(scale, std::abs(xj[i][c]));
      worst = std::max(worst, std::abs(xm[i][c] - xj[i][c]));
      EXPECT_EQ(xm[i][c], again[i][c]) << "node " << i << " column " << c;
    }
    EXPECT_EQ(xm[i][2], 0.0) << "node " << i;
  }
  EXPECT_LT(worst, 1e-7 * scale);
}

TEST(LaplacianSolve, AFloatingGroupOfFreeNodesFallsBackToJacobiInsteadOfFailing) {
  // A grid plus a 3 x 3 x 3 block of free nodes tied to no fixed node: L is singular on the
  // block (its coarse levels too), which a Cholesky factor cannot take. The solve must still
  // converge, leave the block where it started (zero right-hand side there) and solve the
  // grid; before the fallback it threw.
  const Grid g = grid(16);
  const std::size_t base = g.b.size();
  std::set<std::pair<std::int32_t, std::int32_t>> edges;
  std::vector<int> ties(base + 27, 0);
  for (std::size_t i = 0; i < base; ++i) {
    double fixed_part = g.l.degree[i];
    for (std::size_t e = g.l.row_start[i]; e < g.l.row_start[i + 1]; ++e) {
      if (static_cast<std::int32_t>(i) < g.l.neighbour[e])
        edges.emplace(static_cast<std::int32_t>(i), g.l.neighbour[e]);
      fixed_part -= 1.0;
    }
    ties[i] = static_cast<int>(fixed_part);
  }
  const auto block = [base](int i, int j, int k) {
    return static_cast<std::int32_t>(base) + i + 3 * (j + 3 * k);
  };
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        if (i < 2) edges.emplace(block(i, j, k), block(i + 1, j, k));
        if (j < 2) edges.emplace(block(i, j, k), block(i, j + 1, k));
        if (k < 2) edges.emplace(block(i, j, k), block(i, j, k + 1));
      }
    }
  }
  const FreeLaplacian l = laplacian_of(base + 27, edges, ties);
  std::vector<Row3> b = g.b;
  b.resize(base + 27, Row3{0.0, 0.0, 0.0});
  std::vector<Row3> x(base + 27, Row3{0.5, 0.5, 0.5});
  LaplacianSolveOptions o = multigrid();
  o.coarsest = 40;
  SolveOutcome out;
  ASSERT_NO_THROW(out = solve_laplacian(l, b, x, 1e-10, 10000, o));
  EXPECT_EQ(out.levels, 1U);  // Jacobi
  for (std::size_t c = 0; c < 3; ++c) EXPECT_TRUE(out.converged[c]) << c;
  for (std::size_t i = base; i < base + 27; ++i)
    for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(x[i][c], 0.5) << "block node " << i;
  double worst = 0.0;
  for (std::size_t i = 0; i < base; ++i)
    for (std::size_t c = 0; c < 3; ++c) worst = std::max(worst, std::abs(x[i][c] - g.exact[i][c]));
  EXPECT_LT(worst, 1e-6);
}

/// y = L x for the Laplacian `l` (one row per free node).
std::vector<Row3> apply_laplacian(const FreeLaplacian& l, const std::vector<Row3>& x) {
  std::vector<Row3> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    for (std::size_t c = 0; c < 3; ++c) y[i][c] = l.degree[i] * x[i][c];
    for (std::size_t e = l.row_start[i]; e < l.row_start[i + 1]; ++e)
      for (std::size_t c = 0; c < 3; ++c) y[i][c] -= x[static_cast<std::size_t>(l.neighbour[e])][c];
  }
  return y;
}

double dot(const std::vector<Row3>& a, const std::vector<Row3>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t c = 0; c < 3; ++c) s += a[i][c] * b[i][c];
  return s;
}

/// A deterministic vector with varied entries.
std::vector<Row3> wave(std::size_t n, double phase) {
  std::vector<Row3> v(n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < 3; ++c)
      v[i][c] = std::sin(0.37 * static_cast<double>(i) + phase + static_cast<double>(c));
  return v;
}

TEST(LaplacianPreconditioner, IsTheExactInverseOnASmallSystem) {
  // 7^3 = 343 unknowns, below `coarsest`: one level, factored, so M^-1 L x = x.
  const Grid g = grid(8);
  LaplacianPreconditioner m(g.l);
  EXPECT_EQ(m.levels(), 1U);
  const std::vector<Row3> x = wave(g.l.degree.size(), 0.0);
  std::vector<Row3> z;
  m.apply(apply_laplacian(g.l, x), z);
  ASSERT_EQ(z.size(), x.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t c = 0; c < 3; ++c) worst = std::max(worst, std::abs(z[i][c] - x[i][c]));
  EXPECT_LT(worst, 1e-9);
}

TEST(LaplacianPreconditioner, IsSymmetricPositiveDefiniteOnALargeGrid) {
  // 23^3 unknowns: several levels. L-BFGS needs a symmetric positive definite H0.
  const Grid g = grid(24);
  LaplacianPreconditioner m(g.l);
  EXPECT_GT(m.levels(), 2U);
  const std::size_t n = g.l.degree.size();
  const std::vector<Row3> u = wave(n, 0.3);
  const std::vector<Row3> v = wave(n, 1.1);
  std::vector<Row3> mu;
  std::vector<Row3> mv;
  m.apply(u, mu);
  m.apply(v, mv);
  EXPECT_NEAR(dot(u, mv), dot(v, mu), 1e-10 * std::abs(dot(u, mu)));
  EXPECT_GT(dot(u, mu), 0.0);
  EXPECT_GT(dot(v, mv), 0.0);
  // The highest frequency too (alternating signs), where the smoother does the work.
  std::vector<Row3> w(n);
  for (std::size_t i = 0; i < n; ++i) w[i] = Row3{i % 2 ? 1.0 : -1.0, i % 3 ? 0.5 : -2.0, 1.0};
  std::vector<Row3> mw;
  m.apply(w, mw);
  EXPECT_GT(dot(w, mw), 0.0);
  EXPECT_NEAR(dot(w, mu), dot(u, mw), 1e-10 * std::abs(dot(w, mw)));
}

}  // namespace
}  // namespace stcweave::primal
