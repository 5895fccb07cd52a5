#include "stcweave/primal/handles.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <tuple>

#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/surface_topology.hpp"

namespace stcweave::primal {
namespace {

/// A set of homology generators (bit i = generator i), as 64-bit words.
using Bits = std::vector<std::uint64_t>;

void flip(Bits& b, std::size_t i) {
  b[i / 64] ^= std::uint64_t{1} << (i % 64);
}
bool test(const Bits& b, std::size_t i) {
  return ((b[i / 64] >> (i % 64)) & 1U) != 0;
}
void xor_into(Bits& a, const Bits& b) {
  for (std::size_t k = 0; k < a.size(); ++k) a[k] ^= b[k];
}
bool is_zero(const Bits& b) {
  return std::all_of(b.begin(), b.end(), [](std::uint64_t w) { return w == 0; });
}
bool odd_and(const Bits& a, const Bits& b) {
  int c = 0;
  for (std::size_t k = 0; k < a.size(); ++k) c += std::popcount(a[k] & b[k]);
  return c % 2 == 1;
}

/// Node adjacency of the surface's edges, neighbours in increasing order.
struct Graph {
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> adj;  ///< (node, edge)
};

/// A breadth-first tree from `root` over the edges of `g`.
struct Tree {
  std::vector<std::size_t> parent;       ///< node, or npos for the root / unreached
  std::vector<std::size_t> parent_edge;  ///< edge to the parent
  std::vector<std::size_t> depth;
  std::vector<std::size_t> order;  ///< nodes in visiting order
};

constexpr std::size_t kNone = static_cast<std::size_t>(-1);

/// Per class, how many roots' best cycles are kept as alternative representatives.
constexpr std::size_t kAlternativePool = 32;

/// A breadth-first tree from `root` over the edges of `g`. With `leaf`, the nodes marked in it
/// are left as leaves while the others reach the rest, then the nodes reachable only through
/// them are reached (the tree-cotree's second try round nodes of unpointed normal cone).
void grow_tree(const Graph& g, std::size_t root, Tree& t, const std::vector<char>* leaf = nullptr) {
  t.parent[root] = kNone;
  t.parent_edge[root] = kNone;
  t.depth[root] = 0;
  std::size_t head = t.order.size();
  t.order.push_back(root);
  std::vector<std::size_t> held;
  for (int phase = 0; phase < 2; ++phase) {
    if (phase == 1) {
      if (held.empty()) break;
      for (std::size_t v : held) t.order.push_back(v);
      held.clear();
    }
    while (head < t.order.size()) {
      const std::size_t v = t.order[head++];
      if (phase == 0 && leaf != nullptr && (*leaf)[v] != 0 && v != root) {
        held.push_back(v);
        continue;
      }
      for (const auto& [w, e] : g.adj[v]) {
        if (t.depth[w] != kNone) continue;
        t.depth[w] = t.depth[v] + 1;
        t.parent[w] = v;
        t.parent_edge[w] = e;
        t.order.push_back(w);
      }
    }
  }
}

/// Whether the segment a-b crosses the triangle (p, q, r) strictly inside both.
bool segment_hits_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                           const Eigen::Vector3d& r) {
  const Eigen::Vector3d dir = b - a;
  const Eigen::Vector3d e1 = q - p;
  const Eigen::Vector3d e2 = r - p;
  const Eigen::Vector3d h = dir.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-300) return false;
  const Eigen::Vector3d t = a - p;
  const double u = t.dot(h) / det;
  if (u <= 0.0 || u >= 1.0) return false;
  const Eigen::Vector3d k = t.cross(e1);
  const double w = dir.dot(k) / det;
  if (w <= 0.0 || u + w >= 1.0) return false;
  const double s = e2.dot(k) / det;
  return s > 0.0 && s < 1.0;
}

Tree empty_tree(std::size_t n) {
  Tree t;
  t.parent.assign(n, kNone);
  t.parent_edge.assign(n, kNone);
  t.depth.assign(n, kNone);
  return t;
}

