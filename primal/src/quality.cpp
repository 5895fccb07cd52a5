#include "stcweave/primal/quality.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace stcweave::primal {
namespace {

/// Parameters of the nodes in [0,1]^3 (VTK order).
constexpr std::array<std::array<int, 3>, 8> kNodeParams = {
    {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};

using Corners = std::array<Eigen::Vector3d, 8>;

double unit_det(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  if (la <= std::numeric_limits<double>::min() || lb <= std::numeric_limits<double>::min() ||
      lc <= std::numeric_limits<double>::min())
    return 0.0;
  return a.dot(b.cross(c)) / (la * lb * lc);
}

Corners corners_of(const Points& points, const stc::Hex& h) {
  Corners c;
  for (std::size_t i = 0; i < 8; ++i) c[i] = points.row(h[i].value()).transpose();
  return c;
}

/// The principal axes X1, X2, X3 (Verdict): sums of the four edges of each direction.
std::array<Eigen::Vector3d, 3> principal_axes(const Corners& p) {
  return {(p[1] - p[0]) + (p[2] - p[3]) + (p[5] - p[4]) + (p[6] - p[7]),
          (p[3] - p[0]) + (p[2] - p[1]) + (p[7] - p[4]) + (p[6] - p[5]),
          (p[4] - p[0]) + (p[5] - p[1]) + (p[6] - p[2]) + (p[7] - p[3])};
}

double corner_det(const Corners& p, const std::array<int, 4>& c) {
  const Eigen::Vector3d& o = p[static_cast<std::size_t>(c[0])];
  const Eigen::Vector3d e1 = p[static_cast<std::size_t>(c[1])] - o;
  const Eigen::Vector3d e2 = p[static_cast<std::size_t>(c[2])] - o;
  const Eigen::Vector3d e3 = p[static_cast<std::size_t>(c[3])] - o;
  return e1.dot(e2.cross(e3));
}

/// Signed volume of the tet (a, b, c, d) times 6.
double tet6(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
            const Eigen::Vector3d& d) {
  return (b - a).cross(c - a).dot(d - a);
}

/// The point of parameters (u, v, w) of the trilinear map of `p`.
Eigen::Vector3d trilinear(const Corners& p, double u, double v, double w) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < 8; ++i) {
    const double a = kNodeParams[i][0] != 0 ? u : 1.0 - u;
    const double b = kNodeParams[i][1] != 0 ? v : 1.0 - v;
    const double c = kNodeParams[i][2] != 0 ? w : 1.0 - w;
    x += (a * b * c) * p[i];
  }
  return x;
}

Validity validity_of(const Corners& p, int depth) {
  const std::array<double, 27> b = hex_bezier_coefficients(p);
  if (*std::min_element(b.begin(), b.begin() + 8) <= 0.0) return Validity::Invalid;
  if (*std::min_element(b.begin(), b.end()) > 0.0) return Validity::Valid;
  if (depth <= 0) return Validity::Uncertain;
  bool uncertain = false;
  for (int child = 0; child < 8; ++child) {
    const auto& o = kNodeParams[static_cast<std::size_t>(child)];
    Corners sub;
    for (std::size_t i = 0; i < 8; ++i)
      sub[i] = trilinear(p, 0.5 * (o[0] + kNodeParams[i][0]), 0.5 * (o[1] + kNodeParams[i][1]),
                         0.5 * (o[2] + kNodeParams[i][2]));
    const Validity v = validity_of(sub, depth - 1);
    if (v == Validity::Invalid) return Validity::Invalid;
    if (v == Validity::Uncertain) uncertain = true;
  }
  return uncertain ? Validity::Uncertain : Validity::Valid;
}

}  // namespace

std::array<double, 8> hex_corner_jacobians(const Points& points, const stc::Hex& h) {
  const Corners p = corners_of(points, h);
  std::array<double, 8> out{};
  for (std::size_t k = 0; k < 8; ++k) out[k] = corner_det(p, kHexCorners[k]);
  return out;
}

double hex_corner_scaled_jacobian(const Points& points, const stc::Hex& h) {
  const Corners p = corners_of(points, h);
  double best = std::numeric_limits<double>::max();
  for (const auto& c : kHexCorners) {
    const Eigen::Vector3d& o = p[static_cast<std::size_t>(c[0])];
    best = std::min(
        best, unit_det(p[static_cast<std::size_t>(c[1])] - o, p[static_cast<std::size_t>(c[2])] - o,
                       p[static_cast<std::size_t>(c[3])] - o));
  }
  return best;
}

