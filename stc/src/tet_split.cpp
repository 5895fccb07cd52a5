#include "stcweave/stc/tet_split.hpp"

#include <algorithm>
#include <map>
#include <string>
#include <utility>

#include "stcweave/stc/errors.hpp"

namespace stcweave::stc {
namespace {

/// Two-colours the graph given by `neighbours` over the nodes with `in_graph` set, one
/// breadth-first search per component. \return false when a component is not bipartite.
bool two_colour(const std::vector<std::vector<std::size_t>>& neighbours,
                const std::vector<bool>& in_graph, std::vector<int>& colour,
                std::vector<std::size_t>& component) {
  const std::size_t n = neighbours.size();
  colour.assign(n, -1);
  component.assign(n, 0);
  std::size_t next_component = 0;
  std::vector<std::size_t> queue;
  for (std::size_t s = 0; s < n; ++s) {
    if (!in_graph[s] || colour[s] >= 0) continue;
    colour[s] = 0;
    component[s] = next_component;
    queue.assign(1, s);
    for (std::size_t i = 0; i < queue.size(); ++i) {
      const std::size_t u = queue[i];
      for (const std::size_t w : neighbours[u]) {
        if (colour[w] < 0) {
          colour[w] = 1 - colour[u];
          component[w] = next_component;
          queue.push_back(w);
        } else if (colour[w] == colour[u]) {
          return false;
        }
      }
    }
    ++next_component;
  }
  return true;
}

/// Per component of a two-coloured graph, the colour whose nodes all satisfy `fits` (-1 when
/// neither does; `prefer_larger` breaks a tie by the class size, else the tie is -1 too).
std::vector<int> chosen_colour(const std::vector<int>& colour,
                               const std::vector<std::size_t>& component,
                               const std::vector<bool>& in_graph, const std::vector<bool>& fits,
                               bool prefer_larger) {
  std::size_t components = 0;
  for (std::size_t u = 0; u < colour.size(); ++u)
    if (in_graph[u]) components = std::max(components, component[u] + 1);
  std::vector<std::array<bool, 2>> all_fit(components, {true, true});
  std::vector<std::array<std::size_t, 2>> size(components, {0, 0});
  for (std::size_t u = 0; u < colour.size(); ++u) {
    if (!in_graph[u]) continue;
    const auto c = static_cast<std::size_t>(colour[u]);
    ++size[component[u]][c];
    if (!fits[u]) all_fit[component[u]][c] = false;
  }
  std::vector<int> chosen(components, -1);
  for (std::size_t k = 0; k < components; ++k) {
    if (all_fit[k][0] && all_fit[k][1]) {
      // Colour 0 is that of the component's smallest node: on a full tie it is not chosen.
      if (prefer_larger) chosen[k] = size[k][0] > size[k][1] ? 0 : 1;
    } else if (all_fit[k][0] || all_fit[k][1]) {
      chosen[k] = all_fit[k][0] ? 0 : 1;
    }
  }
  return chosen;
}

/// The nodes of `in_graph` of the colour, in the 2-colouring of `neighbours`, whose nodes
/// all lie in `valence` quads (per component, as `chosen_colour` picks it). Nothing when the
/// graph is not bipartite or a component has no such colour.
std::optional<std::vector<bool>> class_of_valence(
    const std::vector<std::vector<std::size_t>>& neighbours, const std::vector<bool>& in_graph,
    const std::vector<std::vector<std::size_t>>& node_quads, std::size_t valence,
    bool prefer_larger) {
  std::vector<int> colour;
  std::vector<std::size_t> component;
  if (!two_colour(neighbours, in_graph, colour, component)) return std::nullopt;
  const std::size_t n = neighbours.size();
  std::vector<bool> fits(n);
  for (std::size_t u = 0; u < n; ++u) fits[u] = node_quads[u].size() == valence;
  const std::vector<int> chosen = chosen_colour(colour, component, in_graph, fits, prefer_larger);
  std::vector<bool> in_class(n, false);
  for (std::size_t u = 0; u < n; ++u) {
    if (!in_graph[u]) continue;
    const int c = chosen[component[u]];
    if (c < 0) return std::nullopt;
    in_class[u] = colour[u] == c;
  }
  return in_class;
}

std::pair<std::size_t, std::size_t> edge_key(NodeId a, NodeId b) {
  return std::minmax(a.index(), b.index());
}

std::array<std::size_t, 3> face_key(NodeId a, NodeId b, NodeId c) {
  std::array<std::size_t, 3> k = {a.index(), b.index(), c.index()};
  std::sort(k.begin(), k.end());
  return k;
}

}  // namespace

std::optional<TriangleSplit> recognise_triangle_split(const QuadSurface& surface) {
  const std::size_t n = surface.num_nodes;
  const std::size_t m = surface.quads.size();
  if (m == 0 || m % 3 != 0) return std::nullopt;
  std::vector<std::vector<std::size_t>> node_quads(n);
  std::vector<std::vector<std::size_t>> edges(n);
  for (std::size_t q = 0; q < m; ++q) {
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t a = surface.quads[q][i].index();
      const std::size_t b = surface.quads[q][(i + 1) % 4].index();
      if (a >= n || b >= n || a == b) return std::nullopt;
      node_quads[a].push_back(q);
      edges[a].push_back(b);
      edges[b].push_back(a);
    }
  }
  std::vector<bool> used(n);
  for (std::size_t u = 0; u < n; ++u) used[u] = !node_quads[u].empty();

