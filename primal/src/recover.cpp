#include "stcweave/primal/recover.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/hex_complex.hpp"

namespace stcweave::primal {

namespace {

/// The graph Laplacian of the hex edges restricted to the free nodes, stored as neighbour
/// lists only: row i is degree[i] on the diagonal and -1 for each free neighbour. Every
/// off-diagonal entry is -1, so no value array is needed, which halves what a product reads.
struct FreeLaplacian {
  std::vector<double> degree;           ///< edge count of free node i (fixed neighbours too)
  std::vector<std::size_t> row_start;   ///< CSR offsets into `neighbour`, size free + 1
  std::vector<std::int32_t> neighbour;  ///< free neighbours, as free indices, ascending
};

using Row3 = std::array<double, 3>;

/// y = L x for three right-hand sides at once (x and y hold one row of three per free node);
/// returns the column-wise dot products x . y, which conjugate gradients needs next.
Row3 multiply(const FreeLaplacian& l, const std::vector<Row3>& x, std::vector<Row3>& y) {
  const std::size_t n = l.degree.size();
  Row3 xy{0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    Row3 sum{0.0, 0.0, 0.0};
    for (std::size_t e = l.row_start[i]; e < l.row_start[i + 1]; ++e) {
      const Row3& xj = x[static_cast<std::size_t>(l.neighbour[e])];
      sum[0] += xj[0];
      sum[1] += xj[1];
      sum[2] += xj[2];
    }
    const double d = l.degree[i];
    const Row3& xi = x[i];
    Row3& yi = y[i];
    for (std::size_t c = 0; c < 3; ++c) {
      yi[c] = d * xi[c] - sum[c];
      xy[c] += xi[c] * yi[c];
    }
  }
  return xy;
}

struct SolveOutcome {
  std::array<std::size_t, 3> iterations{0, 0, 0};
  Row3 relative_residual{0.0, 0.0, 0.0};
  std::array<bool, 3> converged{false, false, false};
};

/// Jacobi-preconditioned conjugate gradients on the three coordinate systems L x_c = b_c, run
/// side by side so that each product reads the matrix once for all three. Each column keeps
/// its own step lengths and stops on its own once its residual is below `tolerance` times its
/// right-hand side; a column that has stopped is left exactly as it is (zero step, direction
/// kept), so the result is that of three separate solves. The sums run sequentially in a
/// fixed order: the result is deterministic.
SolveOutcome conjugate_gradients(const FreeLaplacian& l, const std::vector<Row3>& b,
                                 std::vector<Row3>& x, double tolerance,
                                 std::size_t max_iterations) {
  const std::size_t n = l.degree.size();
  SolveOutcome out;
  std::vector<double> inv_degree(n);
  for (std::size_t i = 0; i < n; ++i) inv_degree[i] = 1.0 / l.degree[i];
  std::vector<Row3> r(n);
  std::vector<Row3> p(n);
  std::vector<Row3> q(n);
  multiply(l, x, q);
  Row3 b_norm2{0.0, 0.0, 0.0};
  Row3 r_norm2{0.0, 0.0, 0.0};
  Row3 rz{0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t c = 0; c < 3; ++c) {
      r[i][c] = b[i][c] - q[i][c];
      p[i][c] = r[i][c] * inv_degree[i];
      b_norm2[c] += b[i][c] * b[i][c];
      r_norm2[c] += r[i][c] * r[i][c];
      rz[c] += r[i][c] * p[i][c];
    }
  }
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
    const Row3 pq = multiply(l, p, q);
    Row3 alpha{0.0, 0.0, 0.0};
    for (std::size_t c = 0; c < 3; ++c) alpha[c] = active[c] ? rz[c] / pq[c] : 0.0;
    // x += alpha p, r -= alpha q; with z = r / degree, the new r . r and r . z.
    Row3 rr{0.0, 0.0, 0.0};
    Row3 rz_new{0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t c = 0; c < 3; ++c) {
        x[i][c] += alpha[c] * p[i][c];
        r[i][c] -= alpha[c] * q[i][c];
        rr[c] += r[i][c] * r[i][c];
        rz_new[c] += r[i][c] * r[i][c] * inv_degree[i];
      }
    }
    ++it;
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
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t c = 0; c < 3; ++c) {
        p[i][c] = z_weight[c] * r[i][c] * inv_degree[i] + beta[c] * p[i][c];
      }
    }
  }
  for (std::size_t c = 0; c < 3; ++c) {
    out.relative_residual[c] = b_norm2[c] == 0.0 ? 0.0 : std::sqrt(r_norm2[c] / b_norm2[c]);
  }
  return out;
}

}  // namespace