/// The simple cycle made of the tree paths from u and w to their lowest common ancestor and
/// the edge u-w: lca ... u, w ... (the lca's child).
std::vector<std::size_t> tree_cycle(const Tree& t, std::size_t u, std::size_t w) {
  std::vector<std::size_t> up_u{u};
  std::vector<std::size_t> up_w{w};
  std::size_t a = u;
  std::size_t b = w;
  while (t.depth[a] > t.depth[b]) up_u.push_back(a = t.parent[a]);
  while (t.depth[b] > t.depth[a]) up_w.push_back(b = t.parent[b]);
  while (a != b) {
    up_u.push_back(a = t.parent[a]);
    up_w.push_back(b = t.parent[b]);
  }
  up_w.pop_back();  // the lca, already last of up_u
  std::vector<std::size_t> cycle(up_u.rbegin(), up_u.rend());
  cycle.insert(cycle.end(), up_w.begin(), up_w.end());
  return cycle;
}

/// Edges of the fundamental cycle of non-tree edge (u, w) in tree `t`, or kNone as soon as
/// the walk to their common ancestor shows that it has more than `limit` (kNone: always the
/// exact length): while the two walkers at depth d have not met, the ancestor is at depth
/// d - 1 or above, so the cycle has at least depth[u] + depth[w] + 1 - 2 (d - 1) edges.
std::size_t cycle_length_within(const Tree& t, std::size_t u, std::size_t w, std::size_t limit) {
  std::size_t a = u;
  std::size_t b = w;
  while (t.depth[a] > t.depth[b]) a = t.parent[a];
  while (t.depth[b] > t.depth[a]) b = t.parent[b];
  const std::size_t ends = t.depth[u] + t.depth[w] + 1;  // > 2 depth[a] - 2
  while (a != b) {
    if (ends + 2 - 2 * t.depth[a] > limit) return kNone;
    a = t.parent[a];
    b = t.parent[b];
  }
  return ends - 2 * t.depth[a];
}

/// Z2 row reduction: keeps a reduced basis, adds a vector if independent.
class Z2Basis {
 public:
  explicit Z2Basis(std::size_t bits) : words_((bits + 63) / 64) {}
  /// Reduces `v` against the basis; true (and stored) when independent.
  bool add(Bits v) {
    for (std::size_t k = 0; k < rows_.size(); ++k)
      if (test(v, pivots_[k])) xor_into(v, rows_[k]);
    if (is_zero(v)) return false;
    std::size_t p = 0;
    while (!test(v, p)) ++p;
    for (std::size_t k = 0; k < rows_.size(); ++k)
      if (test(rows_[k], p)) xor_into(rows_[k], v);
    rows_.push_back(std::move(v));
    pivots_.push_back(p);
    return true;
  }
  [[nodiscard]] std::size_t rank() const { return rows_.size(); }
  [[nodiscard]] std::size_t words() const { return words_; }

 private:
  std::size_t words_;
  std::vector<Bits> rows_;
  std::vector<std::size_t> pivots_;
};

/// Left kernel {x : x^T M = 0} of a square Z2 matrix given by its rows.
std::vector<Bits> left_kernel(const std::vector<Bits>& rows, std::size_t n) {
  // Row-reduce [M | I]: rows whose M part vanishes give the kernel.
  const std::size_t words = (n + 63) / 64;
  std::vector<std::pair<Bits, Bits>> work;
  for (std::size_t i = 0; i < n; ++i) {
    Bits id(words, 0);
    flip(id, i);
    work.emplace_back(rows[i], id);
  }
  std::size_t r = 0;
  for (std::size_t col = 0; col < n && r < n; ++col) {
    std::size_t p = r;
    while (p < n && !test(work[p].first, col)) ++p;
    if (p == n) continue;
    std::swap(work[p], work[r]);
    for (std::size_t i = 0; i < n; ++i) {
      if (i != r && test(work[i].first, col)) {
        xor_into(work[i].first, work[r].first);
        xor_into(work[i].second, work[r].second);
      }
    }
    ++r;
  }
  std::vector<Bits> kernel;
  for (std::size_t i = r; i < n; ++i) kernel.push_back(work[i].second);
  return kernel;
}

/// A closed polygon in space.
using Polygon = std::vector<Eigen::Vector3d>;

