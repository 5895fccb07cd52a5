/// \file
/// The barrier pass of the shape phase (`raise_worst_corners`, docs/geometry.md "Shape
/// phase"): a soft minimum of the corner scaled Jacobians of the poor hexes behind a hard
/// level, minimised by L-BFGS over the free nodes of those hexes, round by round.
#include <LBFGS.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "stcweave/primal/position.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"

#include "node_hexes.hpp"

namespace stcweave::primal {
namespace {

/// Corner scaled Jacobian q = det(e1, e2, e3) / (|e1| |e2| |e3|) and, with `grad`, its
/// derivatives with respect to the three edge vectors. NaN when an edge has length 0.
double corner_quality(const std::array<Eigen::Vector3d, 3>& e,
                      std::array<Eigen::Vector3d, 3>* grad) {
  const double l0 = e[0].norm();
  const double l1 = e[1].norm();
  const double l2 = e[2].norm();
  const double length = l0 * l1 * l2;
  if (!(length > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d c12 = e[1].cross(e[2]);
  const double q = e[0].dot(c12) / length;
  if (grad != nullptr) {
    (*grad)[0] = c12 / length - q * e[0] / (l0 * l0);
    (*grad)[1] = e[2].cross(e[0]) / length - q * e[1] / (l1 * l1);
    (*grad)[2] = e[0].cross(e[1]) / length - q * e[2] / (l2 * l2);
  }
  return q;
}

/// The barrier problem of one round: the hexes around the moving nodes, their corners that
/// depend on a moving node, and the level t below every such corner.
class Barrier {
 public:
  Barrier(HexMesh& mesh, std::vector<std::size_t> hexes, std::vector<std::int32_t> moving,
          double scale)
      : mesh_(mesh), hexes_(std::move(hexes)), moving_(std::move(moving)), scale_(scale) {
    slot_.assign(static_cast<std::size_t>(mesh.points.rows()), -1);
    for (std::size_t i = 0; i < moving_.size(); ++i)
      slot_[static_cast<std::size_t>(moving_[i])] = static_cast<std::int32_t>(i);
    for (const std::size_t h : hexes_) {
      const stc::Hex& hex = mesh.complex.hexes[h];
      for (std::size_t k = 0; k < 8; ++k) {
        bool moves = false;
        for (const int local : kHexCorners[k])
          moves = moves || slot_[hex[static_cast<std::size_t>(local)].index()] >= 0;
        if (moves) corners_.push_back(h * 8 + k);
      }
    }
  }

  [[nodiscard]] Eigen::VectorXd variables() const {
    Eigen::VectorXd x(static_cast<Eigen::Index>(3 * moving_.size()));
    for (std::size_t i = 0; i < moving_.size(); ++i)
      for (int c = 0; c < 3; ++c)
        x(static_cast<Eigen::Index>(3 * i) + c) = mesh_.points(moving_[i], c) / scale_;
    return x;
  }

  void set_variables(const Eigen::VectorXd& x) {
    for (std::size_t i = 0; i < moving_.size(); ++i)
      for (int c = 0; c < 3; ++c)
        mesh_.points(moving_[i], c) = x(static_cast<Eigen::Index>(3 * i) + c) * scale_;
  }

  /// Smallest scaled Jacobian of the corners that depend on a moving node.
  [[nodiscard]] double min_corner() const {
    double best = std::numeric_limits<double>::infinity();
    for (const std::size_t c : corners_) {
      const double q = corner_quality(edges(c), nullptr);
      best = std::isnan(q) ? -std::numeric_limits<double>::infinity() : std::min(best, q);
    }
    return best;
  }

  /// The level t, the softness tau of the soft minimum around `reference` and the weight
  /// of the mean term.
  void set_level(double t, double reference, double tau, double weight) {
    level_ = t;
    reference_ = reference;
    tau_ = tau;
    weight_ = weight;
  }

  /// sum over the corners of exp((q_ref - q) / tau) + weight (1 - q)^2; +infinity when a
  /// corner is at or below t.
  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    set_variables(x);
    grad.setZero(x.size());
    double f = 0.0;
    std::array<Eigen::Vector3d, 3> g;
    for (const std::size_t c : corners_) {
      const double q = corner_quality(edges(c), &g);
      if (!(q > level_)) {
        grad.setZero(x.size());
        return std::numeric_limits<double>::infinity();
      }
      // Soft minimum: exp((q_ref - q) / tau) weighs the worst corners most; the level keeps
      // every corner above t.
      const double soft = std::exp(std::min(600.0, (reference_ - q) / tau_));
      f += soft + weight_ * (1.0 - q) * (1.0 - q);
      const double w = -soft / tau_ - 2.0 * weight_ * (1.0 - q);
      const stc::Hex& hex = mesh_.complex.hexes[c / 8];
      const auto& corner = kHexCorners[c % 8];
      const std::int32_t origin = slot_[hex[static_cast<std::size_t>(corner[0])].index()];
      for (std::size_t j = 0; j < 3; ++j) {
        const std::int32_t to = slot_[hex[static_cast<std::size_t>(corner[j + 1])].index()];
        // Edge j = x_to - x_origin, in model units; variables are scaled by 1 / scale.
        const Eigen::Vector3d d = w * scale_ * g[j];
        if (to >= 0) grad.segment<3>(3 * Eigen::Index{to}) += d;
        if (origin >= 0) grad.segment<3>(3 * Eigen::Index{origin}) -= d;
      }
    }
    if (!std::isfinite(f)) {
      grad.setZero(x.size());
      return std::numeric_limits<double>::infinity();
    }
    if (f < best_energy_) {
      best_energy_ = f;
      best_ = x;
    }
    return f;
  }

  void reset(const Eigen::VectorXd& x) {
    best_ = x;
    best_energy_ = std::numeric_limits<double>::infinity();
    Eigen::VectorXd g;
    (*this)(x, g);
  }
  [[nodiscard]] const Eigen::VectorXd& best() const { return best_; }
  [[nodiscard]] std::size_t num_corners() const { return corners_.size(); }

 private:
  [[nodiscard]] std::array<Eigen::Vector3d, 3> edges(std::size_t c) const {
    const stc::Hex& hex = mesh_.complex.hexes[c / 8];
    const auto& corner = kHexCorners[c % 8];
    const auto p = [&](int local) -> Eigen::Vector3d {
      return mesh_.points.row(hex[static_cast<std::size_t>(local)].value()).transpose();
    };
    const Eigen::Vector3d o = p(corner[0]);
    return {p(corner[1]) - o, p(corner[2]) - o, p(corner[3]) - o};
  }

  HexMesh& mesh_;
  std::vector<std::size_t> hexes_;
  std::vector<std::int32_t> moving_;
  double scale_;
  std::vector<std::int32_t> slot_;
  std::vector<std::size_t> corners_;  ///< hex * 8 + corner
  double level_ = 0.0;
  double reference_ = 0.0;
  double tau_ = 1.0;
  double weight_ = 0.0;
  Eigen::VectorXd best_;
  double best_energy_ = std::numeric_limits<double>::infinity();
};

}  // namespace

BarrierReport raise_worst_corners(HexMesh& mesh, const std::vector<bool>& fixed,
                                  const PositionOptions& options) {
  BarrierReport report;
  const std::size_t n = static_cast<std::size_t>(mesh.points.rows());
  if (fixed.size() != n)
    throw InvalidInput("raise_worst_corners: the fixed mask has " + std::to_string(fixed.size()) +
                       " entries for " + std::to_string(n) + " nodes");
  if (!(options.barrier_margin > 0.0 && options.barrier_margin < 1.0) ||
      !(options.barrier_softness > 0.0) || !(options.barrier_mean_weight >= 0.0)) {
    throw InvalidInput("raise_worst_corners: barrier_margin must be in ]0, 1[ (is " +
                       std::to_string(options.barrier_margin) + "), barrier_softness > 0 (is " +
                       std::to_string(options.barrier_softness) +
                       ") and barrier_mean_weight >= 0 (is " +
                       std::to_string(options.barrier_mean_weight) + ")");
  }
  const std::vector<stc::Hex>& hexes = mesh.complex.hexes;
  for (const stc::Hex& h : hexes) {
    for (const NodeId v : h) {
      if (!v.is_valid() || v.index() >= n) {
        throw InvalidInput("raise_worst_corners: a hex names node " + v.str() + " out of range (" +
                           std::to_string(n) + " nodes)");
      }
    }
  }
  std::vector<double> sj(hexes.size());
  for (std::size_t h = 0; h < hexes.size(); ++h) sj[h] = hex_scaled_jacobian(mesh.points, hexes[h]);
  const auto global_min = [&] {
    return sj.empty() ? 1.0 : *std::min_element(sj.begin(), sj.end());
  };
  report.min_scaled_jacobian_before = report.min_scaled_jacobian_after = global_min();
  if (options.barrier_rounds <= 0) {
    report.stop = "off";
    return report;
  }
  if (!hexes.empty() && !(report.min_scaled_jacobian_before > 0.0)) {
    report.stop = "inverted hexes: skipped";
    return report;
  }
  // Hexes around each node (CSR).
  const NodeHexes incidence = node_hexes(hexes, n);
  const std::vector<std::size_t>& start = incidence.start;
  const std::vector<std::size_t>& around = incidence.around;
  report.stop = "round limit";
  int kept = 0;
  for (int round = 0; round < options.barrier_rounds; ++round) {
    // Moving nodes: the free nodes of the hexes below the target; evaluated: every hex
    // around a moving node (so no hex the round can change is left unwatched).
    const double below = std::min(options.shape_target, global_min() + options.barrier_window);
    std::vector<bool> moving_mask(n, false);
    for (std::size_t h = 0; h < hexes.size(); ++h)
      if (sj[h] < below)
        for (const NodeId v : hexes[h]) moving_mask[v.index()] = !fixed[v.index()];
    std::vector<std::int32_t> moving;
    for (std::size_t v = 0; v < n; ++v)
      if (moving_mask[v]) moving.push_back(static_cast<std::int32_t>(v));
    if (moving.empty()) {
      report.stop = round == 0 && global_min() < options.shape_target
                        ? "no free node below the target"
                        : "target reached";
      break;
    }
    std::vector<bool> seen(hexes.size(), false);
    std::vector<std::size_t> local;
    double length = 0.0;
    std::size_t edges = 0;
    for (const std::int32_t v : moving) {
      for (std::size_t i = start[static_cast<std::size_t>(v)];
           i < start[static_cast<std::size_t>(v) + 1]; ++i) {
        if (seen[around[i]]) continue;
        seen[around[i]] = true;
        local.push_back(around[i]);
      }
    }
    std::sort(local.begin(), local.end());
    for (const std::size_t h : local) {
      for (const auto& [a, b] : stc::kHexEdges) {
        length += (mesh.points.row(hexes[h][static_cast<std::size_t>(a)].value()) -
                   mesh.points.row(hexes[h][static_cast<std::size_t>(b)].value()))
                      .norm();
        ++edges;
      }
    }
    const double scale = edges > 0 && length > 0.0 ? length / static_cast<double>(edges) : 1.0;
    double local_min_before = 1.0;
    for (const std::size_t h : local) local_min_before = std::min(local_min_before, sj[h]);
    Barrier barrier(mesh, local, moving, scale);
    const double q_min = barrier.min_corner();
    if (!(q_min > 0.0)) {
      report.stop = "inverted corner: stopped";
      break;
    }
    report.min_corner_before = round == 0 ? q_min : report.min_corner_before;
    barrier.set_level(q_min * (1.0 - options.barrier_margin), q_min, options.barrier_softness,
                      options.barrier_mean_weight);
    const Eigen::VectorXd x0 = barrier.variables();
    Eigen::VectorXd x = x0;
    barrier.reset(x);
    LBFGSpp::LBFGSParam<double> param;
    param.m = options.memory;
    param.epsilon = 1e-6;
    param.epsilon_rel = 0.0;
    param.past = 1;
    param.delta = 1e-8;
    param.max_iterations = options.barrier_iterations;
    param.max_linesearch = 60;
    param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_ARMIJO;
    LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchBacktracking> solver(param);
    double fx = 0.0;
    try {
      report.iterations += static_cast<std::size_t>(solver.minimize(barrier, x, fx));
    } catch (const std::exception&) {
      // A line search that cannot progress ends the round; the best point is kept.
    }
    barrier.set_variables(barrier.best());
    ++report.rounds;
    // Accept the round only when the worst hex (Verdict's scaled Jacobian, centre included)
    // of the hexes it could change did not get worse and something was gained.
    std::vector<double> updated(local.size());
    double local_min_after = 1.0;
    for (std::size_t i = 0; i < local.size(); ++i) {
      updated[i] = hex_scaled_jacobian(mesh.points, hexes[local[i]]);
      local_min_after = std::min(local_min_after, updated[i]);
    }
    const double q_after = barrier.min_corner();
    const bool worse = local_min_after < local_min_before;
    const bool gained = q_after - q_min >= options.shape_tolerance * 0.1 ||
                        local_min_after - local_min_before >= options.shape_tolerance * 0.1;
    if (worse || !gained) {
      barrier.set_variables(x0);
      report.stop = worse ? "settled (a round lowered the worst hex: undone)" : "settled";
      break;
    }
    for (std::size_t i = 0; i < local.size(); ++i) sj[local[i]] = updated[i];
    ++kept;
    report.min_corner_after = q_after;
    report.min_scaled_jacobian_after = global_min();
  }
  if (kept == 0) report.min_corner_after = report.min_corner_before;
  report.ran = kept > 0;
  return report;
}

}  // namespace stcweave::primal
