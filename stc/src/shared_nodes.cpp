#include "stcweave/stc/shared_nodes.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>

#include "stcweave/stc/errors.hpp"

namespace stcweave::stc {
namespace {

template <std::size_t N>
std::vector<SharedNodesPair> pairs_of(std::span<const std::array<NodeId, N>> elements,
                                      std::size_t at_least) {
  if (at_least == 0) throw InvalidInput("pairs_sharing_nodes: at_least must be at least 1");
  std::vector<std::pair<NodeId, std::size_t>> at;  // (node, element), sorted by node
  at.reserve(N * elements.size());
  for (std::size_t e = 0; e < elements.size(); ++e)
    for (const NodeId n : elements[e]) at.emplace_back(n, e);
  std::sort(at.begin(), at.end());
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // one per pair and shared node
  for (std::size_t i = 0; i < at.size();) {
    std::size_t j = i + 1;
    while (j < at.size() && at[j].first == at[i].first) ++j;
    for (std::size_t a = i; a < j; ++a)
      for (std::size_t b = a + 1; b < j; ++b)
        pairs.emplace_back(std::minmax(at[a].second, at[b].second));
    i = j;
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<SharedNodesPair> out;
  for (std::size_t i = 0; i < pairs.size();) {
    std::size_t j = i + 1;
    while (j < pairs.size() && pairs[j] == pairs[i]) ++j;
    if (j - i >= at_least) out.push_back({pairs[i].first, pairs[i].second, j - i});
    i = j;
  }
  return out;
}

}  // namespace

std::vector<SharedNodesPair> pairs_sharing_nodes(std::span<const Quad> elements,
                                                 std::size_t at_least) {
  return pairs_of<4>(elements, at_least);
}

std::vector<SharedNodesPair> pairs_sharing_nodes(std::span<const Hex> elements,
                                                 std::size_t at_least) {
  return pairs_of<8>(elements, at_least);
}

bool shares_a_side(const Quad& a, const Quad& b) {
  const auto in_b = [&b](NodeId n) { return std::find(b.begin(), b.end(), n) != b.end(); };
  for (std::size_t k = 0; k < 4; ++k)
    if (in_b(a[k]) && in_b(a[(k + 1) % 4])) return true;
  return false;
}

}  // namespace stcweave::stc
