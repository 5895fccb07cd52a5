/// Conjugate gradients on the free-node graph Laplacian, preconditioned by Jacobi (small
/// systems) or by one V-cycle of a plain-aggregation multigrid.
///
/// The hierarchy: a level's nodes are grouped into aggregates (a node and its neighbours not
/// yet taken, in index order; a node left over joins the neighbouring aggregate it is most
/// strongly tied to); each aggregate is one node of the next level, whose matrix is P^T A P for
/// the 0/1 matrix P of the grouping. Levels are built until one has at most `coarsest` nodes,
/// which is solved by a dense Cholesky factorisation. The cycle: a forward Gauss-Seidel sweep,
/// the coarse correction of the residual (scaled by `coarse_scale`: a piecewise constant
/// prolongation under-corrects), a backward sweep. Forward then backward sweeps make the
/// cycle a symmetric positive definite operator, as conjugate gradients needs.

#include "laplacian_solve.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace stcweave::primal {

namespace {

/// A symmetric level matrix: its diagonal, and its off-diagonal entries as CSR rows
/// (`value` empty: every off-diagonal entry is -1, as on the finest level).
struct LevelMatrix {
  std::vector<double> diag;
  std::vector<std::size_t> row_start;
  std::vector<std::int32_t> col;
  std::vector<double> value;
  [[nodiscard]] std::size_t size() const { return diag.size(); }
  [[nodiscard]] double at(std::size_t e) const { return value.empty() ? -1.0 : value[e]; }
};

/// y = A x for three columns; returns the column-wise dot products x . y.
Row3 multiply(const LevelMatrix& a, const std::vector<Row3>& x, std::vector<Row3>& y) {
  const std::size_t n = a.size();
  Row3 xy{0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    Row3 sum{0.0, 0.0, 0.0};
    if (a.value.empty()) {
      for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1]; ++e) {
        const Row3& xj = x[static_cast<std::size_t>(a.col[e])];
        sum[0] += xj[0];
        sum[1] += xj[1];
        sum[2] += xj[2];
      }
    } else {
      for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1]; ++e) {
        const Row3& xj = x[static_cast<std::size_t>(a.col[e])];
        const double v = -a.value[e];
        sum[0] += v * xj[0];
        sum[1] += v * xj[1];
        sum[2] += v * xj[2];
      }
    }
    const double d = a.diag[i];
    const Row3& xi = x[i];
    Row3& yi = y[i];
    for (std::size_t c = 0; c < 3; ++c) {
      yi[c] = d * xi[c] - sum[c];
      xy[c] += xi[c] * yi[c];
    }
  }
  return xy;
}

/// One Gauss-Seidel step at row i of A z = r.
inline void relax_row(const LevelMatrix& a, std::size_t i, const std::vector<Row3>& r,
                      std::vector<Row3>& z) {
  Row3 s = r[i];
  for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1]; ++e) {
    const Row3& zj = z[static_cast<std::size_t>(a.col[e])];
    const double v = a.at(e);
    s[0] -= v * zj[0];
    s[1] -= v * zj[1];
    s[2] -= v * zj[2];
  }
  const double inv = 1.0 / a.diag[i];
  z[i] = {s[0] * inv, s[1] * inv, s[2] * inv};
}

/// The aggregates of `a`'s nodes (per node, its aggregate) and their count.
std::pair<std::vector<std::int32_t>, std::size_t> aggregate(const LevelMatrix& a) {
  const std::size_t n = a.size();
  std::vector<std::int32_t> agg(n, -1);
  std::int32_t count = 0;
  // A node whose neighbours are all free starts an aggregate with them.
  for (std::size_t i = 0; i < n; ++i) {
    if (agg[i] >= 0) continue;
    bool free = true;
    for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1] && free; ++e)
      free = agg[static_cast<std::size_t>(a.col[e])] < 0;
    if (!free) continue;
    agg[i] = count;
    for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1]; ++e)
      agg[static_cast<std::size_t>(a.col[e])] = count;
    ++count;
  }
  // A node left over joins the aggregate it is most strongly tied to (first one on ties).
  std::vector<std::int32_t> joined(agg);
  for (std::size_t i = 0; i < n; ++i) {
    if (agg[i] >= 0) continue;
    double best = 0.0;
    for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1]; ++e) {
      const std::int32_t g = agg[static_cast<std::size_t>(a.col[e])];
      const double tie = -a.at(e);
      if (g >= 0 && tie > best) {
        best = tie;
        joined[i] = g;
      }
    }
  }
  // A node with no aggregated neighbour (only fixed ones) is an aggregate of its own.
  for (std::size_t i = 0; i < n; ++i)
    if (joined[i] < 0) joined[i] = count++;
  return {std::move(joined), static_cast<std::size_t>(count)};
}

