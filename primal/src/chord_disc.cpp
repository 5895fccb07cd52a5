#include "chord_disc.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace stcweave::primal {
namespace {

constexpr std::size_t kNone = static_cast<std::size_t>(-1);

/// A directed edge of the chord arrangement (a chord piece or an arc of the circle).
struct HalfEdge {
  std::size_t from = 0;
  std::size_t to = 0;
  double angle = 0.0;        ///< direction at `from`
  std::size_t arc = kNone;   ///< for an arc run counter-clockwise: the walk node it holds
  std::size_t face = kNone;  ///< face on its left
};

bool interleave(std::size_t a, std::size_t b, std::size_t c, std::size_t d) {
  // Chords (a, b) and (c, d) with a < b, c < d cross iff exactly one of c, d is in (a, b).
  const bool c_in = a < c && c < b;
  const bool d_in = a < d && d < b;
  return c_in != d_in;
}

/// The arrangement for one jitter of the endpoints, or none when degenerate.
std::optional<Disc> build(const std::vector<Eigen::RowVector3d>& cycle_points,
                          const std::vector<std::size_t>& partner, int seed) {
  const std::size_t len = partner.size();
  std::vector<Eigen::Vector2d> point;  // arrangement vertices: endpoints, then crossings
  for (std::size_t k = 0; k < len; ++k) {
    const double frac = std::fmod(static_cast<double>(k) * 0.6180339887 + seed * 0.4142135623, 1.0);
    const double phi = 2.0 * std::numbers::pi *
                       (static_cast<double>(k) + 0.5 + 0.3 * (frac - 0.5)) /
                       static_cast<double>(len);
    point.emplace_back(std::cos(phi), std::sin(phi));
  }
  // Chords from the lower endpoint, and their crossings in order along them.
  std::vector<std::pair<std::size_t, std::size_t>> chords;
  for (std::size_t k = 0; k < len; ++k)
    if (k < partner[k]) chords.emplace_back(k, partner[k]);
  std::vector<std::vector<std::pair<double, std::size_t>>> along(chords.size());
  for (std::size_t i = 0; i < chords.size(); ++i) {
    for (std::size_t j = i + 1; j < chords.size(); ++j) {
      const auto [a, b] = chords[i];
      const auto [c, d] = chords[j];
      if (!interleave(a, b, c, d)) continue;
      const Eigen::Vector2d p = point[a];
      const Eigen::Vector2d r = point[b] - p;
      const Eigen::Vector2d q = point[c];
      const Eigen::Vector2d s = point[d] - q;
      const double den = r.x() * s.y() - r.y() * s.x();
      if (std::abs(den) < 1e-12) return std::nullopt;
      const Eigen::Vector2d qp = q - p;
      const double t = (qp.x() * s.y() - qp.y() * s.x()) / den;
      const double u = (qp.x() * r.y() - qp.y() * r.x()) / den;
      const std::size_t x = point.size();
      point.push_back(p + t * r);
      along[i].emplace_back(t, x);
      along[j].emplace_back(u, x);
    }
  }
  for (auto& list : along) {
    std::sort(list.begin(), list.end());
    for (std::size_t k = 1; k < list.size(); ++k)
      if (list[k].first - list[k - 1].first < 1e-7) return std::nullopt;  // a triple point
  }
  // Half-edges: chord pieces both ways, arcs both ways.
  std::vector<HalfEdge> half;
  std::vector<std::vector<std::size_t>> out(point.size());
  const auto add = [&](std::size_t u, std::size_t v, double angle_u, double angle_v,
                       std::size_t arc) {
    out[u].push_back(half.size());
    half.push_back(HalfEdge{u, v, angle_u, arc, kNone});
    out[v].push_back(half.size());
    half.push_back(HalfEdge{v, u, angle_v, kNone, kNone});
  };
  for (std::size_t i = 0; i < chords.size(); ++i) {
    std::vector<std::size_t> seq{chords[i].first};
    for (const auto& [t, x] : along[i]) seq.push_back(x);
    seq.push_back(chords[i].second);
    for (std::size_t k = 0; k + 1 < seq.size(); ++k) {
      const Eigen::Vector2d d = point[seq[k + 1]] - point[seq[k]];
      add(seq[k], seq[k + 1], std::atan2(d.y(), d.x()), std::atan2(-d.y(), -d.x()), kNone);
    }
  }
  for (std::size_t k = 0; k < len; ++k) {
    const std::size_t k1 = (k + 1) % len;
    const Eigen::Vector2d tk(-point[k].y(), point[k].x());     // counter-clockwise tangent
    const Eigen::Vector2d tk1(point[k1].y(), -point[k1].x());  // clockwise tangent at k1
    add(k, k1, std::atan2(tk.y(), tk.x()), std::atan2(tk1.y(), tk1.x()), k1);
  }
  for (auto& list : out) {
    std::sort(list.begin(), list.end(),
              [&](std::size_t x, std::size_t y) { return half[x].angle < half[y].angle; });
  }
  // Position of each half-edge in its origin's counter-clockwise order, and its twin.
  std::vector<std::size_t> rank(half.size());
  for (const auto& list : out)
    for (std::size_t k = 0; k < list.size(); ++k) rank[list[k]] = k;
  const auto twin = [](std::size_t h) { return h ^ 1U; };
  // Faces: after arriving at v by h, leave by the edge clockwise next to h's twin.
  std::size_t faces = 0;
  std::vector<std::size_t> arcs_of_face;
  std::vector<std::size_t> arc_count;
  for (std::size_t h0 = 0; h0 < half.size(); ++h0) {
    if (half[h0].face != kNone) continue;
    const std::size_t f = faces++;
    arcs_of_face.push_back(kNone);
    arc_count.push_back(0);
    std::size_t h = h0;
    for (std::size_t guard = 0; guard <= half.size(); ++guard) {
      if (half[h].face != kNone) break;
      half[h].face = f;
      if (half[h].arc != kNone) {
        arcs_of_face[f] = half[h].arc;
        ++arc_count[f];
      }
      const std::size_t v = half[h].to;
      const std::vector<std::size_t>& list = out[v];
      const std::size_t r = rank[twin(h)];
      h = list[(r + list.size() - 1) % list.size()];
    }
    if (h != h0) return std::nullopt;
  }
  // The outer face holds every clockwise arc.
  const std::size_t outer = half[twin(half.size() - 2)].face;
  Disc disc;
  std::vector<std::size_t> node_of(faces, kNone);
  disc.walk.resize(len);
  disc.positions.resize(len);
  for (std::size_t f = 0; f < faces; ++f) {
    if (f == outer) continue;
    if (arc_count[f] > 1) return std::nullopt;  // a face touching the circle twice
    if (arc_count[f] == 1) {
      node_of[f] = arcs_of_face[f];
      disc.walk[arcs_of_face[f]] = arcs_of_face[f];
      disc.positions[arcs_of_face[f]] = cycle_points[arcs_of_face[f]];
    }
  }
  for (std::size_t f = 0; f < faces; ++f) {
    if (f == outer || node_of[f] != kNone) continue;
    node_of[f] = disc.walk.size();
    disc.walk.emplace_back(std::nullopt);
    disc.positions.emplace_back(Eigen::RowVector3d::Zero());
  }
  for (std::size_t x = len; x < point.size(); ++x) {
    const std::vector<std::size_t>& list = out[x];
    if (list.size() != 4) return std::nullopt;
    std::array<std::size_t, 4> quad{};
    for (std::size_t k = 0; k < 4; ++k) {
      const std::size_t f = half[list[k]].face;
      if (f == outer) return std::nullopt;
      quad[k] = node_of[f];
    }
    disc.quads.push_back(quad);
  }
  // Checks: distinct corners; every boundary edge p -> p+1 in one quad, forward; every other
  // edge in two quads, once each way; every interior node in at least three quads.
  std::vector<std::size_t> valence(disc.walk.size(), 0);
  std::vector<std::pair<std::pair<std::size_t, std::size_t>, int>> edges;
  for (const auto& q : disc.quads) {
    for (std::size_t k = 0; k < 4; ++k) {
      ++valence[q[k]];
      for (std::size_t j = k + 1; j < 4; ++j)
        if (q[k] == q[j]) return std::nullopt;
      const std::size_t u = q[k];
      const std::size_t v = q[(k + 1) % 4];
      edges.push_back(u < v ? std::make_pair(std::make_pair(u, v), 1)
                            : std::make_pair(std::make_pair(v, u), -1));
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t k = 0; k < edges.size();) {
    std::size_t e = k;
    int sum = 0;
    while (e < edges.size() && edges[e].first == edges[k].first) sum += edges[e++].second;
    const auto [u, v] = edges[k].first;
    const std::size_t count = e - k;
    const bool boundary = u < len && v < len && ((u + 1) % len == v || (v + 1) % len == u);
    if (boundary) {
      const int forward = (u + 1) % len == v ? 1 : -1;
      if (count != 1 || sum != forward) return std::nullopt;
    } else if (count != 2 || sum != 0) {
      return std::nullopt;
    }
    k = e;
  }
  for (std::size_t d = 0; d < disc.walk.size(); ++d) {
    if (valence[d] == 0) return std::nullopt;
    if (!disc.walk[d] && valence[d] < 3) return std::nullopt;
  }
  // Tutte embedding: every interior node at the mean of its edge neighbours.
  std::vector<std::vector<std::size_t>> neighbours(disc.walk.size());
  for (const auto& [key, sign] : edges) {
    neighbours[key.first].push_back(key.second);
    neighbours[key.second].push_back(key.first);
  }
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
  for (std::size_t p = 0; p < len; ++p) centre += cycle_points[p];
  centre /= static_cast<double>(len);
  for (std::size_t d = len; d < disc.walk.size(); ++d) {
    disc.positions[d] = centre;
    std::sort(neighbours[d].begin(), neighbours[d].end());
    neighbours[d].erase(std::unique(neighbours[d].begin(), neighbours[d].end()),
                        neighbours[d].end());
  }
  for (int sweep = 0; sweep < 400; ++sweep) {
    for (std::size_t d = len; d < disc.walk.size(); ++d) {
      Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
      for (std::size_t m : neighbours[d]) sum += disc.positions[m];
      disc.positions[d] = sum / static_cast<double>(neighbours[d].size());
    }
  }
  return disc;
}

/// An even pairing of at least 4 edges, one point per edge, an involution without fixed
/// points that pairs no two adjacent edges (such a chord would cross no other: no disc).
bool usable_pairing(const std::vector<Eigen::RowVector3d>& cycle_points,
                    const std::vector<std::size_t>& partner) {
  const std::size_t len = partner.size();
  if (len < 4 || len % 2 != 0 || cycle_points.size() != len) return false;
  for (std::size_t k = 0; k < len; ++k) {
    const std::size_t m = partner[k];
    if (m >= len || m == k || partner[m] != k) return false;
    if ((k + 1) % len == m || (m + 1) % len == k) return false;
  }
  return true;
}

/// The disc of the first of six jitters whose arrangement makes one.
std::optional<Disc> first_arrangement(const std::vector<Eigen::RowVector3d>& cycle_points,
                                      const std::vector<std::size_t>& partner) {
  for (int seed = 0; seed < 6; ++seed) {
    std::optional<Disc> disc = build(cycle_points, partner, seed);
    if (disc) return disc;
  }
  return std::nullopt;
}

}  // namespace

// Measured: every one of the 6,117 pairings the loop-following search of
// `ecm2017_cylinder_polar` completes is refused here; their six arrangements each cost 0.5 s
// in all.
bool arcs_share_a_face(const std::vector<std::size_t>& partner) {
  const std::size_t len = partner.size();
  std::vector<std::vector<bool>> sides(len);
  for (std::size_t k = 0; k < len; ++k) {
    sides[k].reserve(len / 2);
    for (std::size_t a = 0; a < len; ++a)
      if (a < partner[a]) sides[k].push_back(a <= k && k < partner[a]);
  }
  std::sort(sides.begin(), sides.end());
  return std::adjacent_find(sides.begin(), sides.end()) != sides.end();
}

std::size_t chord_crossings(const std::vector<std::size_t>& partner) {
  std::size_t count = 0;
  for (std::size_t a = 0; a < partner.size(); ++a) {
    if (partner[a] < a) continue;
    for (std::size_t c = a + 1; c < partner.size(); ++c) {
      if (partner[c] < c) continue;
      count += interleave(a, partner[a], c, partner[c]) ? 1 : 0;
    }
  }
  return count;
}

std::optional<Disc> chord_disc(const std::vector<Eigen::RowVector3d>& cycle_points,
                               const std::vector<std::size_t>& partner) {
  if (!usable_pairing(cycle_points, partner) || arcs_share_a_face(partner)) return std::nullopt;
  return first_arrangement(cycle_points, partner);
}

std::optional<Disc> arrangement_disc(const std::vector<Eigen::RowVector3d>& cycle_points,
                                     const std::vector<std::size_t>& partner) {
  if (!usable_pairing(cycle_points, partner)) return std::nullopt;
  return first_arrangement(cycle_points, partner);
}

}  // namespace stcweave::primal
