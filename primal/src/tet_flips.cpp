#include "tet_flips.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace stcweave::primal {

namespace {

/// Each vertex with the other three in an order that keeps a positive tet positive.
constexpr std::array<std::array<int, 4>, 4> kCorners{
    {{0, 1, 2, 3}, {1, 0, 3, 2}, {2, 3, 0, 1}, {3, 2, 1, 0}}};

Eigen::Vector3d at(const Points& points, NodeId n) {
  return points.row(n.value()).transpose();
}

}  // namespace

double tet_volume6(const Points& points, const stc::Tet& tet) {
  const Eigen::Vector3d o = at(points, tet[0]);
  return (at(points, tet[1]) - o).dot((at(points, tet[2]) - o).cross(at(points, tet[3]) - o));
}

double tet_corner_quality(const Points& points, const stc::Tet& tet) {
  double worst = INFINITY;
  for (const auto& k : kCorners) {
    const Eigen::Vector3d o = at(points, tet[static_cast<std::size_t>(k[0])]);
    const Eigen::Vector3d e1 = at(points, tet[static_cast<std::size_t>(k[1])]) - o;
    const Eigen::Vector3d e2 = at(points, tet[static_cast<std::size_t>(k[2])]) - o;
    const Eigen::Vector3d e3 = at(points, tet[static_cast<std::size_t>(k[3])]) - o;
    const double lengths = e1.norm() * e2.norm() * e3.norm();
    const double q = lengths > 0.0 ? e1.dot(e2.cross(e3)) / lengths : 0.0;
    worst = std::min(worst, q);
  }
  return worst;
}

TetFlips flip_tets(const Points& points, std::vector<stc::Tet>& tets, double floor) {
  TetFlips done;
  std::vector<double> quality(tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t) quality[t] = tet_corner_quality(points, tets[t]);
  for (bool changed = true; changed;) {
    changed = false;
    ++done.passes;
    // Every edge with its tets, sorted by the edge's end nodes, then by tet.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
    edges.reserve(6 * tets.size());
    for (std::size_t t = 0; t < tets.size(); ++t) {
      for (std::size_t i = 0; i < 4; ++i) {
        for (std::size_t j = i + 1; j < 4; ++j) {
          const auto a = static_cast<std::uint64_t>(std::min(tets[t][i], tets[t][j]).value());
          const auto b = static_cast<std::uint64_t>(std::max(tets[t][i], tets[t][j]).value());
          edges.emplace_back((a << 32U) | b, static_cast<std::uint32_t>(t));
        }
      }
    }
    std::sort(edges.begin(), edges.end());
    std::vector<char> touched(tets.size(), 0);
    std::vector<stc::Tet> added;
    std::vector<double> added_quality;
    for (std::size_t lo = 0; lo < edges.size();) {
      std::size_t hi = lo;
      while (hi < edges.size() && edges[hi].first == edges[lo].first) ++hi;
      const std::size_t count = hi - lo;
      const std::size_t first = lo;
      lo = hi;
      if (count != 3) continue;
      const NodeId a(static_cast<std::size_t>(edges[first].first >> 32U));
      const NodeId b(static_cast<std::size_t>(edges[first].first & 0xffffffffU));
      std::array<std::uint32_t, 3> around{};
      bool free = true;
      for (std::size_t k = 0; k < 3; ++k) {
        around[k] = edges[first + k].second;
        free = free && touched[around[k]] == 0;
      }
      if (!free) continue;
      // The ring: the other two vertices of each tet; closed when each appears twice.
      std::array<NodeId, 6> pairs{};
      for (std::size_t k = 0; k < 3; ++k) {
        std::size_t p = 0;
        for (const NodeId v : tets[around[k]])
          if (v != a && v != b) pairs[2 * k + p++] = v;
      }
      std::array<NodeId, 3> ring{pairs[0], pairs[1], NodeId::invalid()};
      for (std::size_t k = 2; k < 6; ++k)
        if (pairs[k] != ring[0] && pairs[k] != ring[1]) ring[2] = pairs[k];
      if (!ring[2].is_valid()) continue;
      bool closed = true;
      for (const NodeId r : ring) closed = closed && std::count(pairs.begin(), pairs.end(), r) == 2;
      if (!closed) continue;  // a boundary edge: its tets make an open fan
      const double side_a = tet_volume6(points, {ring[0], ring[1], ring[2], a});
      const double side_b = tet_volume6(points, {ring[0], ring[1], ring[2], b});
      if (!(side_a * side_b < 0.0)) continue;  // the edge does not pierce the ring's triangle
      stc::Tet ta{a, ring[0], ring[1], ring[2]};
      stc::Tet tb{b, ring[0], ring[2], ring[1]};
      if (side_a > 0.0) {  // (r0, r1, r2, a) positive means (a, r0, r1, r2) is negative
        std::swap(ta[2], ta[3]);
        std::swap(tb[2], tb[3]);
      }
      const double qa = tet_corner_quality(points, ta);
      const double qb = tet_corner_quality(points, tb);
      const double before = std::min({quality[around[0]], quality[around[1]], quality[around[2]]});
      if (qa <= 0.0 || qb <= 0.0 || std::min(qa, qb) < std::min(before, floor)) continue;
      for (const std::uint32_t t : around) touched[t] = 1;
      added.push_back(ta);
      added.push_back(tb);
      added_quality.push_back(qa);
      added_quality.push_back(qb);
      ++done.flips;
      changed = true;
    }
    std::size_t kept = 0;
    for (std::size_t t = 0; t < tets.size(); ++t) {
      if (touched[t] != 0) continue;
      tets[kept] = tets[t];
      quality[kept] = quality[t];
      ++kept;
    }
    tets.resize(kept);
    quality.resize(kept);
    tets.insert(tets.end(), added.begin(), added.end());
    quality.insert(quality.end(), added_quality.begin(), added_quality.end());
  }
  return done;
}

}  // namespace stcweave::primal