HarmonicReport harmonic_positions(HexMesh& mesh, std::size_t num_fixed) {
  HarmonicReport report;
  const std::size_t n = static_cast<std::size_t>(mesh.points.rows());
  if (num_fixed >= n) return report;
  const std::size_t free = n - num_fixed;
  report.free_nodes = free;
  // Unique hex edges (as node pairs), each contributing to the graph Laplacian once.
  const auto edges = stc::unique_edges(mesh.complex);

  FreeLaplacian l;
  l.degree.assign(free, 0.0);
  l.row_start.assign(free + 1, 0);
  std::vector<Row3> rhs(free, Row3{0.0, 0.0, 0.0});
  const auto is_free = [&](std::int32_t node) {
    return static_cast<std::size_t>(node) >= num_fixed;
  };
  const auto k = [&](std::int32_t node) { return static_cast<std::size_t>(node) - num_fixed; };
  const auto add_fixed = [&](std::size_t row, std::int32_t fixed_node) {
    const auto m = static_cast<Eigen::Index>(fixed_node);
    rhs[row][0] += mesh.points(m, 0);
    rhs[row][1] += mesh.points(m, 1);
    rhs[row][2] += mesh.points(m, 2);
  };
  for (const auto& [a, b] : edges) {
    if (is_free(a)) l.degree[k(a)] += 1.0;
    if (is_free(b)) l.degree[k(b)] += 1.0;
    if (is_free(a) && is_free(b)) {
      ++l.row_start[k(a) + 1];
      ++l.row_start[k(b) + 1];
    } else if (is_free(a)) {
      add_fixed(k(a), b);
    } else if (is_free(b)) {
      add_fixed(k(b), a);
    }
  }
  for (std::size_t i = 0; i < free; ++i) {
    if (l.degree[i] == 0.0) {
      throw SolverError("harmonic placement: interior node n" + std::to_string(num_fixed + i) +
                        " is on no hex edge");
    }
    l.row_start[i + 1] += l.row_start[i];
  }
  // The edges are sorted pairs (a < b): row r first receives the smaller neighbours of the
  // edges (a, r), then the larger ones of (r, b), so each row comes out ascending.
  l.neighbour.resize(l.row_start[free]);
  std::vector<std::size_t> fill(l.row_start.begin(), l.row_start.end() - 1);
  for (const auto& [a, b] : edges) {
    if (!is_free(a) || !is_free(b)) continue;
    l.neighbour[fill[k(a)]++] = static_cast<std::int32_t>(k(b));
    l.neighbour[fill[k(b)]++] = static_cast<std::int32_t>(k(a));
  }
  // Start from the centroid of the fixed nodes: any start converges, this one is neutral.
  const Eigen::RowVector3d centre =
      mesh.points.topRows(static_cast<Eigen::Index>(num_fixed)).colwise().mean();
  std::vector<Row3> x(free, Row3{centre(0), centre(1), centre(2)});
  const std::size_t max_iterations = std::max<std::size_t>(1000, 20 * free);
  const SolveOutcome out = conjugate_gradients(l, rhs, x, 1e-10, max_iterations);
  for (std::size_t c = 0; c < 3; ++c) {
    if (!out.converged[c]) {
      throw SolverError("harmonic placement did not converge (" +
                        std::to_string(out.iterations[c]) + " iterations, residual " +
                        std::to_string(out.relative_residual[c]) +
                        "): some interior nodes may be cut off from the boundary");
    }
    report.iterations = std::max(report.iterations, out.iterations[c]);
    report.residual = std::max(report.residual, out.relative_residual[c]);
  }
  for (std::size_t i = 0; i < free; ++i) {
    const auto row = static_cast<Eigen::Index>(num_fixed + i);
    mesh.points(row, 0) = x[i][0];
    mesh.points(row, 1) = x[i][1];
    mesh.points(row, 2) = x[i][2];
  }
  return report;
}

