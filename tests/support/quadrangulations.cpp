#include "support/quadrangulations.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "support/shapes.hpp"

namespace stcweave::test {
namespace {

class Lcg {
 public:
  explicit Lcg(std::uint32_t seed) : state_(seed * 2654435761U + 12345U) {}
  std::uint32_t below(std::uint32_t n) {
    state_ = state_ * 1664525U + 1013904223U;
    return (state_ >> 8U) % n;
  }

 private:
  std::uint32_t state_;
};

using Quads = std::vector<stc::Quad>;

std::map<std::pair<std::int32_t, std::int32_t>, std::size_t> directed_edges(const Quads& quads) {
  std::map<std::pair<std::int32_t, std::int32_t>, std::size_t> e;
  for (std::size_t q = 0; q < quads.size(); ++q)
    for (std::size_t i = 0; i < 4; ++i) e[{quads[q][i].value(), quads[q][(i + 1) % 4].value()}] = q;
  return e;
}

bool has_edge(const Quads& quads, NodeId a, NodeId b) {
  for (const stc::Quad& q : quads)
    for (std::size_t i = 0; i < 4; ++i)
      if ((q[i] == a && q[(i + 1) % 4] == b) || (q[i] == b && q[(i + 1) % 4] == a)) return true;
  return false;
}

/// Rotates the edge leaving corner i of quad q (to the diagonal a1-b1, or a2-b2 when
/// `other_diagonal`); nothing when the hexagon has a repeated node or the diagonal is an edge.
std::optional<Quads> rotated(const Quads& quads, std::size_t q, std::size_t i,
                             bool other_diagonal) {
  const auto dir = directed_edges(quads);
  const stc::Quad A = quads[q];
  const NodeId u = A[i];
  const NodeId v = A[(i + 1) % 4];
  const NodeId a1 = A[(i + 2) % 4];
  const NodeId a2 = A[(i + 3) % 4];
  const auto it = dir.find({v.value(), u.value()});
  if (it == dir.end()) return std::nullopt;
  const std::size_t p = it->second;
  const stc::Quad B = quads[p];
  std::size_t j = 0;
  while (B[j] != v) ++j;
  const NodeId b1 = B[(j + 2) % 4];
  const NodeId b2 = B[(j + 3) % 4];
  const std::set<std::int32_t> six{u.value(),  v.value(),  a1.value(),
                                   a2.value(), b1.value(), b2.value()};
  if (six.size() != 6) return std::nullopt;
  Quads next = quads;
  if (!other_diagonal) {
    if (has_edge(quads, a1, b1)) return std::nullopt;
    next[q] = {a1, a2, u, b1};
    next[p] = {b1, b2, v, a1};
  } else {
    if (has_edge(quads, a2, b2)) return std::nullopt;
    next[q] = {a2, u, b1, b2};
    next[p] = {b2, v, a1, a2};
  }
  return next;
}

/// Defects against a strong quadrangulation: missing valence below 3, repeated quads and
/// quad pairs sharing two edges.
std::size_t defects(const Quads& quads, std::size_t num_nodes) {
  std::vector<int> valence(num_nodes, 0);
  for (const stc::Quad& f : quads)
    for (const NodeId n : f) ++valence[n.index()];
  std::size_t d = 0;
  for (const int v : valence)
    if (v > 0 && v < 3) d += static_cast<std::size_t>(3 - v);
  const auto dir = directed_edges(quads);
  std::map<std::pair<std::size_t, std::size_t>, int> shared;
  for (std::size_t q = 0; q < quads.size(); ++q)
    for (std::size_t i = 0; i < 4; ++i) {
      const auto it = dir.find({quads[q][(i + 1) % 4].value(), quads[q][i].value()});
      if (it != dir.end() && q < it->second && ++shared[{q, it->second}] > 1) ++d;
    }
  return d;
}

}  // namespace

bool is_strong_quadrangulation(const stc::QuadSurface& surface) {
  const Quads& quads = surface.quads;
  std::map<std::pair<std::int32_t, std::int32_t>, int> uses;
  std::vector<int> valence(surface.num_nodes, 0);
  std::set<std::array<std::int32_t, 4>> keys;
  for (const stc::Quad& q : quads) {
    std::array<std::int32_t, 4> k{q[0].value(), q[1].value(), q[2].value(), q[3].value()};
    std::sort(k.begin(), k.end());
    if (std::adjacent_find(k.begin(), k.end()) != k.end()) return false;
    if (!keys.insert(k).second) return false;
    for (std::size_t i = 0; i < 4; ++i) {
      ++uses[{q[i].value(), q[(i + 1) % 4].value()}];
      ++valence[q[i].index()];
    }
  }
  for (const auto& [e, n] : uses) {
    if (n != 1) return false;
    const auto it = uses.find({e.second, e.first});
    if (it == uses.end()) return false;
  }
  for (const int v : valence)
    if (v != 0 && v < 3) return false;
  // Two quads sharing two edges.
  std::map<std::pair<std::size_t, std::size_t>, int> shared;
  const auto dir = directed_edges(quads);
  for (std::size_t q = 0; q < quads.size(); ++q) {
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t o = dir.at({quads[q][(i + 1) % 4].value(), quads[q][i].value()});
      if (q < o && ++shared[{q, o}] > 1) return false;
    }
  }
  return true;
}

