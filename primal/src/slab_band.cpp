#include "slab_band.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <set>
#include <tuple>
#include <utility>

#include "stcweave/stc/surface_topology.hpp"

namespace stcweave::primal {
namespace {

constexpr std::size_t kNone = static_cast<std::size_t>(-1);

/// Roots of the breadth-first trees `far_bands` grows: the nodes farthest from the cycle.
constexpr std::size_t kRoots = 4;
/// Fundamental cycles checked per root, shortest first.
constexpr std::size_t kCandidatesPerRoot = 80;

/// The undirected edge {x, y} as an ordered pair.
std::pair<NodeId, NodeId> undirected(NodeId x, NodeId y) {
  return x < y ? std::make_pair(x, y) : std::make_pair(y, x);
}

/// Sorted neighbour lists of the surface's edge graph.
std::vector<std::vector<std::size_t>> edge_graph(const stc::QuadSurface& surface) {
  std::vector<std::vector<std::size_t>> adj(surface.num_nodes);
  for (const stc::Quad& q : surface.quads) {
    for (std::size_t i = 0; i < 4; ++i) {
      adj[q[i].index()].push_back(q[(i + 1) % 4].index());
      adj[q[(i + 1) % 4].index()].push_back(q[i].index());
    }
  }
  for (auto& list : adj) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return adj;
}

}  // namespace

std::optional<SlabBand> band_between(const stc::QuadSurface& surface,
                                     const std::vector<NodeId>& cycle,
                                     const std::vector<NodeId>& partner) {
  if (cycle.size() < 3 || partner.size() < 3) return std::nullopt;
  std::vector<char> on_cycle(surface.num_nodes, 0);
  for (NodeId v : cycle) on_cycle[v.index()] = 1;
  for (NodeId v : partner)
    if (on_cycle[v.index()] != 0) return std::nullopt;
  std::set<std::pair<NodeId, NodeId>> barrier;
  std::set<std::pair<NodeId, NodeId>> cycle_forward;
  std::set<std::pair<NodeId, NodeId>> cycle_backward;
  for (std::size_t k = 0; k < cycle.size(); ++k) {
    const NodeId a = cycle[k];
    const NodeId b = cycle[(k + 1) % cycle.size()];
    barrier.insert(undirected(a, b));
    cycle_forward.emplace(a, b);
    cycle_backward.emplace(b, a);
  }
  std::set<std::pair<NodeId, NodeId>> partner_edges;
  for (std::size_t k = 0; k < partner.size(); ++k) {
    const auto e = undirected(partner[k], partner[(k + 1) % partner.size()]);
    barrier.insert(e);
    partner_edges.insert(e);
  }
  const stc::SurfaceTopology topo = stc::surface_topology(surface);
  const std::size_t nq = surface.num_quads();
  std::vector<char> in_band(nq, 0);
  std::deque<std::size_t> queue;
  for (std::size_t q = 0; q < nq; ++q) {
    for (std::size_t i = 0; i < 4; ++i) {
      const auto side = std::make_pair(surface.quads[q][i], surface.quads[q][(i + 1) % 4]);
      if (cycle_forward.count(side) != 0) continue;
      if (cycle_backward.count(side) != 0 && in_band[q] == 0) {
        in_band[q] = 1;
        queue.push_back(q);
      }
    }
  }
  while (!queue.empty()) {
    const std::size_t q = queue.front();
    queue.pop_front();
    for (int i = 0; i < 4; ++i) {
      const stc::Quad& quad = surface.quads[q];
      const auto side = std::make_pair(quad[static_cast<std::size_t>(i)],
                                       quad[static_cast<std::size_t>((i + 1) % 4)]);
      if (cycle_forward.count(side) != 0) return std::nullopt;  // reached the other side
      if (barrier.count(undirected(side.first, side.second)) != 0) continue;
      const stc::QuadSide across = topo.neighbour(stc::QuadSide{QuadId(q), i});
      if (!across.is_valid()) return std::nullopt;
      const std::size_t r = across.quad.index();
      if (in_band[r] != 0) continue;
      in_band[r] = 1;
      queue.push_back(r);
    }
  }
  SlabBand band;
  std::map<NodeId, NodeId> next;
  std::size_t cycle_sides = 0;
  for (std::size_t q = 0; q < nq; ++q) {
    if (in_band[q] == 0) continue;
    band.quads.push_back(q);
    const stc::Quad& quad = surface.quads[q];
    for (std::size_t i = 0; i < 4; ++i) {
      const NodeId x = quad[i];
      const NodeId y = quad[(i + 1) % 4];
      if (cycle_forward.count({x, y}) != 0) return std::nullopt;
      if (cycle_backward.count({x, y}) != 0) {
        ++cycle_sides;
        continue;
      }
      if (partner_edges.count(undirected(x, y)) == 0) continue;
      if (!next.emplace(x, y).second) return std::nullopt;  // pinched
    }
  }
  if (cycle_sides != cycle.size() || next.size() != partner.size()) return std::nullopt;
  if (band.quads.size() == nq) return std::nullopt;
  // Each partner edge once: a partner edge with both its quads in the band does not bound it.
  std::set<std::pair<NodeId, NodeId>> seen;
  for (const auto& [x, y] : next)
    if (!seen.insert(undirected(x, y)).second) return std::nullopt;
  NodeId v = partner.front();
  for (std::size_t k = 0; k < partner.size(); ++k) {
    band.outer.push_back(v);
    const auto it = next.find(v);
    if (it == next.end()) return std::nullopt;
    v = it->second;
  }
  if (v != band.outer.front()) return std::nullopt;
  return band;
}

std::vector<SlabBand> far_bands(const stc::QuadSurface& surface, const std::vector<NodeId>& cycle,
                                std::size_t max_bands) {
  const std::size_t n = surface.num_nodes;
  const std::vector<std::vector<std::size_t>> adj = edge_graph(surface);
  // Distances from the cycle.
  std::vector<std::size_t> dist(n, kNone);
  std::deque<std::size_t> queue;
  for (NodeId v : cycle) {
    dist[v.index()] = 0;
    queue.push_back(v.index());
  }
  while (!queue.empty()) {
    const std::size_t v = queue.front();
    queue.pop_front();
    for (std::size_t w : adj[v]) {
      if (dist[w] != kNone) continue;
      dist[w] = dist[v] + 1;
      queue.push_back(w);
    }
  }
  std::vector<std::size_t> order;
  for (std::size_t v = 0; v < n; ++v)
    if (dist[v] != kNone && dist[v] > 0 && !adj[v].empty()) order.push_back(v);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(dist[b], a) < std::tie(dist[a], b);
  });
  if (order.size() > kRoots) order.resize(kRoots);

  struct Found {
    std::size_t smaller = 0;  ///< quads on the smaller side
    SlabBand band;
  };
  std::vector<Found> found;
  std::set<std::vector<NodeId>> seen;
  const std::size_t nq = surface.num_quads();
  for (std::size_t root : order) {
    std::vector<std::size_t> parent(n, kNone);
    std::vector<std::size_t> depth(n, kNone);
    depth[root] = 0;
    queue.assign(1, root);
    while (!queue.empty()) {
      const std::size_t v = queue.front();
      queue.pop_front();
      for (std::size_t w : adj[v]) {
        if (dist[w] == 0 || depth[w] != kNone) continue;
        depth[w] = depth[v] + 1;
        parent[w] = v;
        queue.push_back(w);
      }
    }
    // Non-tree edges, their fundamental cycle's length bounded by depth[u] + depth[w] + 1.
    std::vector<std::tuple<std::size_t, std::size_t, std::size_t>> candidates;
    for (std::size_t u = 0; u < n; ++u) {
      if (depth[u] == kNone) continue;
      for (std::size_t w : adj[u]) {
        if (w <= u || depth[w] == kNone || parent[w] == u || parent[u] == w) continue;
        candidates.emplace_back(depth[u] + depth[w] + 1, u, w);
      }
    }
    std::sort(candidates.begin(), candidates.end());
    std::size_t checked = 0;
    for (const auto& [bound, u, w] : candidates) {
      if (checked == kCandidatesPerRoot) break;
      // The tree paths from u and w up to their lowest common ancestor.
      std::vector<std::size_t> up_u{u};
      std::vector<std::size_t> up_w{w};
      std::size_t a = u;
      std::size_t b = w;
      while (a != b) {
        if (depth[a] >= depth[b]) {
          a = parent[a];
          up_u.push_back(a);
        } else {
          b = parent[b];
          up_w.push_back(b);
        }
      }
      up_w.pop_back();  // the common ancestor is the end of up_u
      std::vector<NodeId> cyc;
      cyc.reserve(up_u.size() + up_w.size());
      for (std::size_t x : up_u) cyc.push_back(NodeId(x));
      for (auto it = up_w.rbegin(); it != up_w.rend(); ++it) cyc.push_back(NodeId(*it));
      if (cyc.size() < 4) continue;
      std::vector<NodeId> key = cyc;
      std::sort(key.begin(), key.end());
      if (!seen.insert(key).second) continue;
      ++checked;
      std::optional<SlabBand> band = band_between(surface, cycle, cyc);
      if (!band) continue;
      const std::size_t smaller = std::min(band->quads.size(), nq - band->quads.size());
      found.push_back(Found{smaller, std::move(*band)});
    }
  }
  std::stable_sort(found.begin(), found.end(), [](const Found& p, const Found& q) {
    // The even split per partner edge first (p.smaller / |p| > q.smaller / |q|).
    const std::size_t lp = p.smaller * q.band.outer.size();
    const std::size_t lq = q.smaller * p.band.outer.size();
    if (lp != lq) return lp > lq;
    return p.band.outer.size() < q.band.outer.size();
  });
  std::vector<SlabBand> out;
  out.reserve(std::min(max_bands, found.size()));
  for (Found& f : found) {
    if (out.size() == max_bands) break;
    out.push_back(std::move(f.band));
  }
  return out;
}

}  // namespace stcweave::primal