double hex_scaled_jacobian(const Points& points, const stc::Hex& h) {
  const Corners p = corners_of(points, h);
  // A hex with a coordinate that is not finite is the worst there is (NaN compares false, so
  // it would pass every "<= 0" test and every judge that keeps the best try).
  for (const Eigen::Vector3d& c : p)
    if (!c.allFinite()) return -1.0;
  const std::array<Eigen::Vector3d, 3> x = principal_axes(p);
  const double sj = std::min(hex_corner_scaled_jacobian(points, h), unit_det(x[0], x[1], x[2]));
  return std::isnan(sj) ? -1.0 : sj;
}

double hex_jacobian(const Points& points, const stc::Hex& h) {
  const Corners p = corners_of(points, h);
  const std::array<Eigen::Vector3d, 3> x = principal_axes(p);
  double best = x[0].dot(x[1].cross(x[2])) / 64.0;
  for (const auto& c : kHexCorners) best = std::min(best, corner_det(p, c));
  return best;
}

double hex_edge_ratio(const Points& points, const stc::Hex& h) {
  const Corners p = corners_of(points, h);
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (const auto& e : stc::kHexEdges) {
    const double l = (p[static_cast<std::size_t>(e[1])] - p[static_cast<std::size_t>(e[0])]).norm();
    lo = std::min(lo, l);
    hi = std::max(hi, l);
  }
  if (lo <= 0.0) return std::numeric_limits<double>::infinity();
  return hi / lo;
}

double hex_max_aspect_frobenius(const Points& points, const stc::Hex& h) {
  const Corners p = corners_of(points, h);
  double worst = 0.0;
  for (const auto& c : kHexCorners) {
    const Eigen::Vector3d& o = p[static_cast<std::size_t>(c[0])];
    const Eigen::Vector3d e1 = p[static_cast<std::size_t>(c[1])] - o;
    const Eigen::Vector3d e2 = p[static_cast<std::size_t>(c[2])] - o;
    const Eigen::Vector3d e3 = p[static_cast<std::size_t>(c[3])] - o;
    const double det = e1.dot(e2.cross(e3));
    if (det <= std::numeric_limits<double>::min()) return std::numeric_limits<double>::max();
    const double norm = std::sqrt(e1.squaredNorm() + e2.squaredNorm() + e3.squaredNorm());
    const double adj = std::sqrt(e1.cross(e2).squaredNorm() + e2.cross(e3).squaredNorm() +
                                 e3.cross(e1).squaredNorm());
    worst = std::max(worst, norm * adj / (3.0 * det));
  }
  return worst;
}

double hex_jacobian_at(const Points& points, const stc::Hex& h, double u, double v, double w) {
  const Corners p = corners_of(points, h);
  const Eigen::Vector3d du = (1 - v) * (1 - w) * (p[1] - p[0]) + v * (1 - w) * (p[2] - p[3]) +
                             (1 - v) * w * (p[5] - p[4]) + v * w * (p[6] - p[7]);
  const Eigen::Vector3d dv = (1 - u) * (1 - w) * (p[3] - p[0]) + u * (1 - w) * (p[2] - p[1]) +
                             (1 - u) * w * (p[7] - p[4]) + u * w * (p[6] - p[5]);
  const Eigen::Vector3d dw = (1 - u) * (1 - v) * (p[4] - p[0]) + u * (1 - v) * (p[5] - p[1]) +
                             u * v * (p[6] - p[2]) + (1 - u) * v * (p[7] - p[3]);
  return du.dot(dv.cross(dw));
}

