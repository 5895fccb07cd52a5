#include "surface_crossings.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace stcweave::primal {
namespace {

using Vec = Eigen::Vector3d;
using Triangle = std::array<Vec, 3>;

/// The sign of `x` with |x| <= tol read as 0.
int sign_of(double x, double tol) {
  if (x > tol) return 1;
  if (x < -tol) return -1;
  return 0;
}

/// Six times the signed volume of the tetrahedron (a, b, c, d).
double orient(const Vec& a, const Vec& b, const Vec& c, const Vec& d) {
  return (b - a).cross(c - a).dot(d - a);
}

/// Whether segment pq passes through triangle t: p and q strictly on the two sides of its
/// plane, and the line pq through the closed triangle (its edges included, so that a segment
/// through the edge two triangles share, or through a quad's diagonal, counts).
bool segment_crosses(const Vec& p, const Vec& q, const Triangle& t, double tol) {
  const int sp = sign_of(orient(t[0], t[1], t[2], p), tol);
  const int sq = sign_of(orient(t[0], t[1], t[2], q), tol);
  if (sp == 0 || sp != -sq) return false;
  const int u = sign_of(orient(p, q, t[0], t[1]), tol);
  const int v = sign_of(orient(p, q, t[1], t[2]), tol);
  const int w = sign_of(orient(p, q, t[2], t[0]), tol);
  const bool none_negative = u >= 0 && v >= 0 && w >= 0;
  const bool none_positive = u <= 0 && v <= 0 && w <= 0;
  return (none_negative || none_positive) && (u != 0 || v != 0 || w != 0);
}

/// Whether two triangles cross: where two triangles meet transversally, each end of the
/// segment they share is where an edge of one passes through the other. (Both ends may lie on
/// edges of both: hence closed triangles above.)
bool triangles_cross(const Triangle& a, const Triangle& b, double tol) {
  for (int i = 0; i < 3; ++i) {
    if (segment_crosses(a[i], a[(i + 1) % 3], b, tol)) return true;
    if (segment_crosses(b[i], b[(i + 1) % 3], a, tol)) return true;
  }
  return false;
}

/// The two triangles of quad (c0, c1, c2, c3) split along diagonal 0-2 (`split` 0) or 1-3.
std::array<Triangle, 2> halves(const std::array<Vec, 4>& c, int split) {
  if (split == 0) return {Triangle{c[0], c[1], c[2]}, Triangle{c[0], c[2], c[3]}};
  return {Triangle{c[1], c[2], c[3]}, Triangle{c[1], c[3], c[0]}};
}

/// Whether the quads cross under every choice of their diagonals (so a warped quad's split
/// alone never makes a crossing).
bool quads_cross(const std::array<Vec, 4>& a, const std::array<Vec, 4>& b, double tol) {
  for (int sa = 0; sa < 2; ++sa) {
    for (int sb = 0; sb < 2; ++sb) {
      bool any = false;
      for (const Triangle& ta : halves(a, sa))
        for (const Triangle& tb : halves(b, sb)) any = any || triangles_cross(ta, tb, tol);
      if (!any) return false;
    }
  }
  return true;
}

struct Box {
  Vec lo, hi;
  [[nodiscard]] bool overlaps(const Box& o) const {
    return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all();
  }
};

}  // namespace

std::vector<std::array<QuadId, 2>> crossing_quads(const Points& points,
                                                  const stc::QuadSurface& surface) {
  const std::size_t n = surface.quads.size();
  std::vector<std::array<QuadId, 2>> out;
  if (n < 2) return out;
  std::vector<std::array<Vec, 4>> corners(n);
  std::vector<Box> boxes(n);
  double size_sum = 0.0;
  Vec lo_all = Vec::Constant(std::numeric_limits<double>::infinity());
  for (std::size_t q = 0; q < n; ++q) {
    for (std::size_t i = 0; i < 4; ++i)
      corners[q][i] = points.row(surface.quads[q][i].value()).transpose();
    Box& b = boxes[q];
    b.lo = b.hi = corners[q][0];
    for (std::size_t i = 1; i < 4; ++i) {
      b.lo = b.lo.cwiseMin(corners[q][i]);
      b.hi = b.hi.cwiseMax(corners[q][i]);
    }
    size_sum += (b.hi - b.lo).maxCoeff();
    lo_all = lo_all.cwiseMin(b.lo);
  }
  // Cells about twice the mean quad size; a quad goes into every cell its box meets, and a
  // quad that would meet more than kMaxCells cells is compared with every other quad instead.
  constexpr std::int64_t kMaxCells = 64;
  const double cell =
      std::max(2.0 * size_sum / static_cast<double>(n), std::numeric_limits<double>::min());
  const auto index_of = [&](double x, double lo) {
    return static_cast<std::int64_t>(std::floor((x - lo) / cell));
  };
  // Cells keyed by their three indices packed into one integer (21 bits each; a surface of
  // quads of one order of size spans far fewer cells).
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;
  std::vector<std::uint32_t> big;
  for (std::size_t q = 0; q < n; ++q) {
    std::array<std::int64_t, 3> a{}, b{};
    for (int k = 0; k < 3; ++k) {
      a[k] = index_of(boxes[q].lo[k], lo_all[k]);
      b[k] = index_of(boxes[q].hi[k], lo_all[k]);
    }
    const std::int64_t count = (b[0] - a[0] + 1) * (b[1] - a[1] + 1) * (b[2] - a[2] + 1);
    if (count > kMaxCells || b[0] >= (1 << 21) || b[1] >= (1 << 21) || b[2] >= (1 << 21)) {
      big.push_back(static_cast<std::uint32_t>(q));
      continue;
    }
    for (std::int64_t i = a[0]; i <= b[0]; ++i) {
      for (std::int64_t j = a[1]; j <= b[1]; ++j) {
        for (std::int64_t k = a[2]; k <= b[2]; ++k) {
          cells[(static_cast<std::uint64_t>(i) << 42) | (static_cast<std::uint64_t>(j) << 21) |
                static_cast<std::uint64_t>(k)]
              .push_back(static_cast<std::uint32_t>(q));
        }
      }
    }
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> candidates;
  for (const auto& [key, list] : cells) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      for (std::size_t j = i + 1; j < list.size(); ++j)
        candidates.emplace_back(std::min(list[i], list[j]), std::max(list[i], list[j]));
    }
  }
  for (const std::uint32_t q : big) {
    for (std::size_t r = 0; r < n; ++r) {
      if (r == q) continue;
      candidates.emplace_back(std::min<std::uint32_t>(q, static_cast<std::uint32_t>(r)),
                              std::max<std::uint32_t>(q, static_cast<std::uint32_t>(r)));
    }
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());

  for (const auto& [a, b] : candidates) {
    if (!boxes[a].overlaps(boxes[b])) continue;
    const stc::Quad& qa = surface.quads[a];
    const stc::Quad& qb = surface.quads[b];
    bool shared = false;
    for (const NodeId u : qa)
      for (const NodeId v : qb) shared = shared || u == v;
    if (shared) continue;
    // The tolerance on six times a volume: 1e-9 of the cube of the pair's size.
    const Vec lo = boxes[a].lo.cwiseMin(boxes[b].lo);
    const Vec hi = boxes[a].hi.cwiseMax(boxes[b].hi);
    const double span = (hi - lo).maxCoeff();
    const double tol = 1e-9 * span * span * span;
    if (quads_cross(corners[a], corners[b], tol))
      out.push_back({QuadId(static_cast<std::size_t>(a)), QuadId(static_cast<std::size_t>(b))});
  }
  return out;
}

}  // namespace stcweave::primal
