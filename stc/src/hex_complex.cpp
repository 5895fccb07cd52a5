#include "stcweave/stc/hex_complex.hpp"

#include <algorithm>
#include <unordered_map>

#include "stcweave/stc/bucket_sort.hpp"

namespace stcweave::stc {
namespace {

struct FaceKey {
  std::array<NodeId, 4> sorted;
  friend bool operator==(const FaceKey&, const FaceKey&) = default;
};

struct FaceKeyHash {
  std::size_t operator()(const FaceKey& k) const noexcept {
    std::size_t h = 1469598103934665603ULL;
    for (NodeId v : k.sorted) h = (h ^ static_cast<std::size_t>(v.value())) * 1099511628211ULL;
    return h;
  }
};

}  // namespace

QuadSurface boundary_surface(const HexComplex& complex, std::vector<HexFaceRef>* origin,
                             std::vector<HexFaceRef>* nonmanifold) {
  struct Use {
    HexFaceRef first;
    int count = 0;
  };
  std::unordered_map<FaceKey, Use, FaceKeyHash> uses;
  uses.reserve(complex.hexes.size() * 4);
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    for (int f = 0; f < 6; ++f) {
      FaceKey key{hex_face(complex.hexes[h], f)};
      std::sort(key.sorted.begin(), key.sorted.end());
      Use& use = uses[key];
      if (use.count == 0) use.first = HexFaceRef{HexId(h), f};
      ++use.count;
    }
  }
  QuadSurface out;
  out.num_nodes = complex.num_nodes;
  if (origin != nullptr) origin->clear();
  if (nonmanifold != nullptr) nonmanifold->clear();
  // Deterministic order: walk the hexes again rather than the hash map.
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    for (int f = 0; f < 6; ++f) {
      const Quad q = hex_face(complex.hexes[h], f);
      FaceKey key{q};
      std::sort(key.sorted.begin(), key.sorted.end());
      const Use& use = uses.at(key);
      const bool is_first = use.first.hex == HexId(h) && use.first.face == f;
      if (!is_first) continue;
      if (use.count == 1) {
        out.quads.push_back(q);
        if (origin != nullptr) origin->push_back(use.first);
      } else if (use.count > 2 && nonmanifold != nullptr) {
        nonmanifold->push_back(use.first);
      }
    }
  }
  return out;
}

std::vector<std::pair<std::int32_t, std::int32_t>> unique_edges(const HexComplex& complex) {
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  edges.reserve(complex.hexes.size() * 12);
  for (const Hex& h : complex.hexes) {
    for (const auto& e : kHexEdges) {
      std::int32_t a = h[static_cast<std::size_t>(e[0])].value();
      std::int32_t b = h[static_cast<std::size_t>(e[1])].value();
      if (a > b) std::swap(a, b);
      edges.emplace_back(a, b);
    }
  }
  sort_by_smallest_node(edges, [](const auto& e) { return e.first; });
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

}  // namespace stcweave::stc