std::optional<primal::SurfaceMesh> random_quadrangulation(std::uint32_t seed, int target_quads,
                                                          int flips) {
  const primal::SurfaceMesh cube = box_surface(1, 1, 1);
  std::vector<Eigen::RowVector3d> points;
  for (Eigen::Index i = 0; i < cube.points.rows(); ++i) points.emplace_back(cube.points.row(i));
  Quads quads = cube.surface.quads;
  Lcg rng(seed);
  // Doublet splits: quad (a, b, c, d) -> (a, b, c, x), (a, x, c, d).
  while (static_cast<int>(quads.size()) < target_quads) {
    const std::size_t q = rng.below(static_cast<std::uint32_t>(quads.size()));
    const std::size_t r = rng.below(2);
    const stc::Quad f = quads[q];
    const NodeId a = f[r];
    const NodeId b = f[r + 1];
    const NodeId c = f[r + 2];
    const NodeId d = f[(r + 3) % 4];
    const NodeId x(points.size());
    Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
    for (const NodeId v : f) centre += points[v.index()];
    points.emplace_back(centre / 4.0);
    quads[q] = {a, b, c, x};
    quads.push_back({a, x, c, d});
  }
  // Edge rotations: quads (u, v, a1, a2) and (v, u, b1, b2), hexagon v a1 a2 u b1 b2.
  for (int step = 0; step < flips; ++step) {
    const std::size_t q = rng.below(static_cast<std::uint32_t>(quads.size()));
    const std::size_t i = rng.below(4);
    const bool other_diagonal = rng.below(2) == 1;
    if (auto next = rotated(quads, q, i, other_diagonal)) quads = std::move(*next);
  }
  // Repair: rotations that lower the defects, first found in a scan from a random start.
  for (int round = 0; round < 64; ++round) {
    const std::size_t d = defects(quads, points.size());
    if (d == 0) break;
    const std::size_t n = quads.size() * 8;
    const std::size_t start = rng.below(static_cast<std::uint32_t>(n));
    bool done = false;
    for (std::size_t k = 0; k < n && !done; ++k) {
      const std::size_t c = (start + k) % n;
      auto next = rotated(quads, c / 8, (c / 2) % 4, c % 2 == 1);
      if (next && defects(*next, points.size()) < d) {
        quads = std::move(*next);
        done = true;
      }
    }
    if (!done) break;
  }
  primal::SurfaceMesh mesh;
  mesh.surface.quads = quads;
  mesh.surface.num_nodes = points.size();
  mesh.points.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t n = 0; n < points.size(); ++n)
    mesh.points.row(static_cast<Eigen::Index>(n)) = points[n];
  if (!is_strong_quadrangulation(mesh.surface)) return std::nullopt;
  return mesh;
}

std::optional<primal::SurfaceMesh> rotate_edge(const primal::SurfaceMesh& mesh, std::size_t quad,
                                               std::size_t corner, bool other_diagonal) {
  auto quads = rotated(mesh.surface.quads, quad, corner, other_diagonal);
  if (!quads) return std::nullopt;
  primal::SurfaceMesh out = mesh;
  out.surface.quads = std::move(*quads);
  if (!is_strong_quadrangulation(out.surface)) return std::nullopt;
  return out;
}

}  // namespace stcweave::test
