#include "stcweave/stc/surface_topology.hpp"

#include <algorithm>
#include <numeric>
#include <string>

#include "stcweave/stc/errors.hpp"
#include "union_find.hpp"

namespace stcweave::stc {
namespace {

using detail::UnionFind;

constexpr std::size_t kNone = static_cast<std::size_t>(-1);

/// The corner (4*quad + i) of `use`'s quad at node `v`, `v` being an end of the side.
std::size_t corner_at(const QuadSurface& surface, QuadSide use, NodeId v) {
  const Quad& q = surface.quad(use.quad);
  const int i = q[static_cast<std::size_t>(use.side)] == v ? use.side : (use.side + 1) % 4;
  return 4 * use.quad.index() + static_cast<std::size_t>(i);
}

}  // namespace

std::optional<int> SurfaceTopology::genus() const {
  int total = 0;
  for (const ComponentTopology& c : components) {
    if (!c.genus) return std::nullopt;
    total += *c.genus;
  }
  return total;
}

/*
 * surface_topology: what it guarantees and how.
 *
 * Edges: every non-degenerate quad side is keyed by its sorted node pair; one sort groups
 * the sides of each edge, so edge ids follow (a, b) order and are deterministic.
 * Node fans: the corners of a node are united across every edge at the node (and within a
 * quad that repeats the node); a node whose corners form more than one class is
 * non-manifold. This is the usual link test: the quads around a manifold node are one fan.
 * Orientation: a breadth-first walk across manifold edges decides for each quad whether it
 * must be reversed so that both quads of the edge traverse it in opposite directions; a
 * contradiction proves the component non-orientable (an edge on a Moebius-like cycle).
 */
SurfaceTopology surface_topology(const QuadSurface& surface) {
  const std::size_t num_quads = surface.num_quads();
  SurfaceTopology topo;

  // Node ids in range, nodes used, degenerate quads.
  std::vector<char> used(surface.num_nodes, 0);
  for (std::size_t q = 0; q < num_quads; ++q) {
    const Quad& quad = surface.quads[q];
    for (NodeId v : quad) {
      if (!v.is_valid() || v.index() >= surface.num_nodes) {
        throw InvalidInput("quad " + QuadId(q).str() + " refers to node " + v.str() +
                           " but the surface has " + std::to_string(surface.num_nodes) +
                           " nodes: fix the connectivity of the input file");
      }
      used[v.index()] = 1;
    }
    bool repeated = false;
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = i + 1; j < 4; ++j) repeated = repeated || quad[i] == quad[j];
    if (repeated) topo.degenerate_quads.push_back(QuadId(q));
  }
  topo.num_nodes_used =
      static_cast<std::size_t>(std::count(used.begin(), used.end(), static_cast<char>(1)));

  // Edges: sort the non-degenerate sides by their sorted node pair.
  struct SideKey {
    NodeId a, b;
    std::size_t side;  // flat side index
  };
  std::vector<SideKey> keys;
  keys.reserve(4 * num_quads);
  for (std::size_t q = 0; q < num_quads; ++q) {
    const Quad& quad = surface.quads[q];
    for (std::size_t i = 0; i < 4; ++i) {
      NodeId u = quad[i], v = quad[(i + 1) % 4];
      if (u == v) continue;
      if (v < u) std::swap(u, v);
      keys.push_back({u, v, 4 * q + i});
    }
  }
  std::sort(keys.begin(), keys.end(), [](const SideKey& x, const SideKey& y) {
    if (x.a != y.a) return x.a < y.a;
    if (x.b != y.b) return x.b < y.b;
    return x.side < y.side;
  });
  topo.side_edges.assign(4 * num_quads, EdgeId::invalid());
  topo.neighbours.assign(4 * num_quads, QuadSide{});
  topo.edge_uses.reserve(keys.size());
  for (std::size_t k = 0; k < keys.size();) {
    std::size_t end = k;
    while (end < keys.size() && keys[end].a == keys[k].a && keys[end].b == keys[k].b) ++end;
    const EdgeId e(topo.edges.size());
    topo.edges.push_back({keys[k].a, keys[k].b, topo.edge_uses.size(), end - k});
    for (std::size_t u = k; u < end; ++u) {
      const QuadSide s{QuadId(keys[u].side / 4), static_cast<int>(keys[u].side % 4)};
      topo.edge_uses.push_back(s);
      topo.side_edges[keys[u].side] = e;
    }
    k = end;
  }