/// Crossings of `p` over `q` in the projection along `dir`, mod 2; false in `*ok` when the
/// projection is degenerate (a vertex on a segment, collinear segments, equal heights).
bool over_crossings_odd(const Polygon& p, const Polygon& q, const Eigen::Vector3d& dir, double tol,
                        bool* ok) {
  Eigen::Vector3d u = dir.unitOrthogonal();
  Eigen::Vector3d w = dir.cross(u);
  const auto proj = [&](const Eigen::Vector3d& x) { return Eigen::Vector2d(x.dot(u), x.dot(w)); };
  const auto orient = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                         const Eigen::Vector2d& c) {
    return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
  };
  std::vector<Eigen::Vector2d> p2;
  std::vector<Eigen::Vector2d> q2;
  for (const auto& x : p) p2.push_back(proj(x));
  for (const auto& x : q) q2.push_back(proj(x));
  int count = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::size_t i1 = (i + 1) % p.size();
    const Eigen::Vector2d& a = p2[i];
    const Eigen::Vector2d& b = p2[i1];
    for (std::size_t j = 0; j < q.size(); ++j) {
      const std::size_t j1 = (j + 1) % q.size();
      const Eigen::Vector2d& c = q2[j];
      const Eigen::Vector2d& d = q2[j1];
      if (std::max(a.x(), b.x()) + tol < std::min(c.x(), d.x()) ||
          std::max(c.x(), d.x()) + tol < std::min(a.x(), b.x()) ||
          std::max(a.y(), b.y()) + tol < std::min(c.y(), d.y()) ||
          std::max(c.y(), d.y()) + tol < std::min(a.y(), b.y()))
        continue;
      const double o1 = orient(a, b, c);
      const double o2 = orient(a, b, d);
      const double o3 = orient(c, d, a);
      const double o4 = orient(c, d, b);
      const double area_tol = tol * tol;
      if (std::abs(o1) < area_tol || std::abs(o2) < area_tol || std::abs(o3) < area_tol ||
          std::abs(o4) < area_tol) {
        *ok = false;
        return false;
      }
      if ((o1 > 0) == (o2 > 0) || (o3 > 0) == (o4 > 0)) continue;
      const double t = o3 / (o3 - o4);  // along a-b
      const double s = o1 / (o1 - o2);  // along c-d
      const double hp = (p[i] + t * (p[i1] - p[i])).dot(dir);
      const double hq = (q[j] + s * (q[j1] - q[j])).dot(dir);
      if (std::abs(hp - hq) < tol) {
        *ok = false;
        return false;
      }
      if (hp > hq) ++count;
    }
  }
  return count % 2 == 1;
}

}  // namespace

std::string cycle_name(const HandleCycle& cycle, const std::vector<NodeId>& names) {
  std::string s;
  for (std::size_t i = 0; i < cycle.nodes.size(); ++i) {
    if (i > 0) s += "-";
    const NodeId v = cycle.nodes[i];
    s += (v.index() < names.size() ? names[v.index()] : v).str();
  }
  return s;
}

