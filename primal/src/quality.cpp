#include "stcweave/primal/quality.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <limits>

namespace stcweave::primal {
namespace {

/// For corner k: the corner node and its three edge neighbours, ordered so that the
/// determinant is positive for a positively oriented hex (Verdict's table).
constexpr std::array<std::array<int, 4>, 8> kCorners = {{{0, 1, 3, 4},
                                                         {1, 2, 0, 5},
                                                         {2, 3, 1, 6},
                                                         {3, 0, 2, 7},
                                                         {4, 7, 5, 0},
                                                         {5, 4, 6, 1},
                                                         {6, 5, 7, 2},
                                                         {7, 6, 4, 3}}};

double unit_det(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  if (la <= std::numeric_limits<double>::min() || lb <= std::numeric_limits<double>::min() ||
      lc <= std::numeric_limits<double>::min())
    return 0.0;
  return a.dot(b.cross(c)) / (la * lb * lc);
}

Eigen::Vector3d p(const Points& points, const stc::Hex& h, int i) {
  return points.row(h[static_cast<std::size_t>(i)].value()).transpose();
}

}  // namespace

double hex_corner_scaled_jacobian(const Points& points, const stc::Hex& h) {
  double best = std::numeric_limits<double>::max();
  for (const auto& c : kCorners) {
    const Eigen::Vector3d o = p(points, h, c[0]);
    best = std::min(best, unit_det(p(points, h, c[1]) - o, p(points, h, c[2]) - o,
                                   p(points, h, c[3]) - o));
  }
  return best;
}

double hex_scaled_jacobian(const Points& points, const stc::Hex& h) {
  const auto P = [&](int i) { return p(points, h, i); };
  const Eigen::Vector3d x1 = (P(1) - P(0)) + (P(2) - P(3)) + (P(5) - P(4)) + (P(6) - P(7));
  const Eigen::Vector3d x2 = (P(3) - P(0)) + (P(2) - P(1)) + (P(7) - P(4)) + (P(6) - P(5));
  const Eigen::Vector3d x3 = (P(4) - P(0)) + (P(5) - P(1)) + (P(6) - P(2)) + (P(7) - P(3));
  return std::min(hex_corner_scaled_jacobian(points, h), unit_det(x1, x2, x3));
}

QualitySummary summarize_quality(const HexMesh& mesh) {
  QualitySummary s;
  s.hexes = mesh.complex.hexes.size();
  s.per_hex.reserve(s.hexes);
  double sum = 0.0;
  s.min_scaled_jacobian = s.hexes == 0 ? 0.0 : std::numeric_limits<double>::max();
  for (const stc::Hex& h : mesh.complex.hexes) {
    const double sj = hex_scaled_jacobian(mesh.points, h);
    s.per_hex.push_back(sj);
    s.min_scaled_jacobian = std::min(s.min_scaled_jacobian, sj);
    sum += sj;
    if (sj <= 0.0) ++s.inverted;
    if (sj < 0.2) ++s.below_0_2;
  }
  s.mean_scaled_jacobian = s.hexes == 0 ? 0.0 : sum / static_cast<double>(s.hexes);
  return s;
}

}  // namespace stcweave::primal