std::array<double, 27> hex_bezier_coefficients(const std::array<Eigen::Vector3d, 8>& p) {
  const auto m = [&p](int a, int b) -> Eigen::Vector3d {
    return 0.5 * (p[static_cast<std::size_t>(a)] + p[static_cast<std::size_t>(b)]);
  };
  const auto node = [&p](int a) -> const Eigen::Vector3d& {
    return p[static_cast<std::size_t>(a)];
  };
  // J0..J7: the corner values; J8..J19: tets with two edge midpoints (Johnen et al.).
  std::array<double, 20> j{};
  for (std::size_t k = 0; k < 8; ++k) j[k] = corner_det(p, kHexCorners[k]);
  j[8] = tet6(node(0), node(1), m(2, 3), m(4, 5));
  j[9] = tet6(node(1), node(2), m(3, 0), m(5, 6));
  j[10] = tet6(node(2), node(3), m(0, 1), m(6, 7));
  j[11] = tet6(node(3), node(0), m(1, 2), m(7, 4));
  j[12] = tet6(node(0), node(4), m(1, 5), m(3, 7));
  j[13] = tet6(node(1), node(5), m(2, 6), m(0, 4));
  j[14] = tet6(node(2), node(6), m(3, 7), m(1, 5));
  j[15] = tet6(node(3), node(7), m(0, 4), m(2, 6));
  j[16] = tet6(node(4), node(5), m(0, 1), m(6, 7));
  j[17] = tet6(node(5), node(6), m(1, 2), m(7, 4));
  j[18] = tet6(node(6), node(7), m(2, 3), m(4, 5));
  j[19] = tet6(node(7), node(4), m(3, 0), m(5, 6));
  std::array<double, 27> b{};
  for (std::size_t i = 0; i < 8; ++i) b[i] = j[i];
  for (std::size_t i = 8; i < 12; ++i) b[i] = 2 * j[i] - 0.5 * (j[i - 8] + j[(i - 7) % 4]);
  for (std::size_t i = 12; i < 16; ++i) b[i] = 2 * j[i] - 0.5 * (j[i - 12] + j[i - 8]);
  for (std::size_t i = 16; i < 20; ++i) b[i] = 2 * j[i] - 0.5 * (j[i - 12] + j[4 + (i - 15) % 4]);
  const auto sum = [&j](std::size_t first, std::size_t last) {
    double s = 0.0;
    for (std::size_t i = first; i <= last; ++i) s += j[i];
    return s;
  };
  b[20] = sum(8, 11) - 0.75 * sum(0, 3);
  for (std::size_t i = 21; i < 25; ++i)
    b[i] = j[i - 13] + j[i - 9] + j[12 + (i - 20) % 4] + j[i - 5] -
           0.75 * (j[i - 21] + j[i - 17] + j[(i - 20) % 4] + j[4 + (i - 20) % 4]);
  b[25] = sum(16, 19) - 0.75 * sum(4, 7);
  b[26] = 0.5 * (sum(8, 19) - 1.25 * sum(0, 7));
  return b;
}

Validity hex_bezier_validity(const Points& points, const stc::Hex& h, int max_depth) {
  return validity_of(corners_of(points, h), max_depth);
}

ValidityCounts count_bezier_validity(const HexMesh& mesh, int max_depth) {
  ValidityCounts c;
  for (const stc::Hex& h : mesh.complex.hexes) {
    switch (hex_bezier_validity(mesh.points, h, max_depth)) {
      case Validity::Valid:
        ++c.valid;
        break;
      case Validity::Invalid:
        ++c.invalid;
        break;
      case Validity::Uncertain:
        ++c.uncertain;
        break;
    }
  }
  return c;
}

QualitySummary summarize_quality(const HexMesh& mesh, std::size_t worst_count) {
  QualitySummary s;
  s.hexes = mesh.complex.hexes.size();
  s.per_hex.reserve(s.hexes);
  double sum = 0.0;
  s.min_scaled_jacobian = s.hexes == 0 ? 0.0 : std::numeric_limits<double>::max();
  s.min_jacobian = s.hexes == 0 ? 0.0 : std::numeric_limits<double>::max();
  for (const stc::Hex& h : mesh.complex.hexes) {
    const double sj = hex_scaled_jacobian(mesh.points, h);
    s.per_hex.push_back(sj);
    s.min_scaled_jacobian = std::min(s.min_scaled_jacobian, sj);
    sum += sj;
    if (sj <= 0.0) ++s.inverted;
    if (sj < 0.0) ++s.negative;
    if (sj < 0.2) ++s.below_0_2;
    if (sj < 0.5) ++s.below_0_5;
    const double bin = std::floor((sj + 1.0) / 0.1);
    s.histogram[static_cast<std::size_t>(std::clamp(bin, 0.0, 19.0))] += 1;
    s.min_jacobian = std::min(s.min_jacobian, hex_jacobian(mesh.points, h));
    s.max_edge_ratio = std::max(s.max_edge_ratio, hex_edge_ratio(mesh.points, h));
    s.max_aspect_frobenius =
        std::max(s.max_aspect_frobenius, hex_max_aspect_frobenius(mesh.points, h));
    const std::array<double, 8> corners = hex_corner_jacobians(mesh.points, h);
    if (*std::min_element(corners.begin(), corners.end()) <= 0.0) ++s.corner_inverted;
  }
  s.mean_scaled_jacobian = s.hexes == 0 ? 0.0 : sum / static_cast<double>(s.hexes);
  if (s.hexes > 0) {
    std::vector<std::size_t> order(s.hexes);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&s](std::size_t a, std::size_t b) { return s.per_hex[a] < s.per_hex[b]; });
    for (std::size_t q = 0; q < s.quantiles.size(); ++q) {
      const double rank = QualitySummary::kQuantileLevels[q] * static_cast<double>(s.hexes - 1);
      s.quantiles[q] = s.per_hex[order[static_cast<std::size_t>(std::llround(rank))]];
    }
    for (std::size_t i = 0; i < std::min(worst_count, s.hexes); ++i) s.worst.emplace_back(order[i]);
  }
  return s;
}

}  // namespace stcweave::primal
