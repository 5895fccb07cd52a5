#pragma once
/// \file
/// Which elements of a small list share nodes, and how many: the count behind every check
/// that refuses two hexes sharing four nodes off a face before they are made (parallel
/// merging's batch, the weave's recovery pillows, the pipeline's pillow layer). A whole
/// complex is checked by `validate_hex_complex` (`SharedNodesNotAFace`) in linear time; these
/// take lists of a few elements or a surface's quads.

#include <cstddef>
#include <span>
#include <vector>

#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::stc {

/// Two elements of a list, by index (`first` < `second`), and how many nodes they share.
struct SharedNodesPair {
  std::size_t first = 0;
  std::size_t second = 0;
  std::size_t shared = 0;
};

/// Every pair of elements that share at least `at_least` nodes (at least 1), in increasing
/// (first, second) order. Each element's nodes are assumed distinct. Time: a sort of the
/// (node, element) incidences, then of one entry per pair and shared node.
[[nodiscard]] std::vector<SharedNodesPair> pairs_sharing_nodes(std::span<const Quad> elements,
                                                               std::size_t at_least);
[[nodiscard]] std::vector<SharedNodesPair> pairs_sharing_nodes(std::span<const Hex> elements,
                                                               std::size_t at_least);

/// True when some side of `a` has both its nodes in `b` (for two quads of a manifold surface
/// sharing two nodes: they share an edge, not two opposite corners).
[[nodiscard]] bool shares_a_side(const Quad& a, const Quad& b);

}  // namespace stcweave::stc