/// P^T A P for the grouping `agg` into `count` aggregates (rows' columns ascending).
LevelMatrix coarsen(const LevelMatrix& a, const std::vector<std::int32_t>& agg, std::size_t count) {
  const std::size_t n = a.size();
  // The members of each aggregate, by a counting sort.
  std::vector<std::size_t> member_start(count + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++member_start[static_cast<std::size_t>(agg[i]) + 1];
  for (std::size_t g = 0; g < count; ++g) member_start[g + 1] += member_start[g];
  std::vector<std::int32_t> members(n);
  {
    std::vector<std::size_t> fill(member_start.begin(), member_start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      members[fill[static_cast<std::size_t>(agg[i])]++] = static_cast<std::int32_t>(i);
  }
  LevelMatrix c;
  c.diag.assign(count, 0.0);
  c.row_start.assign(count + 1, 0);
  std::vector<std::int32_t> seen(count, -1);
  std::vector<std::size_t> slot(count, 0);
  std::vector<std::pair<std::int32_t, double>> row;
  for (std::size_t g = 0; g < count; ++g) {
    row.clear();
    for (std::size_t m = member_start[g]; m < member_start[g + 1]; ++m) {
      const auto i = static_cast<std::size_t>(members[m]);
      c.diag[g] += a.diag[i];
      for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1]; ++e) {
        const std::int32_t h = agg[static_cast<std::size_t>(a.col[e])];
        const double v = a.at(e);
        if (static_cast<std::size_t>(h) == g) {
          c.diag[g] += v;
        } else if (seen[static_cast<std::size_t>(h)] != static_cast<std::int32_t>(g)) {
          seen[static_cast<std::size_t>(h)] = static_cast<std::int32_t>(g);
          slot[static_cast<std::size_t>(h)] = row.size();
          row.emplace_back(h, v);
        } else {
          row[slot[static_cast<std::size_t>(h)]].second += v;
        }
      }
    }
    std::sort(row.begin(), row.end());
    for (const auto& [h, v] : row) {
      c.col.push_back(h);
      c.value.push_back(v);
    }
    c.row_start[g + 1] = c.col.size();
  }
  return c;
}

/// The dense Cholesky factor (lower, row-major) of a small level matrix; empty when a pivot is
/// not clearly positive (a group of free nodes with no fixed neighbour makes the matrix
/// singular: the caller then preconditions by Jacobi, which converges there all the same).
std::vector<double> dense_cholesky(const LevelMatrix& a) {
  const std::size_t n = a.size();
  std::vector<double> l(n * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    l[i * n + i] = a.diag[i];
    for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1]; ++e)
      l[i * n + static_cast<std::size_t>(a.col[e])] = a.at(e);
  }
  for (std::size_t j = 0; j < n; ++j) {
    double d = l[j * n + j];
    for (std::size_t k = 0; k < j; ++k) d -= l[j * n + k] * l[j * n + k];
    if (!(d > 1e-12 * a.diag[j])) return {};
    const double ljj = std::sqrt(d);
    l[j * n + j] = ljj;
    for (std::size_t i = j + 1; i < n; ++i) {
      double s = l[i * n + j];
      for (std::size_t k = 0; k < j; ++k) s -= l[i * n + k] * l[j * n + k];
      l[i * n + j] = s / ljj;
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) l[i * n + j] = 0.0;
  return l;
}