HexMesh recover_hex_mesh(const Points& input_points, const weave::WeaveResult& woven,
                         HarmonicReport* report) {
  if (static_cast<std::size_t>(input_points.rows()) != woven.num_input_nodes) {
    throw InvalidInput("recover_hex_mesh: " + std::to_string(input_points.rows()) +
                       " input points for a weave of " + std::to_string(woven.num_input_nodes) +
                       " input nodes");
  }
  HexMesh mesh;
  mesh.complex = woven.complex;
  mesh.points.resize(static_cast<Eigen::Index>(woven.complex.num_nodes), 3);
  mesh.points.topRows(input_points.rows()) = input_points;
  const HarmonicReport r = harmonic_positions(mesh, woven.num_input_nodes);
  if (report != nullptr) *report = r;
  return mesh;
}

std::size_t layer_positions(HexMesh& mesh, const weave::WeaveResult& woven) {
  const std::size_t fixed = woven.num_input_nodes;
  const std::size_t n = woven.complex.num_nodes;
  if (static_cast<std::size_t>(mesh.points.rows()) != n ||
      woven.hex_rule.size() != woven.complex.hexes.size())
    throw InvalidInput("layer_positions: the mesh is not the recovered mesh of this weave");
  Points sum = Points::Zero(static_cast<Eigen::Index>(n), 3);
  std::vector<int> count(n, 0);
  const auto known = [&](NodeId m) { return m.index() < fixed || count[m.index()] > 0; };
  const auto at = [&](NodeId m) -> Eigen::RowVector3d {
    if (m.index() < fixed) return mesh.points.row(static_cast<Eigen::Index>(m.index()));
    return sum.row(static_cast<Eigen::Index>(m.index())) / count[m.index()];
  };
  const auto add = [&](NodeId m, const Eigen::RowVector3d& p) {
    if (m.index() < fixed) return;
    sum.row(static_cast<Eigen::Index>(m.index())) += p;
    ++count[m.index()];
  };
  for (std::size_t h = 0; h < woven.complex.hexes.size(); ++h) {
    const stc::Hex& x = woven.complex.hexes[h];
    const std::string& rule = woven.hex_rule[h];
    if (rule == "cross" || rule == "cross-relaxed") {
      // {v, b, xab, a, c, xbc, w, xca}: w completes the corner at v.
      if (known(x[0]) && known(x[1]) && known(x[2]) && known(x[3]) && known(x[4]) && known(x[5]) &&
          known(x[7]))
        add(x[6], at(x[2]) + at(x[5]) + at(x[7]) - at(x[1]) - at(x[3]) - at(x[4]) + at(x[0]));
    } else if (rule == "blind-chord") {
      // {s, p3, p2, t, q2, n5, n6, q3}: n5 above p3, n6 above p2 (q2 is above s, q3 above t).
      if (known(x[0]) && known(x[1]) && known(x[4])) add(x[5], at(x[1]) + at(x[4]) - at(x[0]));
      if (known(x[2]) && known(x[3]) && known(x[7])) add(x[6], at(x[2]) + at(x[7]) - at(x[3]));
    }
  }
  std::size_t placed = 0;
  for (std::size_t m = fixed; m < n; ++m) {
    if (count[m] == 0) continue;
    mesh.points.row(static_cast<Eigen::Index>(m)) =
        sum.row(static_cast<Eigen::Index>(m)) / count[m];
    ++placed;
  }
  return placed;
}

}  // namespace stcweave::primal