  // Edge nodes: one colour of the quad edges' 2-colouring, every node in four quads.
  const std::optional<std::vector<bool>> edge_nodes =
      class_of_valence(edges, used, node_quads, 4, false);
  if (!edge_nodes) return std::nullopt;
  const std::vector<bool>& is_edge_node = *edge_nodes;

  // Centres and vertices: the quads' other diagonals, 2-coloured; centres are in three quads.
  std::vector<std::vector<std::size_t>> diagonals(n);
  std::vector<bool> corner(n, false);
  for (std::size_t q = 0; q < m; ++q) {
    const Quad& quad = surface.quads[q];
    const std::size_t s = is_edge_node[quad[0].index()] ? 1 : 0;
    const std::size_t a = quad[s].index();
    const std::size_t b = quad[s + 2].index();
    diagonals[a].push_back(b);
    diagonals[b].push_back(a);
    corner[a] = corner[b] = true;
  }
  const std::optional<std::vector<bool>> centres =
      class_of_valence(diagonals, corner, node_quads, 3, true);
  if (!centres) return std::nullopt;
  const std::vector<bool>& is_centre = *centres;

  // One triangle per centre: its three quads (vertex, edge node, centre, edge node) in
  // surface order, chained by their shared edge nodes.
  TriangleSplit split;
  std::map<std::pair<std::size_t, std::size_t>, NodeId> edge_node_of;
  std::vector<int> edge_node_sides(n, 0);
  for (std::size_t c = 0; c < n; ++c) {
    if (!is_centre[c]) continue;
    std::array<std::array<NodeId, 3>, 3> corners{};  // per quad: vertex, next edge node, previous
    std::array<QuadId, 3> quads{};
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t q = node_quads[c][k];
      const Quad& quad = surface.quads[q];
      std::size_t at = 4;
      for (std::size_t i = 0; i < 4; ++i)
        if (quad[i].index() == c) at = i;
      const NodeId v = quad[(at + 2) % 4];
      if (is_centre[v.index()] || is_edge_node[v.index()]) return std::nullopt;
      corners[k] = {v, quad[(at + 3) % 4], quad[(at + 1) % 4]};
      quads[k] = QuadId(q);
    }
    // Order the quads so that quad k's next edge node is quad k+1's previous one.
    std::array<std::size_t, 3> order = {0, 3, 3};
    for (std::size_t k = 1; k < 3; ++k) {
      for (std::size_t j = 0; j < 3; ++j)
        if (corners[j][2] == corners[order[k - 1]][1]) order[k] = j;
      if (order[k] == 3) return std::nullopt;
    }
    if (corners[order[0]][2] != corners[order[2]][1]) return std::nullopt;
    std::array<NodeId, 3> tri{};
    std::array<NodeId, 3> mids{};
    std::array<QuadId, 3> tri_quads{};
    for (std::size_t k = 0; k < 3; ++k) {
      tri[k] = corners[order[k]][0];
      mids[k] = corners[order[k]][1];
      tri_quads[k] = quads[order[k]];
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) return std::nullopt;
    for (std::size_t k = 0; k < 3; ++k) {
      const auto key = edge_key(tri[k], tri[(k + 1) % 3]);
      const auto [it, inserted] = edge_node_of.emplace(key, mids[k]);
      if (!inserted && it->second != mids[k]) return std::nullopt;
      if (++edge_node_sides[mids[k].index()] > 2) return std::nullopt;
    }
    split.triangles.push_back(tri);
    split.centres.push_back(NodeId(c));
    split.edge_nodes.push_back(mids);
    split.quads.push_back(tri_quads);
  }
  if (split.triangles.size() * 3 != m) return std::nullopt;
  for (std::size_t u = 0; u < n; ++u) {
    if (is_edge_node[u] && edge_node_sides[u] != 2) return std::nullopt;
    if (used[u] && !is_edge_node[u] && !is_centre[u]) split.vertices.push_back(NodeId(u));
  }
  // Each edge node must be the node of one vertex pair (its two triangle sides agree).
  std::vector<std::size_t> pairs_per_edge_node(n, 0);
  for (const auto& [key, node] : edge_node_of) ++pairs_per_edge_node[node.index()];
  for (std::size_t u = 0; u < n; ++u)
    if (is_edge_node[u] && pairs_per_edge_node[u] != 1) return std::nullopt;
  return split;
}