/// The V-cycle preconditioner.
class Multigrid {
 public:
  Multigrid(LevelMatrix fine, const LaplacianSolveOptions& options) : scale_(options.coarse_scale) {
    levels_.push_back(Level{std::move(fine), {}, {}, {}, {}});
    while (levels_.back().a.size() > options.coarsest) {
      Level& top = levels_.back();
      auto [agg, count] = aggregate(top.a);
      if (count * 10 > top.a.size() * 9) break;  // no real coarsening left
      LevelMatrix next = coarsen(top.a, agg, count);
      top.aggregate = std::move(agg);
      levels_.push_back(Level{std::move(next), {}, {}, {}, {}});
    }
    if (levels_.back().a.size() <= options.coarsest && levels_.back().a.size() > 0)
      coarsest_factor_ = dense_cholesky(levels_.back().a);
    for (Level& level : levels_) {
      const std::size_t n = level.a.size();
      level.r.assign(n, Row3{});
      level.z.assign(n, Row3{});
      level.residual.assign(n, Row3{});
    }
  }

  /// Whether the hierarchy ends in a level small enough to factor, and factored (else: use
  /// Jacobi).
  [[nodiscard]] bool usable() const { return !coarsest_factor_.empty(); }
  [[nodiscard]] std::size_t levels() const { return levels_.size(); }

  /// z = M^-1 r.
  void apply(const std::vector<Row3>& r, std::vector<Row3>& z) {
    levels_[0].r = r;
    cycle(0);
    z = levels_[0].z;
  }

 private:
  struct Level {
    LevelMatrix a;
    std::vector<std::int32_t> aggregate;  ///< per node, its node on the next level
    std::vector<Row3> r, z, residual;
  };

  void cycle(std::size_t k) {
    Level& level = levels_[k];
    const std::size_t n = level.a.size();
    if (k + 1 == levels_.size()) {
      solve_coarsest(level);
      return;
    }
    std::fill(level.z.begin(), level.z.end(), Row3{0.0, 0.0, 0.0});
    for (std::size_t i = 0; i < n; ++i) relax_row(level.a, i, level.r, level.z);
    multiply(level.a, level.z, level.residual);
    Level& next = levels_[k + 1];
    std::fill(next.r.begin(), next.r.end(), Row3{0.0, 0.0, 0.0});
    for (std::size_t i = 0; i < n; ++i) {
      Row3& rc = next.r[static_cast<std::size_t>(level.aggregate[i])];
      for (std::size_t c = 0; c < 3; ++c) rc[c] += level.r[i][c] - level.residual[i][c];
    }
    cycle(k + 1);
    for (std::size_t i = 0; i < n; ++i) {
      const Row3& zc = next.z[static_cast<std::size_t>(level.aggregate[i])];
      for (std::size_t c = 0; c < 3; ++c) level.z[i][c] += scale_ * zc[c];
    }
    for (std::size_t i = n; i-- > 0;) relax_row(level.a, i, level.r, level.z);
  }

  void solve_coarsest(Level& level) const {
    const std::size_t n = level.a.size();
    const std::vector<double>& l = coarsest_factor_;
    for (std::size_t i = 0; i < n; ++i) {  // L y = r
      Row3 s = level.r[i];
      for (std::size_t k = 0; k < i; ++k)
        for (std::size_t c = 0; c < 3; ++c) s[c] -= l[i * n + k] * level.z[k][c];
      for (std::size_t c = 0; c < 3; ++c) level.z[i][c] = s[c] / l[i * n + i];
    }
    for (std::size_t i = n; i-- > 0;) {  // L^T z = y
      Row3 s = level.z[i];
      for (std::size_t k = i + 1; k < n; ++k)
        for (std::size_t c = 0; c < 3; ++c) s[c] -= l[k * n + i] * level.z[k][c];
      for (std::size_t c = 0; c < 3; ++c) level.z[i][c] = s[c] / l[i * n + i];
    }
  }

  double scale_;
  std::vector<Level> levels_;
  std::vector<double> coarsest_factor_;
};

}  // namespace