  // Classify edges; neighbours across manifold edges.
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    const EdgeId id(e);
    const auto uses = topo.uses(id);
    if (uses.size() == 1) {
      topo.open_edges.push_back(id);
    } else if (uses.size() > 2) {
      topo.nonmanifold_edges.push_back(id);
    } else {
      topo.neighbours[uses[0].index()] = uses[1];
      topo.neighbours[uses[1].index()] = uses[0];
      const auto n0 = side_nodes(surface, uses[0]);
      const auto n1 = side_nodes(surface, uses[1]);
      if (n0[0] == n1[0]) topo.inconsistent_edges.push_back(id);
    }
  }

  // Node fans: unite corners across edges and repeated nodes of one quad.
  {
    UnionFind corners(4 * num_quads);
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
      const SurfaceEdge& edge = topo.edges[e];
      const auto uses = topo.uses(EdgeId(e));
      for (NodeId v : {edge.a, edge.b}) {
        const std::size_t first = corner_at(surface, uses[0], v);
        for (std::size_t u = 1; u < uses.size(); ++u)
          corners.unite(first, corner_at(surface, uses[u], v));
      }
    }
    for (QuadId q : topo.degenerate_quads) {
      const Quad& quad = surface.quad(q);
      for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t j = i + 1; j < 4; ++j)
          if (quad[i] == quad[j]) corners.unite(4 * q.index() + i, 4 * q.index() + j);
    }
    std::vector<std::size_t> node_root(surface.num_nodes, kNone);
    std::vector<char> flagged(surface.num_nodes, 0);
    for (std::size_t c = 0; c < 4 * num_quads; ++c) {
      const NodeId v = surface.quads[c / 4][c % 4];
      const std::size_t root = corners.find(c);
      if (node_root[v.index()] == kNone) {
        node_root[v.index()] = root;
      } else if (node_root[v.index()] != root && flagged[v.index()] == 0) {
        flagged[v.index()] = 1;
      }
    }
    for (std::size_t v = 0; v < surface.num_nodes; ++v)
      if (flagged[v] != 0) topo.nonmanifold_nodes.push_back(NodeId(v));
  }

  // Connected components through shared edges (any number of uses).
  UnionFind quads(num_quads);
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    const auto uses = topo.uses(EdgeId(e));
    for (std::size_t u = 1; u < uses.size(); ++u)
      quads.unite(uses[0].quad.index(), uses[u].quad.index());
  }
  topo.quad_components.assign(num_quads, ComponentId::invalid());
  {
    std::vector<std::size_t> root_component(num_quads, kNone);
    for (std::size_t q = 0; q < num_quads; ++q) {
      const std::size_t root = quads.find(q);
      if (root_component[root] == kNone) {
        root_component[root] = topo.components.size();
        topo.components.emplace_back();
      }
      topo.quad_components[q] = ComponentId(root_component[root]);
    }
  }

  // Orientation: breadth-first propagation across manifold edges.
  topo.orientation_flips.assign(num_quads, false);
  std::vector<EdgeId> conflict_edge(topo.components.size(), EdgeId::invalid());
  {
    std::vector<char> seen(num_quads, 0);
    std::vector<std::size_t> queue;
    queue.reserve(num_quads);
    for (std::size_t start = 0; start < num_quads; ++start) {
      if (seen[start] != 0) continue;
      seen[start] = 1;
      queue.clear();
      queue.push_back(start);
      for (std::size_t head = 0; head < queue.size(); ++head) {
        const std::size_t f = queue[head];
        for (int i = 0; i < 4; ++i) {
          const QuadSide s{QuadId(f), i};
          const QuadSide t = topo.neighbour(s);
          if (!t.is_valid()) continue;
          const auto ns = side_nodes(surface, s);
          const auto nt = side_nodes(surface, t);
          const bool same_direction = ns[0] == nt[0];
          // reversed(f) xor reversed(g) must equal same_direction.
          const bool want = topo.orientation_flips[f] != same_direction;
          const std::size_t g = t.quad.index();
          if (seen[g] == 0) {
            seen[g] = 1;
            topo.orientation_flips[g] = want;
            queue.push_back(g);
          } else if (topo.orientation_flips[g] != want) {
            const std::size_t c = topo.quad_components[f].index();
            if (!conflict_edge[c].is_valid()) conflict_edge[c] = topo.edge_of(s);
          }
        }
      }
    }
  }
  for (std::size_t c = 0; c < topo.components.size(); ++c)
    if (conflict_edge[c].is_valid()) topo.orientation_conflicts.push_back(conflict_edge[c]);

  // Per-component figures.
  {
    std::vector<std::size_t> node_component(surface.num_nodes, kNone);
    for (std::size_t q = 0; q < num_quads; ++q) {
      ComponentTopology& comp = topo.components[topo.quad_components[q].index()];
      ++comp.num_quads;
      for (NodeId v : surface.quads[q]) {
        if (node_component[v.index()] == kNone) {
          node_component[v.index()] = topo.quad_components[q].index();
          ++comp.num_nodes;
        }
      }
    }
    for (const SurfaceEdge& edge : topo.edges)
      ++topo.components[topo.quad_components[topo.edge_uses[edge.first_use].quad.index()].index()]
            .num_edges;
    std::vector<char> open(topo.components.size(), 0), nonmanifold(topo.components.size(), 0),
        inconsistent(topo.components.size(), 0);
    const auto component_of_edge = [&](EdgeId e) {
      return topo.quad_components[topo.edge_uses[topo.edge(e).first_use].quad.index()].index();
    };
    for (EdgeId e : topo.open_edges) open[component_of_edge(e)] = 1;
    for (EdgeId e : topo.nonmanifold_edges) nonmanifold[component_of_edge(e)] = 1;
    for (EdgeId e : topo.inconsistent_edges) inconsistent[component_of_edge(e)] = 1;
    // A non-manifold node may join several components (a pinch): mark each of them.
    std::vector<char> nonmanifold_node(topo.components.size(), 0);
    {
      std::vector<char> is_nm(surface.num_nodes, 0);
      for (NodeId v : topo.nonmanifold_nodes) is_nm[v.index()] = 1;
      for (std::size_t q = 0; q < num_quads; ++q)
        for (NodeId v : surface.quads[q])
          if (is_nm[v.index()] != 0) nonmanifold_node[topo.quad_components[q].index()] = 1;
    }
    std::vector<char> conflict(topo.components.size(), 0);
    for (EdgeId e : topo.orientation_conflicts) conflict[component_of_edge(e)] = 1;
    for (std::size_t c = 0; c < topo.components.size(); ++c) {
      ComponentTopology& comp = topo.components[c];
      comp.euler_characteristic = static_cast<long>(comp.num_nodes) -
                                  static_cast<long>(comp.num_edges) +
                                  static_cast<long>(comp.num_quads);
      comp.closed = open[c] == 0 && nonmanifold[c] == 0;
      comp.manifold = nonmanifold[c] == 0 && nonmanifold_node[c] == 0;
      comp.orientable = conflict[c] == 0;
      comp.consistently_oriented = inconsistent[c] == 0;
      if (comp.closed && comp.manifold && comp.orientable)
        comp.genus = static_cast<int>((2 - comp.euler_characteristic) / 2);
    }
  }
  return topo;
}

QuadSurface consistently_oriented(const QuadSurface& surface, const SurfaceTopology& topology) {
  QuadSurface out = surface;
  for (std::size_t q = 0; q < out.quads.size(); ++q)
    if (topology.orientation_flips[q]) out.quads[q] = reversed(out.quads[q]);
  return out;
}

}  // namespace stcweave::stc
