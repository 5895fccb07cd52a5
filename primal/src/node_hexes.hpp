#pragma once
/// \file
/// The hexes around each node in compressed rows (internal to primal/src: the positioning's
/// shape phase and barrier pass both walk them).

#include <cstddef>
#include <span>
#include <vector>

#include "stcweave/stc/hex_complex.hpp"

namespace stcweave::primal {

/// Hexes around each node: those of node v are `around[start[v] .. start[v + 1])`, in
/// increasing hex order.
struct NodeHexes {
  std::vector<std::size_t> start;   ///< num_nodes + 1 row offsets
  std::vector<std::size_t> around;  ///< hex indices, one entry per hex corner

  /// The hexes around node `v`.
  [[nodiscard]] std::span<const std::size_t> of(std::size_t v) const {
    return {around.data() + start[v], start[v + 1] - start[v]};
  }
};

/// The rows of `hexes` over `num_nodes` nodes (every node id below `num_nodes`).
inline NodeHexes node_hexes(const std::vector<stc::Hex>& hexes, std::size_t num_nodes) {
  NodeHexes out;
  out.start.assign(num_nodes + 1, 0);
  for (const stc::Hex& h : hexes) {
    for (const NodeId v : h) ++out.start[v.index() + 1];
  }
  for (std::size_t v = 0; v < num_nodes; ++v) out.start[v + 1] += out.start[v];
  out.around.resize(out.start[num_nodes]);
  std::vector<std::size_t> fill(out.start.begin(), out.start.end() - 1);
  for (std::size_t h = 0; h < hexes.size(); ++h) {
    for (const NodeId v : hexes[h]) out.around[fill[v.index()]++] = h;
  }
  return out;
}

}  // namespace stcweave::primal