TetSplit split_tets(const TriangleSplit& split, std::size_t num_nodes,
                    const std::vector<Tet>& tets) {
  // What the surface gives: the node of each boundary edge and of each boundary face.
  std::map<std::pair<std::size_t, std::size_t>, NodeId> edge_node;
  std::map<std::array<std::size_t, 3>, std::size_t> boundary_face;  // -> triangle
  std::vector<bool> surface_only(num_nodes, false);
  for (std::size_t t = 0; t < split.triangles.size(); ++t) {
    const auto& tri = split.triangles[t];
    for (std::size_t k = 0; k < 3; ++k) {
      edge_node.emplace(edge_key(tri[k], tri[(k + 1) % 3]), split.edge_nodes[t][k]);
      if (split.edge_nodes[t][k].index() < num_nodes)
        surface_only[split.edge_nodes[t][k].index()] = true;
    }
    boundary_face.emplace(face_key(tri[0], tri[1], tri[2]), t);
    if (split.centres[t].index() < num_nodes) surface_only[split.centres[t].index()] = true;
  }

  TetSplit out;
  out.first_added = num_nodes;
  std::size_t next = num_nodes;
  const auto add = [&](std::vector<NodeId> parents) {
    out.added_parents.push_back(std::move(parents));
    return NodeId(next++);
  };
  std::map<std::array<std::size_t, 3>, std::pair<NodeId, int>> face_node;  // node, tets
  std::vector<int> boundary_face_tets(split.triangles.size(), 0);
  const auto middle = [&](NodeId a, NodeId b) {
    const auto [it, inserted] = edge_node.emplace(edge_key(a, b), NodeId());
    if (inserted) {
      it->second = add({std::min(a, b), std::max(a, b)});
      ++out.interior_edges;
    }
    return it->second;
  };
  const auto centre = [&](NodeId a, NodeId b, NodeId c) {
    const auto key = face_key(a, b, c);
    if (const auto bf = boundary_face.find(key); bf != boundary_face.end()) {
      ++boundary_face_tets[bf->second];
      return split.centres[bf->second];
    }
    auto [it, inserted] = face_node.emplace(key, std::make_pair(NodeId(), 0));
    if (inserted) {
      it->second.first = add({NodeId(key[0]), NodeId(key[1]), NodeId(key[2])});
      ++out.interior_faces;
    }
    if (++it->second.second > 2) {
      throw InvalidInput("tet split: the face " + NodeId(key[0]).str() + "-" +
                         NodeId(key[1]).str() + "-" + NodeId(key[2]).str() +
                         " is shared by more than two tetrahedra");
    }
    return it->second.first;
  };

  // The four orderings of a tet that start at each vertex and keep its orientation.
  static constexpr std::array<std::array<std::size_t, 4>, 4> kAt = {
      {{0, 1, 2, 3}, {1, 0, 3, 2}, {2, 3, 0, 1}, {3, 2, 1, 0}}};
  out.complex.hexes.reserve(4 * tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const Tet& tet = tets[t];
    for (std::size_t i = 0; i < 4; ++i) {
      if (!tet[i].is_valid() || tet[i].index() >= num_nodes || surface_only[tet[i].index()]) {
        throw InvalidInput("tet split: tetrahedron " + std::to_string(t) + " uses node " +
                           tet[i].str() + ", which is not a triangle vertex");
      }
      for (std::size_t j = 0; j < i; ++j) {
        if (tet[i] == tet[j]) {
          throw InvalidInput("tet split: tetrahedron " + std::to_string(t) + " repeats node " +
                             tet[i].str());
        }
      }
    }
    // Edge middles and face centres, in a fixed order so that ids are deterministic.
    std::map<std::pair<std::size_t, std::size_t>, NodeId> mid;
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = i + 1; j < 4; ++j)
        mid[edge_key(tet[i], tet[j])] = middle(tet[i], tet[j]);
    std::map<std::array<std::size_t, 3>, NodeId> face;
    for (std::size_t skip = 4; skip-- > 0;) {
      std::array<NodeId, 3> f{};
      std::size_t k = 0;
      for (std::size_t i = 0; i < 4; ++i)
        if (i != skip) f[k++] = tet[i];
      face[face_key(f[0], f[1], f[2])] = centre(f[0], f[1], f[2]);
    }
    const NodeId body = add({tet[0], tet[1], tet[2], tet[3]});
    for (const auto& at : kAt) {
      const NodeId p = tet[at[0]];
      const NodeId q = tet[at[1]];
      const NodeId r = tet[at[2]];
      const NodeId s = tet[at[3]];
      out.complex.hexes.push_back({p, mid[edge_key(p, q)], face[face_key(p, q, r)],
                                   mid[edge_key(p, r)], mid[edge_key(p, s)],
                                   face[face_key(p, q, s)], body, face[face_key(p, r, s)]});
    }
  }
  for (const auto& [key, node] : face_node) {
    if (node.second != 2) {
      throw InvalidInput("tet split: the interior face " + NodeId(key[0]).str() + "-" +
                         NodeId(key[1]).str() + "-" + NodeId(key[2]).str() +
                         " is a face of one tetrahedron only (the tetrahedra leave a gap)");
    }
  }
  for (std::size_t t = 0; t < boundary_face_tets.size(); ++t) {
    if (boundary_face_tets[t] != 1) {
      const auto& tri = split.triangles[t];
      throw InvalidInput("tet split: the boundary triangle " + tri[0].str() + "-" + tri[1].str() +
                         "-" + tri[2].str() + " is a face of " +
                         std::to_string(boundary_face_tets[t]) +
                         " tetrahedra, not of exactly one (the tetrahedral mesh does not keep "
                         "the surface)");
    }
  }
  out.complex.num_nodes = next;
  return out;
}

}  // namespace stcweave::stc