SolveOutcome solve_laplacian(const FreeLaplacian& l, const std::vector<Row3>& b,
                             std::vector<Row3>& x, double tolerance, std::size_t max_iterations,
                             const LaplacianSolveOptions& options) {
  const std::size_t n = l.degree.size();
  SolveOutcome out;
  LevelMatrix a;
  a.diag = l.degree;
  a.row_start = l.row_start;
  a.col = l.neighbour;
  std::optional<Multigrid> mg;
  if (n >= options.multigrid_from) {
    mg.emplace(a, options);
    if (!mg->usable()) mg.reset();
  }
  out.levels = mg ? mg->levels() : 1;
  std::vector<double> inv_degree(n);
  for (std::size_t i = 0; i < n; ++i) inv_degree[i] = 1.0 / l.degree[i];
  // z = M^-1 r and the column-wise r . z. (Jacobi after the first step sums r r / degree, in
  // that order: the rounding of the Jacobi solve this one replaced, kept bit for bit.)
  std::vector<Row3> z(n);
  const auto precondition = [&](const std::vector<Row3>& r, bool first) {
    Row3 rz{0.0, 0.0, 0.0};
    if (mg) {
      mg->apply(r, z);
    } else {
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < 3; ++c) z[i][c] = r[i][c] * inv_degree[i];
      if (!first) {
        for (std::size_t i = 0; i < n; ++i)
          for (std::size_t c = 0; c < 3; ++c) rz[c] += r[i][c] * r[i][c] * inv_degree[i];
        return rz;
      }
    }
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) rz[c] += r[i][c] * z[i][c];
    return rz;
  };
  std::vector<Row3> r(n);
  std::vector<Row3> q(n);
  multiply(a, x, q);
  Row3 b_norm2{0.0, 0.0, 0.0};
  Row3 r_norm2{0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t c = 0; c < 3; ++c) {
      r[i][c] = b[i][c] - q[i][c];
      b_norm2[c] += b[i][c] * b[i][c];
      r_norm2[c] += r[i][c] * r[i][c];
    }
  }
  Row3 rz = precondition(r, true);
  std::vector<Row3> p = z;
  Row3 threshold{};
  std::array<bool, 3> active{};
  for (std::size_t c = 0; c < 3; ++c) {
    if (b_norm2[c] == 0.0) {
      // A zero right-hand side has the zero solution.
      for (std::size_t i = 0; i < n; ++i) x[i][c] = 0.0;
      r_norm2[c] = 0.0;
      out.converged[c] = true;
      continue;
    }
    threshold[c] = std::max(tolerance * tolerance * b_norm2[c], std::numeric_limits<double>::min());
    out.converged[c] = r_norm2[c] < threshold[c];
    active[c] = !out.converged[c];
  }
  std::size_t it = 0;
  while ((active[0] || active[1] || active[2]) && it < max_iterations) {
    const Row3 pq = multiply(a, p, q);
    Row3 alpha{0.0, 0.0, 0.0};
    for (std::size_t c = 0; c < 3; ++c) alpha[c] = active[c] ? rz[c] / pq[c] : 0.0;
    Row3 rr{0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t c = 0; c < 3; ++c) {
        x[i][c] += alpha[c] * p[i][c];
        r[i][c] -= alpha[c] * q[i][c];
        rr[c] += r[i][c] * r[i][c];
      }
    }
    ++it;
    const Row3 rz_new = precondition(r, false);
    // p = z + beta p for the columns still running; (0, 1) keeps a stopped column's p.
    Row3 z_weight{0.0, 0.0, 0.0};
    Row3 beta{1.0, 1.0, 1.0};
    for (std::size_t c = 0; c < 3; ++c) {
      if (!active[c]) continue;
      r_norm2[c] = rr[c];
      out.iterations[c] = it;
      if (rr[c] < threshold[c]) {
        active[c] = false;
        out.converged[c] = true;
        continue;
      }
      z_weight[c] = 1.0;
      beta[c] = rz_new[c] / rz[c];
      rz[c] = rz_new[c];
    }
    if (mg) {
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < 3; ++c) p[i][c] = z_weight[c] * z[i][c] + beta[c] * p[i][c];
    } else {  // the Jacobi solve's own expression (the same rounding with contracted FMAs)
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t c = 0; c < 3; ++c)
          p[i][c] = z_weight[c] * r[i][c] * inv_degree[i] + beta[c] * p[i][c];
      }
    }
  }
  for (std::size_t c = 0; c < 3; ++c) {
    out.relative_residual[c] = b_norm2[c] == 0.0 ? 0.0 : std::sqrt(r_norm2[c] / b_norm2[c]);
  }
  return out;
}

