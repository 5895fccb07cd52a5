#pragma once
/// \file
/// Accumulation measures of a hex complex (issue 11, "No accumulation point"): how many hexes
/// meet at each interior edge and at each interior node. A structured mesh has 4 around every
/// interior edge and 8 at every interior node; a woven star (every hex at one interior node)
/// or a 17-hex edge shows as a long tail of these histograms. Topology only: no coordinates.

#include <cstddef>
#include <vector>

#include <nlohmann/json.hpp>

#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::primal {

/// Hexes per interior edge and per interior node of a hex complex. Interior: an edge that is
/// no edge of a boundary face, a node on no boundary face (a boundary face is a hex face
/// used by exactly one hex). Counted once per hex (a hex using an edge or node twice, which a
/// valid complex never has, counts once).
struct ValenceStats {
  std::size_t interior_edges = 0;  ///< interior edges of the complex
  std::size_t interior_nodes = 0;  ///< interior nodes used by a hex
  /// Most hexes around one interior edge; 0 when there is no interior edge.
  std::size_t max_hexes_at_interior_edge = 0;
  /// Most hexes at one interior node; 0 when there is no interior node.
  std::size_t max_hexes_at_interior_node = 0;
  /// edge_histogram[k]: interior edges with k hexes around them (size max + 1).
  std::vector<std::size_t> edge_histogram;
  /// node_histogram[k]: interior nodes with k hexes at them (size max + 1).
  std::vector<std::size_t> node_histogram;
  /// Interior edges with more than 4 hexes, and with fewer than 3 (irregular either way).
  std::size_t interior_edges_over_4 = 0;
  std::size_t interior_edges_under_3 = 0;
  /// Interior nodes with more than 8 hexes.
  std::size_t interior_nodes_over_8 = 0;
};

/// The accumulation measures of `complex`. Deterministic (no hashing). Linear-logarithmic in
/// the number of hexes. Node ids must be below `complex.num_nodes`.
/// \throw InvalidInput when a hex uses a node id out of range.
[[nodiscard]] ValenceStats valence_stats(const stc::HexComplex& complex);

/// `stats` as the report's "valence" object: the counts and maxima above, and each histogram
/// as an array of [k, count] pairs, its non-zero entries in increasing k.
[[nodiscard]] nlohmann::json valence_json(const ValenceStats& stats);

}  // namespace stcweave::primal
