#include "stcweave/primal/recover.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "laplacian_solve.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/hex_complex.hpp"

namespace stcweave::primal {

HarmonicReport harmonic_positions(HexMesh& mesh, std::size_t num_fixed) {
  HarmonicReport report;
  const std::size_t n = static_cast<std::size_t>(mesh.points.rows());
  if (num_fixed >= n) return report;
  const std::size_t free = n - num_fixed;
  report.free_nodes = free;
  // Unique hex edges (as node pairs), each contributing to the graph Laplacian once.
  const auto edges = stc::unique_edges(mesh.complex);

  std::vector<std::int32_t> slot(n, -1);
  for (std::size_t v = num_fixed; v < n; ++v) slot[v] = static_cast<std::int32_t>(v - num_fixed);
  const FreeLaplacian l = edge_laplacian(edges, slot, free);
  for (std::size_t i = 0; i < free; ++i) {
    if (l.degree[i] == 0.0) {
      throw SolverError("harmonic placement: interior node n" + std::to_string(num_fixed + i) +
                        " is on no hex edge");
    }
  }
  // Right-hand side: the coordinates of each free node's fixed neighbours, summed.
  std::vector<Row3> rhs(free, Row3{0.0, 0.0, 0.0});
  for (const auto& [a, b] : edges) {
    const std::int32_t ra = slot[static_cast<std::size_t>(a)];
    const std::int32_t rb = slot[static_cast<std::size_t>(b)];
    if ((ra >= 0) == (rb >= 0)) continue;
    const auto r = static_cast<std::size_t>(ra >= 0 ? ra : rb);
    const auto m = static_cast<Eigen::Index>(ra >= 0 ? b : a);
    rhs[r][0] += mesh.points(m, 0);
    rhs[r][1] += mesh.points(m, 1);
    rhs[r][2] += mesh.points(m, 2);
  }
  // Start from the centroid of the fixed nodes: any start converges, this one is neutral.
  const Eigen::RowVector3d centre =
      mesh.points.topRows(static_cast<Eigen::Index>(num_fixed)).colwise().mean();
  std::vector<Row3> x(free, Row3{centre(0), centre(1), centre(2)});
  const std::size_t max_iterations = std::max<std::size_t>(1000, 20 * free);
  const SolveOutcome out = solve_laplacian(l, rhs, x, 1e-10, max_iterations);
  report.levels = out.levels;
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