FreeLaplacian edge_laplacian(const std::vector<std::pair<std::int32_t, std::int32_t>>& edges,
                             const std::vector<std::int32_t>& slot, std::size_t free) {
  FreeLaplacian l;
  l.degree.assign(free, 0.0);
  l.row_start.assign(free + 1, 0);
  const auto row = [&](std::int32_t node) { return slot[static_cast<std::size_t>(node)]; };
  for (const auto& [a, b] : edges) {
    const std::int32_t ra = row(a);
    const std::int32_t rb = row(b);
    if (ra >= 0) l.degree[static_cast<std::size_t>(ra)] += 1.0;
    if (rb >= 0) l.degree[static_cast<std::size_t>(rb)] += 1.0;
    if (ra >= 0 && rb >= 0) {
      ++l.row_start[static_cast<std::size_t>(ra) + 1];
      ++l.row_start[static_cast<std::size_t>(rb) + 1];
    }
  }
  for (std::size_t i = 0; i < free; ++i) l.row_start[i + 1] += l.row_start[i];
  l.neighbour.resize(l.row_start[free]);
  std::vector<std::size_t> fill(l.row_start.begin(), l.row_start.end() - 1);
  for (const auto& [a, b] : edges) {
    const std::int32_t ra = row(a);
    const std::int32_t rb = row(b);
    if (ra < 0 || rb < 0) continue;
    l.neighbour[fill[static_cast<std::size_t>(ra)]++] = rb;
    l.neighbour[fill[static_cast<std::size_t>(rb)]++] = ra;
  }
  return l;
}

struct LaplacianPreconditioner::Impl {
  std::optional<Multigrid> mg;
  std::vector<double> inv_degree;
};

LaplacianPreconditioner::LaplacianPreconditioner(const FreeLaplacian& l,
                                                 const LaplacianSolveOptions& options)
    : impl_(std::make_unique<Impl>()) {
  const std::size_t n = l.degree.size();
  impl_->inv_degree.resize(n);
  for (std::size_t i = 0; i < n; ++i) impl_->inv_degree[i] = 1.0 / l.degree[i];
  if (n == 0) return;
  LevelMatrix a;
  a.diag = l.degree;
  a.row_start = l.row_start;
  a.col = l.neighbour;
  impl_->mg.emplace(std::move(a), options);
  if (!impl_->mg->usable()) impl_->mg.reset();
}

LaplacianPreconditioner::~LaplacianPreconditioner() = default;
LaplacianPreconditioner::LaplacianPreconditioner(LaplacianPreconditioner&&) noexcept = default;
LaplacianPreconditioner& LaplacianPreconditioner::operator=(LaplacianPreconditioner&&) noexcept =
    default;

void LaplacianPreconditioner::apply(const std::vector<Row3>& r, std::vector<Row3>& z) {
  if (impl_->mg) {
    impl_->mg->apply(r, z);
    return;
  }
  z.resize(r.size());
  for (std::size_t i = 0; i < r.size(); ++i)
    for (std::size_t c = 0; c < 3; ++c) z[i][c] = r[i][c] * impl_->inv_degree[i];
}

std::size_t LaplacianPreconditioner::size() const {
  return impl_->inv_degree.size();
}

std::size_t LaplacianPreconditioner::levels() const {
  return impl_->mg ? impl_->mg->levels() : 0;
}

}  // namespace stcweave::primal
