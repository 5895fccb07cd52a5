/// Hexes per interior edge and per interior node (see valence_stats.hpp).

#include "stcweave/primal/valence_stats.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <utility>

#include "stcweave/stc/bucket_sort.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::primal {

namespace {

using Edge = std::pair<std::int32_t, std::int32_t>;

Edge edge_key(NodeId a, NodeId b) {
  return a.value() < b.value() ? Edge{a.value(), b.value()} : Edge{b.value(), a.value()};
}

/// Calls `on_run(key, count)` for every run of equal keys of a sorted vector.
template <typename Key, typename OnRun>
void runs(const std::vector<Key>& sorted, OnRun&& on_run) {
  std::size_t i = 0;
  while (i < sorted.size()) {
    std::size_t j = i + 1;
    while (j < sorted.size() && sorted[j] == sorted[i]) ++j;
    on_run(sorted[i], j - i);
    i = j;
  }
}

void add(std::vector<std::size_t>& histogram, std::size_t k) {
  if (histogram.size() <= k) histogram.resize(k + 1, 0);
  ++histogram[k];
}

}  // namespace

ValenceStats valence_stats(const stc::HexComplex& complex) {
  ValenceStats out;
  const std::size_t n = complex.num_nodes;
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    for (const NodeId v : complex.hexes[h]) {
      if (!v.is_valid() || static_cast<std::size_t>(v.value()) >= n) {
        throw InvalidInput("valence_stats: hex " + std::to_string(h) + " uses node " +
                           std::to_string(v.value()) + ", but the complex has " +
                           std::to_string(n) + " nodes; renumber the nodes or fix num_nodes");
      }
    }
  }
  // Boundary faces: hex faces used by exactly one hex (sorted node sets as keys).
  std::vector<std::pair<std::array<std::int32_t, 4>, std::size_t>> faces;
  faces.reserve(complex.hexes.size() * 6);
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    for (const auto& f : stc::kHexFaces) {
      std::array<std::int32_t, 4> key{};
      for (std::size_t k = 0; k < 4; ++k)
        key[k] = complex.hexes[h][static_cast<std::size_t>(f[k])].value();
      std::sort(key.begin(), key.end());
      faces.emplace_back(key, h);
    }
  }
  stc::sort_by_smallest_node(faces, [](const auto& f) { return f.first[0]; });
  std::vector<bool> boundary_node(n, false);
  std::vector<Edge> boundary_edges;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].first == faces[i].first) ++j;
    if (j - i == 1) {
      const auto& hex = complex.hexes[faces[i].second];
      // the face's nodes in cyclic order, from the hex
      for (const auto& f : stc::kHexFaces) {
        std::array<std::int32_t, 4> key{};
        for (std::size_t k = 0; k < 4; ++k) key[k] = hex[static_cast<std::size_t>(f[k])].value();
        std::sort(key.begin(), key.end());
        if (key != faces[i].first) continue;
        for (std::size_t k = 0; k < 4; ++k) {
          const NodeId a = hex[static_cast<std::size_t>(f[k])];
          const NodeId b = hex[static_cast<std::size_t>(f[(k + 1) % 4])];
          boundary_node[static_cast<std::size_t>(a.value())] = true;
          boundary_edges.push_back(edge_key(a, b));
        }
        break;
      }
    }
    i = j;
  }
  stc::sort_by_smallest_node(boundary_edges, [](const Edge& e) { return e.first; });
  boundary_edges.erase(std::unique(boundary_edges.begin(), boundary_edges.end()),
                       boundary_edges.end());

  // Hexes per edge and per node (each hex once per edge / node).
  std::vector<Edge> edges;
  edges.reserve(complex.hexes.size() * 12);
  std::vector<std::int32_t> nodes;
  nodes.reserve(complex.hexes.size() * 8);
  for (const auto& hex : complex.hexes) {
    std::array<Edge, 12> mine{};
    for (std::size_t e = 0; e < 12; ++e) {
      mine[e] = edge_key(hex[static_cast<std::size_t>(stc::kHexEdges[e][0])],
                         hex[static_cast<std::size_t>(stc::kHexEdges[e][1])]);
    }
    std::sort(mine.begin(), mine.end());
    edges.insert(edges.end(), mine.begin(), std::unique(mine.begin(), mine.end()));
    std::array<std::int32_t, 8> vs{};
    for (std::size_t k = 0; k < 8; ++k) vs[k] = hex[k].value();
    std::sort(vs.begin(), vs.end());
    nodes.insert(nodes.end(), vs.begin(), std::unique(vs.begin(), vs.end()));
  }
  stc::sort_by_smallest_node(edges, [](const Edge& e) { return e.first; });
  stc::sort_by_smallest_node(nodes, [](std::int32_t v) { return v; });
  runs(edges, [&](const Edge& e, std::size_t k) {
    if (std::binary_search(boundary_edges.begin(), boundary_edges.end(), e)) return;
    ++out.interior_edges;
    add(out.edge_histogram, k);
    out.max_hexes_at_interior_edge = std::max(out.max_hexes_at_interior_edge, k);
    if (k > 4) ++out.interior_edges_over_4;
    if (k < 3) ++out.interior_edges_under_3;
  });
  runs(nodes, [&](std::int32_t v, std::size_t k) {
    if (boundary_node[static_cast<std::size_t>(v)]) return;
    ++out.interior_nodes;
    add(out.node_histogram, k);
    out.max_hexes_at_interior_node = std::max(out.max_hexes_at_interior_node, k);
    if (k > 8) ++out.interior_nodes_over_8;
  });
  return out;
}

nlohmann::json valence_json(const ValenceStats& stats) {
  const auto histogram = [](const std::vector<std::size_t>& h) {
    nlohmann::json j = nlohmann::json::array();
    for (std::size_t k = 0; k < h.size(); ++k)
      if (h[k] > 0) j.push_back({k, h[k]});
    return j;
  };
  return {{"interior_edges", stats.interior_edges},
          {"interior_nodes", stats.interior_nodes},
          {"max_hexes_at_interior_edge", stats.max_hexes_at_interior_edge},
          {"max_hexes_at_interior_node", stats.max_hexes_at_interior_node},
          {"interior_edges_over_4", stats.interior_edges_over_4},
          {"interior_edges_under_3", stats.interior_edges_under_3},
          {"interior_nodes_over_8", stats.interior_nodes_over_8},
          {"edge_histogram", histogram(stats.edge_histogram)},
          {"node_histogram", histogram(stats.node_histogram)}};
}

}  // namespace stcweave::primal
