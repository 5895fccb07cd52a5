#include "stcweave/primal/recover.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <vector>

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

  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> triplets;
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(static_cast<Eigen::Index>(free), 3);
  std::vector<double> degree(free, 0.0);
  const auto k = [&](std::int32_t node) {
    return static_cast<Eigen::Index>(node) - static_cast<Eigen::Index>(num_fixed);
  };
  for (const auto& [a, b] : edges) {
    const bool fa = static_cast<std::size_t>(a) < num_fixed;
    const bool fb = static_cast<std::size_t>(b) < num_fixed;
    if (!fa) degree[static_cast<std::size_t>(k(a))] += 1.0;
    if (!fb) degree[static_cast<std::size_t>(k(b))] += 1.0;
    if (!fa && !fb) {
      triplets.emplace_back(k(a), k(b), -1.0);
      triplets.emplace_back(k(b), k(a), -1.0);
    } else if (!fa) {
      rhs.row(k(a)) += mesh.points.row(b);
    } else if (!fb) {
      rhs.row(k(b)) += mesh.points.row(a);
    }
  }
  Eigen::MatrixX3d guess(static_cast<Eigen::Index>(free), 3);
  for (std::size_t i = 0; i < free; ++i) {
    if (degree[i] == 0.0) {
      throw SolverError("harmonic placement: interior node n" + std::to_string(num_fixed + i) +
                        " is on no hex edge");
    }
    triplets.emplace_back(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i), degree[i]);
  }
  // Start from the centroid of the fixed nodes: any start converges, this one is neutral.
  const Eigen::RowVector3d centre =
      mesh.points.topRows(static_cast<Eigen::Index>(num_fixed)).colwise().mean();
  guess.rowwise() = centre;
  Eigen::SparseMatrix<double> laplacian(static_cast<Eigen::Index>(free),
                                        static_cast<Eigen::Index>(free));
  laplacian.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
  cg.setTolerance(1e-10);
  cg.setMaxIterations(std::max<Eigen::Index>(1000, 20 * static_cast<Eigen::Index>(free)));
  cg.compute(laplacian);
  if (cg.info() != Eigen::Success)
    throw SolverError("harmonic placement: cannot set up the solver");
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd x = cg.solveWithGuess(rhs.col(c), guess.col(c));
    if (cg.info() != Eigen::Success) {
      throw SolverError("harmonic placement did not converge (" + std::to_string(cg.iterations()) +
                        " iterations, residual " + std::to_string(cg.error()) +
                        "): some interior nodes may be cut off from the boundary");
    }
    mesh.points.block(static_cast<Eigen::Index>(num_fixed), c, static_cast<Eigen::Index>(free), 1) =
        x;
    report.iterations =
        std::max<std::size_t>(report.iterations, static_cast<std::size_t>(cg.iterations()));
    report.residual = std::max(report.residual, cg.error());
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
