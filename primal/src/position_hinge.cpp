// Hinge untangling of a small mesh (position_hinge.hpp; docs/geometry.md "Local untangling").
//
// Why this energy: on `pmp/fandisk_quads` the last inverted hex sits in overlapping pillowed
// blocks where three nodes have nearly merged (an edge 1e-3 of the mesh size). Every max-min
// formulation tried there (smoothed minimum of the scaled Jacobians by L-BFGS, sequential
// linear programs on scaled Jacobians, determinants or mean ratios) crept up to 0 from below
// and stalled where such an edge collapses: raising the worst corner drives the nodes
// together. A sum of hinges on a measure that is bounded and smooth at short edges pushes
// every corner below `beta` up at once and leaves the others alone; measured there it ends
// with no inverted hex from either weave's mesh (docs/geometry.md).

#include "position_hinge.hpp"

#include <LBFGS.h>
#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <utility>

#include "stcweave/primal/quality.hpp"

namespace stcweave::primal {
namespace {

using Vec3 = Eigen::Vector3d;

/// The mean-ratio measure of three edge vectors and its gradient with respect to them.
double mean_ratio(const Vec3& a, const Vec3& b, const Vec3& c, std::array<Vec3, 3>& g) {
  const double s = a.squaredNorm() + b.squaredNorm() + c.squaredNorm();
  if (!(s > 0.0)) {
    g = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    return -1.0;
  }
  const double k = 3.0 * std::sqrt(3.0);
  const Vec3 bc = b.cross(c);
  const double det = a.dot(bc);
  const double s32 = s * std::sqrt(s);
  const double q = k * det / s32;
  const double shrink = 3.0 * q / s;  // d/dx of s^(-3/2) times k det, over x
  g = {k * bc / s32 - shrink * a, k * c.cross(a) / s32 - shrink * b,
       k * a.cross(b) / s32 - shrink * c};
  return q;
}

/// Signs of the hex's nodes in its three principal axes (`principal_axes` in quality.cpp).
constexpr std::array<std::array<double, 8>, 3> kAxisSigns = {
    {{-1, 1, 1, -1, -1, 1, 1, -1}, {-1, -1, 1, 1, -1, -1, 1, 1}, {-1, -1, -1, -1, 1, 1, 1, 1}}};

/// One term: a hex corner (0..7) or its centre (8).
struct Term {
  std::uint32_t hex = 0;
  std::uint8_t corner = 0;
};

}  // namespace

HingeOutcome hinge_untangle(HexMesh& mesh, const std::vector<bool>& fixed, double beta,
                            std::size_t max_iterations, double first_delta) {
  HingeOutcome out;
  const auto num_nodes = static_cast<std::size_t>(mesh.points.rows());
  std::vector<std::int32_t> slot(num_nodes, -1);
  std::vector<std::int32_t> free_nodes;
  for (std::size_t v = 0; v < num_nodes; ++v) {
    if (fixed[v]) continue;
    slot[v] = static_cast<std::int32_t>(free_nodes.size());
    free_nodes.push_back(static_cast<std::int32_t>(v));
  }
  if (free_nodes.empty() || max_iterations == 0) return out;
  const std::vector<stc::Hex>& hexes = mesh.complex.hexes;
  std::vector<Term> terms;
  double edge_sum = 0.0;
  std::size_t edges = 0;
  for (std::size_t h = 0; h < hexes.size(); ++h) {
    const stc::Hex& x = hexes[h];
    if (std::none_of(x.begin(), x.end(), [&](NodeId v) { return slot[v.index()] >= 0; })) continue;
    for (std::uint8_t k = 0; k < 8; ++k) {
      const auto& c = kHexCorners[k];
      if (std::any_of(c.begin(), c.end(),
                      [&](int i) { return slot[x[static_cast<std::size_t>(i)].index()] >= 0; }))
        terms.push_back({static_cast<std::uint32_t>(h), k});
    }
    terms.push_back({static_cast<std::uint32_t>(h), 8});
    for (const std::size_t k : {0, 2, 5, 7}) {  // the three edges at these corners: all 12
      const auto& c = kHexCorners[k];
      for (std::size_t l = 1; l < 4; ++l) {
        edge_sum += (mesh.points.row(x[static_cast<std::size_t>(c[l])].value()) -
                     mesh.points.row(x[static_cast<std::size_t>(c[0])].value()))
                        .norm();
        ++edges;
      }
    }
  }
  // The unknowns are the free nodes' coordinates over the mean edge length (the measure does
  // not depend on the scale; L-BFGS's first steps do).
  const double scale = edges > 0 && edge_sum > 0.0 ? edge_sum / static_cast<double>(edges) : 1.0;
  const auto n = static_cast<Eigen::Index>(free_nodes.size());
  Eigen::VectorXd x(3 * n);
  for (Eigen::Index i = 0; i < n; ++i)
    x.segment<3>(3 * i) =
        mesh.points.row(free_nodes[static_cast<std::size_t>(i)]).transpose() / scale;

  std::vector<Vec3> p(num_nodes);
  for (std::size_t v = 0; v < num_nodes; ++v)
    p[v] = mesh.points.row(static_cast<Eigen::Index>(v)).transpose();
  const auto place = [&](const Eigen::VectorXd& y) {
    for (Eigen::Index i = 0; i < n; ++i)
      p[static_cast<std::size_t>(free_nodes[static_cast<std::size_t>(i)])] =
          y.segment<3>(3 * i) * scale;
  };
  double delta = 0.1;
  const auto energy = [&](const Eigen::VectorXd& y, Eigen::VectorXd& grad) -> double {
    place(y);
    grad.setZero();
    double f = 0.0;
    std::array<Vec3, 3> g;
    std::array<Vec3, 8> node_grad;
    for (const Term& t : terms) {
      const stc::Hex& hx = hexes[t.hex];
      double q = 0.0;
      if (t.corner < 8) {
        const auto& c = kHexCorners[t.corner];
        const Vec3& o = p[hx[static_cast<std::size_t>(c[0])].index()];
        q = mean_ratio(p[hx[static_cast<std::size_t>(c[1])].index()] - o,
                       p[hx[static_cast<std::size_t>(c[2])].index()] - o,
                       p[hx[static_cast<std::size_t>(c[3])].index()] - o, g);
        node_grad.fill(Vec3::Zero());
        for (std::size_t l = 0; l < 3; ++l) {
          node_grad[static_cast<std::size_t>(c[l + 1])] += g[l];
          node_grad[static_cast<std::size_t>(c[0])] -= g[l];
        }
      } else {
        std::array<Vec3, 3> axis = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
        for (std::size_t a = 0; a < 3; ++a)
          for (std::size_t i = 0; i < 8; ++i) axis[a] += kAxisSigns[a][i] * p[hx[i].index()];
        q = mean_ratio(axis[0], axis[1], axis[2], g);
        for (std::size_t i = 0; i < 8; ++i) {
          node_grad[i] = Vec3::Zero();
          for (std::size_t a = 0; a < 3; ++a) node_grad[i] += kAxisSigns[a][i] * g[a];
        }
      }
      if (!std::isfinite(q)) return std::numeric_limits<double>::max();
      const double u = q - beta;
      const double root = std::sqrt(u * u + delta * delta);
      f += root - u;
      const double df = u / root - 1.0;
      for (std::size_t i = 0; i < 8; ++i) {
        const std::int32_t s = slot[hx[i].index()];
        if (s >= 0) grad.segment<3>(3 * static_cast<Eigen::Index>(s)) += df * scale * node_grad[i];
      }
    }
    return f;
  };

  LBFGSpp::LBFGSParam<double> param;
  param.m = 10;
  param.epsilon = 1e-10;
  param.max_linesearch = 60;
  std::size_t left = max_iterations;
  Eigen::VectorXd grad(3 * n);
  for (delta = first_delta; delta > 1e-6 && left > 0; delta *= 0.3) {
    param.max_iterations = static_cast<int>(std::min<std::size_t>(5000, left));
    LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchBracketing> solver(param);
    const Eigen::VectorXd start = x;
    const double f_start = energy(start, grad);
    double fx = 0.0;
    std::size_t used = 0;
    try {
      used = static_cast<std::size_t>(solver.minimize(energy, x, fx));
    } catch (const std::exception&) {
      // The line search gave up: keep where it stopped if that is no worse than the start.
      used = static_cast<std::size_t>(param.max_iterations);
      if (!(energy(x, grad) <= f_start)) x = start;
    }
    used = std::max<std::size_t>(1, std::min(used, left));
    out.iterations += used;
    left -= used;
    ++out.stages;
  }
  place(x);
  for (const std::int32_t v : free_nodes)
    mesh.points.row(v) = p[static_cast<std::size_t>(v)].transpose();
  return out;
}

}  // namespace stcweave::primal