HandleDiagnosis diagnose_handles(const SurfaceMesh& mesh, const HandleOptions& options) {
  const stc::QuadSurface& surface = mesh.surface;
  if (static_cast<std::size_t>(mesh.points.rows()) < surface.num_nodes) {
    throw InvalidInput("diagnose_handles: the surface has " + std::to_string(surface.num_nodes) +
                       " nodes but only " + std::to_string(mesh.points.rows()) + " points");
  }
  const stc::SurfaceTopology topo = stc::surface_topology(surface);
  HandleDiagnosis out;
  const std::size_t num_components = topo.components.size();
  out.genus_per_component.assign(num_components, 0);
  for (std::size_t c = 0; c < num_components; ++c) {
    if (!topo.components[c].genus) {
      out.undecided_reason = "component " + ComponentId(c).str() +
                             " is not a closed orientable manifold: its genus is undefined";
      return out;
    }
    out.genus_per_component[c] = *topo.components[c].genus;
    out.genus += *topo.components[c].genus;
  }
  if (out.genus == 0) {
    out.decided = true;
    return out;
  }

  const std::size_t n = surface.num_nodes;
  const std::size_t num_edges = topo.edges.size();
  Graph g;
  g.adj.resize(n);
  for (std::size_t e = 0; e < num_edges; ++e) {
    const auto a = topo.edges[e].a.index();
    const auto b = topo.edges[e].b.index();
    g.adj[a].emplace_back(b, e);
    g.adj[b].emplace_back(a, e);
  }
  for (auto& list : g.adj) std::sort(list.begin(), list.end());
  std::vector<std::size_t> node_component(n, kNone);
  for (std::size_t q = 0; q < surface.num_quads(); ++q)
    for (NodeId v : surface.quads[q]) node_component[v.index()] = topo.quad_components[q].index();

  // Push-offs: each node moves along its normal (area-weighted quad normals) by a fraction of
  // its shortest edge; the normal cone must be pointed (the normal within 84 degrees of every
  // quad normal at the node).
  const auto pt = [&](std::size_t v) -> Eigen::Vector3d {
    return mesh.points.row(static_cast<Eigen::Index>(v)).transpose();
  };
  std::vector<Eigen::Vector3d> normal(n, Eigen::Vector3d::Zero());
  std::vector<std::vector<Eigen::Vector3d>> quad_normals(n);
  for (const stc::Quad& q : surface.quads) {
    const Eigen::Vector3d nq3 =
        (pt(q[2].index()) - pt(q[0].index())).cross(pt(q[3].index()) - pt(q[1].index()));
    for (NodeId v : q) {
      normal[v.index()] += nq3;
      quad_normals[v.index()].push_back(nq3.normalized());
    }
  }
  std::vector<double> push(n, 0.0);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-INFINITY);
  for (std::size_t v = 0; v < n; ++v) {
    if (node_component[v] == kNone) continue;
    lo = lo.cwiseMin(pt(v));
    hi = hi.cwiseMax(pt(v));
    double shortest = INFINITY;
    for (const auto& [w, e] : g.adj[v]) shortest = std::min(shortest, (pt(w) - pt(v)).norm());
    push[v] = options.push_fraction * shortest;
    normal[v].normalize();
  }
  const double scale = (hi - lo).norm();
  // Nodes whose normal cone is not pointed (no normal within 84 degrees of every quad there).
  std::vector<char> unpointed(n, 0);
  bool any_unpointed = false;
  for (std::size_t v = 0; v < n; ++v) {
    for (const Eigen::Vector3d& nf : quad_normals[v]) {
      if (node_component[v] != kNone && !(normal[v].dot(nf) > 0.1)) {
        unpointed[v] = 1;
        any_unpointed = true;
      }
    }
  }
  // Tree-cotree decomposition: a spanning forest of the nodes, a spanning forest of the quads
  // across the other edges; the 2g edges left give the generators.
  // When a generator meets a node of unpointed cone, once more with those nodes kept as
  // leaves of the node tree and the other edges at them taken first into the quad tree, so
  // that the generators go round them where the surface allows it.
  std::vector<std::size_t> leftover;
  std::vector<Bits> mask;
  std::vector<std::vector<std::size_t>> generators;
  std::size_t num_gen = 0;
  std::size_t words = 0;
  for (int variant = 0; variant < 2; ++variant) {
    const bool avoid = variant == 1;
    Tree tree = empty_tree(n);
    for (std::size_t v = 0; v < n; ++v) {
      if (node_component[v] == kNone || tree.depth[v] != kNone) continue;
      grow_tree(g, v, tree, avoid ? &unpointed : nullptr);
    }
    std::vector<char> in_tree(num_edges, 0);
    for (std::size_t v = 0; v < n; ++v)
      if (tree.parent_edge[v] != kNone) in_tree[tree.parent_edge[v]] = 1;
    const std::size_t nq = surface.num_quads();
    std::vector<std::size_t> qparent(nq, kNone);
    std::vector<std::size_t> qparent_edge(nq, kNone);
    std::vector<std::size_t> qdepth(nq, kNone);
    std::vector<char> in_cotree(num_edges, 0);
    const auto at_unpointed = [&](stc::EdgeId e) {
      return avoid && e.is_valid() &&
             (unpointed[topo.edges[e.index()].a.index()] != 0 ||
              unpointed[topo.edges[e.index()].b.index()] != 0);
    };
    for (std::size_t start = 0; start < nq; ++start) {
      if (qdepth[start] != kNone) continue;
      qdepth[start] = 0;
      std::deque<std::size_t> queue{start};
      while (!queue.empty()) {
        const std::size_t q = queue.front();
        queue.pop_front();
        for (int s = 0; s < 4; ++s) {
          const stc::QuadSide side{QuadId(q), s};
          const stc::EdgeId e = topo.edge_of(side);
          const stc::QuadSide other = topo.neighbour(side);
          if (!e.is_valid() || !other.is_valid() || in_tree[e.index()] != 0) continue;
          const std::size_t r = other.quad.index();
          if (qdepth[r] != kNone) continue;
          qdepth[r] = qdepth[q] + 1;
          qparent[r] = q;
          qparent_edge[r] = e.index();
          in_cotree[e.index()] = 1;
          if (at_unpointed(e))
            queue.push_front(r);
          else
            queue.push_back(r);
        }
      }
    }
    leftover.clear();
    for (std::size_t e = 0; e < num_edges; ++e)
      if (in_tree[e] == 0 && in_cotree[e] == 0) leftover.push_back(e);
    num_gen = leftover.size();
    if (num_gen != 2 * static_cast<std::size_t>(out.genus)) {
      out.undecided_reason = "the tree-cotree decomposition left " + std::to_string(num_gen) +
                             " edges for genus " + std::to_string(out.genus) +
                             " (expected 2g): the surface is not a closed manifold";
      return out;
    }
    words = (num_gen + 63) / 64;
    // mask[e]: the dual generator cycles that cross edge e.
    mask.assign(num_edges, Bits(words, 0));
    generators.clear();
    for (std::size_t i = 0; i < num_gen; ++i) {
      const std::size_t e = leftover[i];
      flip(mask[e], i);
      const auto uses = topo.uses(stc::EdgeId(e));
      std::size_t a = uses[0].quad.index();
      std::size_t b = uses[1].quad.index();
      while (qdepth[a] > qdepth[b]) {
        flip(mask[qparent_edge[a]], i);
        a = qparent[a];
      }
      while (qdepth[b] > qdepth[a]) {
        flip(mask[qparent_edge[b]], i);
        b = qparent[b];
      }
      while (a != b) {
        flip(mask[qparent_edge[a]], i);
        flip(mask[qparent_edge[b]], i);
        a = qparent[a];
        b = qparent[b];
      }
      generators.push_back(tree_cycle(tree, topo.edges[e].a.index(), topo.edges[e].b.index()));
    }
    const bool meets_unpointed =
        std::any_of(generators.begin(), generators.end(), [&](const auto& cy) {
          return std::any_of(cy.begin(), cy.end(),
                             [&](std::size_t v) { return unpointed[v] != 0; });
        });
    if (!meets_unpointed || !any_unpointed) break;
    // Going round nodes of unpointed cone is sound only where the surface is embedded: a
    // quad at such a node pierced by an edge of the surface (a fold through the solid), or an
    // edge at it piercing a quad, leaves it undecided.
    const auto pierces = [&](std::size_t a, std::size_t b, const stc::Quad& q) {
      for (NodeId x : q)
        if (x.index() == a || x.index() == b) return false;
      // Pierced whichever diagonal splits the quad (a non-planar quad is not misread).
      const auto hits = [&](int d) {
        const auto c = [&](int k) { return pt(q[static_cast<std::size_t>((k + d) % 4)].index()); };
        return segment_hits_triangle(pt(a), pt(b), c(0), c(1), c(2)) ||
               segment_hits_triangle(pt(a), pt(b), c(0), c(2), c(3));
      };
      return hits(0) && hits(1);
    };
    for (std::size_t v = 0; v < n; ++v) {
      if (unpointed[v] == 0) continue;
      for (const stc::Quad& q : surface.quads) {
        const bool at_v = std::find(q.begin(), q.end(), NodeId(v)) != q.end();
        // A quad at v against every edge; any other quad against the edges at v.
        const std::size_t count = at_v ? num_edges : g.adj[v].size();
        for (std::size_t i = 0; i < count; ++i) {
          const std::size_t e = at_v ? i : g.adj[v][i].second;
          const std::size_t a = topo.edges[e].a.index();
          const std::size_t b = topo.edges[e].b.index();
          if (!pierces(a, b, q)) continue;
          out.undecided_reason = "the quads around node " + NodeId(v).str() +
                                 " face too many ways and the surface is not embedded there "
                                 "(edge " +
                                 NodeId(a).str() + "-" + NodeId(b).str() + " pierces quad " +
                                 q[0].str() + "-" + q[1].str() + "-" + q[2].str() + "-" +
                                 q[3].str() + ")";
          return out;
        }
      }
    }
  }

  for (const auto& cycle : generators) {
    for (std::size_t v : cycle) {
      for (const Eigen::Vector3d& nf : quad_normals[v]) {
        if (!(normal[v].dot(nf) > 0.1)) {
          out.undecided_reason = "the quads around node " + NodeId(v).str() +
                                 " face too many ways (no normal within 84 degrees of all of "
                                 "them): a homology generator cannot be pushed off the surface";
          return out;
        }
      }
    }
  }
  std::vector<Polygon> inward;
  std::vector<Polygon> outward;
  for (const auto& cycle : generators) {
    Polygon in;
    Polygon outp;
    for (std::size_t v : cycle) {
      in.push_back(pt(v) - push[v] * normal[v]);
      outp.push_back(pt(v) + push[v] * normal[v]);
    }
    inward.push_back(std::move(in));
    outward.push_back(std::move(outp));
  }

  // Linking matrix mod 2 in a generic projection, retried along other directions when
  // degenerate.
  static const std::array<Eigen::Vector3d, 8> directions = {
      Eigen::Vector3d(0.5390117, 0.6421423, 0.5449871), Eigen::Vector3d(-0.3127, 0.8315, 0.2290),
      Eigen::Vector3d(0.7071, -0.1945, 0.6311),         Eigen::Vector3d(0.1123, 0.2789, -0.9537),
      Eigen::Vector3d(-0.8611, -0.3377, 0.3801),        Eigen::Vector3d(0.4242, -0.8743, -0.2361),
      Eigen::Vector3d(0.9319, 0.3301, 0.1501),          Eigen::Vector3d(-0.2012, -0.5517, 0.8093)};
  const double tol = 1e-11 * (scale > 0 ? scale : 1.0);
  std::vector<Bits> rows;
  bool ok = false;
  const int tries = std::clamp(options.max_projections, 1, static_cast<int>(directions.size()));
  for (int attempt = 0; attempt < tries && !ok; ++attempt) {
    ++out.projections_tried;
    const Eigen::Vector3d dir = directions[static_cast<std::size_t>(attempt)].normalized();
    ok = true;
    rows.assign(num_gen, Bits(words, 0));
    for (std::size_t i = 0; i < num_gen && ok; ++i)
      for (std::size_t j = 0; j < num_gen && ok; ++j)
        if (over_crossings_odd(inward[i], outward[j], dir, tol, &ok)) flip(rows[i], j);
  }
  if (!ok) {
    out.undecided_reason = "every one of " + std::to_string(out.projections_tried) +
                           " projection directions was degenerate for the linking numbers";
    return out;
  }
  // Columns of M, to test x^T M = 0 quickly.
  std::vector<Bits> cols(num_gen, Bits(words, 0));
  for (std::size_t i = 0; i < num_gen; ++i)
    for (std::size_t j = 0; j < num_gen; ++j)
      if (test(rows[i], j)) flip(cols[j], i);
  const std::vector<Bits> kernel = left_kernel(rows, num_gen);
  if (kernel.size() != static_cast<std::size_t>(out.genus)) {
    out.undecided_reason =
        "the linking matrix has a kernel of dimension " + std::to_string(kernel.size()) +
        " where Alexander duality gives " + std::to_string(out.genus) +
        ": a pushed cycle probably crosses the surface (walls thinner than the push distance, " +
        "or self-intersecting geometry)";
    return out;
  }
  const auto bounds_inside = [&](const Bits& x) {
    for (std::size_t j = 0; j < num_gen; ++j)
      if (odd_and(x, cols[j])) return false;
    return true;
  };

  // Short representatives: the shortest fundamental cycle of each class of the kernel over
  // breadth-first trees from many roots, then a greedy basis (shortest first).
  std::vector<std::size_t> used;
  for (std::size_t v = 0; v < n; ++v)
    if (node_component[v] != kNone) used.push_back(v);
  std::vector<std::size_t> roots;
  if (used.size() <= options.all_roots_up_to) {
    roots = used;
  } else {
    const std::size_t count = std::max<std::size_t>(1, options.sampled_roots);
    for (std::size_t k = 0; k < count; ++k) roots.push_back(used[k * used.size() / count]);
  }
  struct Candidate {
    std::size_t length;
    std::size_t root;
    std::size_t u;
    std::size_t w;
  };
  std::map<Bits, Candidate> best;
  // Per class, each root's best candidate (for alternative representatives).
  std::map<Bits, std::vector<Candidate>> per_root;
  std::map<Bits, Candidate> root_best;
  {  // the scan's tree and class buffer end with it (the basis below has its own)
    // Flat per-node class prefixes and one tree reused for every root (only the visited nodes
    // are reset): no allocation per node and root.
    std::vector<std::uint64_t> prefix(n * words, 0);
    Tree t = empty_tree(n);
    Bits x(words, 0);
    for (std::size_t r = 0; r < roots.size(); ++r) {
      for (std::size_t v : t.order) t.depth[v] = kNone;
      t.order.clear();
      root_best.clear();
      grow_tree(g, roots[r], t);
      for (std::size_t v : t.order) {
        std::uint64_t* pv = &prefix[v * words];
        if (t.parent[v] == kNone) {
          std::fill(pv, pv + words, 0);
        } else {
          const std::uint64_t* pp = &prefix[t.parent[v] * words];
          const Bits& m = mask[t.parent_edge[v]];
          for (std::size_t k = 0; k < words; ++k) pv[k] = pp[k] ^ m[k];
        }
      }
      for (std::size_t v : t.order) {
        for (const auto& [w, e] : g.adj[v]) {
          if (w < v || t.parent_edge[w] == e || t.parent_edge[v] == e) continue;
          for (std::size_t k = 0; k < words; ++k)
            x[k] = prefix[v * words + k] ^ prefix[w * words + k] ^ mask[e][k];
          if (is_zero(x) || !bounds_inside(x)) continue;
          // A cycle longer than the best of its class for this root and overall loses both
          // comparisons below, so its exact length is not needed (the walk to the common
          // ancestor was most of this scan's time).
          auto rb = root_best.find(x);
          auto it = best.find(x);
          const std::size_t limit = rb == root_best.end() || it == best.end()
                                        ? kNone
                                        : std::max(rb->second.length, it->second.length);
          const std::size_t length = cycle_length_within(t, v, w, limit);
          if (length == kNone) continue;
          const Candidate c{length, r, v, w};
          // A root's own candidate: among the shortest, the one whose lowest common ancestor
          // is nearest the root (the cycle through the root where there is one), so that
          // roots far apart give cycles far apart.
          const auto lca_depth = [&](const Candidate& k) {
            return (t.depth[k.u] + t.depth[k.w] + 1 - k.length) / 2;
          };
          if (rb == root_best.end()) {
            root_best.emplace(x, c);
          } else if (std::make_tuple(c.length, lca_depth(c), c.u, c.w) <
                     std::make_tuple(rb->second.length, lca_depth(rb->second), rb->second.u,
                                     rb->second.w)) {
            rb->second = c;
          }
          if (it == best.end()) {
            best.emplace(x, c);
          } else if (std::tie(c.length, c.root, c.u, c.w) <
                     std::tie(it->second.length, it->second.root, it->second.u, it->second.w)) {
            it->second = c;
          }
        }
      }
      for (const auto& [cls, c] : root_best) {
        auto& list = per_root[cls];
        list.push_back(c);
        std::sort(list.begin(), list.end(), [](const Candidate& p, const Candidate& q) {
          return std::tie(p.length, p.root, p.u, p.w) < std::tie(q.length, q.root, q.u, q.w);
        });
        if (list.size() > kAlternativePool) list.pop_back();
      }
    }
  }
  std::vector<std::pair<Candidate, Bits>> sorted;
  sorted.reserve(best.size());
  for (const auto& [x, c] : best) sorted.emplace_back(c, x);
  std::sort(sorted.begin(), sorted.end(), [](const auto& p, const auto& q) {
    return std::tie(p.first.length, p.first.root, p.first.u, p.first.w) <
           std::tie(q.first.length, q.first.root, q.first.u, q.first.w);
  });
  Z2Basis basis(num_gen);
  std::vector<std::size_t> generator_parity(num_gen);
  for (std::size_t i = 0; i < num_gen; ++i) generator_parity[i] = generators[i].size() % 2;
  for (const auto& [c, x] : sorted) {
    if (basis.rank() == static_cast<std::size_t>(out.genus)) break;
    if (!basis.add(x)) continue;
    Tree t = empty_tree(n);
    grow_tree(g, roots[c.root], t);
    HandleCycle h;
    const std::vector<std::size_t> cycle = tree_cycle(t, c.u, c.w);
    h.component = ComponentId(node_component[cycle.front()]);
    for (std::size_t v : cycle) h.nodes.push_back(NodeId(v));
    if (!h.is_even() && out.odd_handle < 0) out.odd_handle = static_cast<int>(out.handles.size());
    // Other simple cycles of the same class (distinct node sets), shortest first.
    std::vector<HandleCycle> others;
    std::vector<std::vector<NodeId>> seen{h.nodes};
    std::sort(seen.back().begin(), seen.back().end());
    for (const Candidate& a : per_root[x]) {
      if (others.size() == options.alternatives) break;
      Tree ta = empty_tree(n);
      grow_tree(g, roots[a.root], ta);
      HandleCycle alt;
      alt.component = h.component;
      for (std::size_t v : tree_cycle(ta, a.u, a.w)) alt.nodes.push_back(NodeId(v));
      std::vector<NodeId> key = alt.nodes;
      std::sort(key.begin(), key.end());
      if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
      seen.push_back(std::move(key));
      others.push_back(std::move(alt));
    }
    out.alternatives.push_back(std::move(others));
    out.handles.push_back(std::move(h));
  }
  // Basis vectors of the kernel that no single fundamental cycle represents.
  for (const Bits& x : kernel) {
    if (basis.rank() == static_cast<std::size_t>(out.genus)) break;
    if (!basis.add(x)) continue;
    std::vector<char> in_sum(num_edges, 0);
    std::size_t parity = 0;
    for (std::size_t i = 0; i < num_gen; ++i) {
      if (!test(x, i)) continue;
      parity += generator_parity[i];
      const auto& cyc = generators[i];
      for (std::size_t k = 0; k < cyc.size(); ++k) {
        const std::size_t a = cyc[k];
        const std::size_t b = cyc[(k + 1) % cyc.size()];
        for (const auto& [w, e] : g.adj[a])
          if (w == b) in_sum[e] ^= 1;
      }
    }
    out.combined_lengths.push_back(
        static_cast<std::size_t>(std::count(in_sum.begin(), in_sum.end(), 1)));
    if (parity % 2 == 1) out.odd_combined = true;
  }
  out.decided = true;
  return out;
}

