#include "shells.hpp"

#include <algorithm>
#include <numeric>

namespace stcweave::primal {

std::vector<int> shell_of_nodes(const stc::QuadSurface& surface, std::size_t* shells) {
  std::vector<std::size_t> parent(surface.num_nodes);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  const auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& q : surface.quads) {
    for (int i = 1; i < 4; ++i) {
      const std::size_t a = find(q[0].index());
      const std::size_t b = find(q[static_cast<std::size_t>(i)].index());
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  std::vector<int> label(surface.num_nodes, -1);
  std::vector<int> root_label(surface.num_nodes, -1);
  int next = 0;
  for (const auto& q : surface.quads) {
    const std::size_t r = find(q[0].index());
    if (root_label[r] < 0) root_label[r] = next++;
    for (const NodeId v : q) label[v.index()] = root_label[r];
  }
  *shells = static_cast<std::size_t>(next);
  return label;
}

}  // namespace stcweave::primal