std::vector<std::vector<NodeId>> disjoint_handle_cycles(const HandleDiagnosis& diagnosis,
                                                        std::size_t num_nodes,
                                                        std::size_t max_tries) {
  const std::size_t g = diagnosis.handles.size();
  if (g == 0) return {};
  // Per handle, its candidates: its own cycle, then its alternatives.
  std::vector<std::vector<const std::vector<NodeId>*>> options(g);
  for (std::size_t k = 0; k < g; ++k) {
    options[k].push_back(&diagnosis.handles[k].nodes);
    if (k < diagnosis.alternatives.size())
      for (const HandleCycle& alt : diagnosis.alternatives[k]) options[k].push_back(&alt.nodes);
  }
  std::vector<int> owner(num_nodes, -1);  // the handle whose chosen cycle holds the node
  std::vector<std::size_t> pick(g, 0);
  std::size_t tries = 0;
  const auto fits = [&](const std::vector<NodeId>& c) {
    return std::all_of(c.begin(), c.end(),
                       [&](NodeId v) { return v.index() < num_nodes && owner[v.index()] < 0; });
  };
  const auto mark = [&](const std::vector<NodeId>& c, int who) {
    for (NodeId v : c) owner[v.index()] = who;
  };
  const std::function<bool(std::size_t)> choose = [&](std::size_t k) -> bool {
    if (k == g) return true;
    for (std::size_t i = 0; i < options[k].size(); ++i) {
      if (++tries > max_tries) return false;
      if (!fits(*options[k][i])) continue;
      mark(*options[k][i], static_cast<int>(k));
      pick[k] = i;
      if (choose(k + 1)) return true;
      mark(*options[k][i], -1);
    }
    return false;
  };
  if (!choose(0)) return {};
  std::vector<std::vector<NodeId>> out;
  out.reserve(g);
  for (std::size_t k = 0; k < g; ++k) out.push_back(*options[k][pick[k]]);
  return out;
}

}  // namespace stcweave::primal
