#pragma once
/// \file
/// Topology of a quad surface, computed once and read by everything that walks it: the
/// edge adjacency (for each quad side its neighbour quad and side), open, non-manifold and
/// inconsistently oriented edges, non-manifold nodes, degenerate quads, orientability and
/// a consistent orientation, connected components, Euler characteristic and genus.
///
/// Nothing is assumed about the surface: every defect is recorded, none is thrown.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "stcweave/stc/ids.hpp"
#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::stc {

/// Tag of an undirected edge of a quad surface (printed `e12`).
struct EdgeTag {
  static constexpr const char* kPrefix = "e";
};
/// An undirected edge of a quad surface (an index into `SurfaceTopology::edges`).
using EdgeId = Id<EdgeTag>;

/// Side `side` (0..3) of quad `quad`: the edge from `q[side]` to `q[(side+1)%4]`.
struct QuadSide {
  QuadId quad;
  int side = -1;

  [[nodiscard]] bool is_valid() const { return quad.is_valid(); }
  /// The flat index `4*quad + side` used by per-side vectors. \pre is_valid().
  [[nodiscard]] std::size_t index() const {
    return 4 * quad.index() + static_cast<std::size_t>(side);
  }
  friend bool operator==(const QuadSide&, const QuadSide&) = default;
};

/// An undirected edge: its end nodes (`a < b`) and where its uses (the quad sides lying on
/// it) are stored in `SurfaceTopology::edge_uses`.
struct SurfaceEdge {
  NodeId a;
  NodeId b;
  std::size_t first_use = 0;
  std::size_t num_uses = 0;
};

/// The figures of one connected component (quads connected through shared edges).
struct ComponentTopology {
  std::size_t num_quads = 0;
  std::size_t num_nodes = 0;           ///< nodes referenced by the component's quads
  std::size_t num_edges = 0;           ///< distinct non-degenerate edges
  long euler_characteristic = 0;       ///< nodes - edges + quads
  bool closed = false;                 ///< no open and no non-manifold edge
  bool manifold = false;               ///< no non-manifold edge and no non-manifold node
  bool orientable = false;             ///< a consistent orientation of its quads exists
  bool consistently_oriented = false;  ///< every two-quad edge is traversed both ways
  /// (2 - euler_characteristic) / 2, when the component is closed, manifold and orientable.
  std::optional<int> genus;
};

/// Everything `surface_topology` finds out about a quad surface.
///
/// Per-side vectors are indexed by `QuadSide::index()` (4 per quad). An edge with exactly
/// two uses is *manifold*; one use is *open*; more than two is *non-manifold*. A side whose
/// two nodes are equal is *degenerate*: it belongs to no edge.
struct SurfaceTopology {
  std::vector<SurfaceEdge> edges;    ///< sorted by (a, b)
  std::vector<QuadSide> edge_uses;   ///< the uses of every edge, see SurfaceEdge
  std::vector<EdgeId> side_edges;    ///< per side: its edge, invalid when degenerate
  std::vector<QuadSide> neighbours;  ///< per side: the other use of a manifold edge, else invalid

  std::vector<EdgeId> open_edges;          ///< edges used by one quad side
  std::vector<EdgeId> nonmanifold_edges;   ///< edges used by three or more quad sides
  std::vector<EdgeId> inconsistent_edges;  ///< manifold edges traversed twice the same way
  /// Nodes whose quads do not form one fan connected through edges at the node (a node
  /// used by a single quad is a boundary node, not a non-manifold one).
  std::vector<NodeId> nonmanifold_nodes;
  std::vector<QuadId> degenerate_quads;  ///< quads with a repeated node
  std::size_t num_nodes_used = 0;        ///< distinct nodes referenced by the quads

  std::vector<ComponentId> quad_components;  ///< per quad: its connected component
  std::vector<ComponentTopology> components;

  /// Per quad: reverse it to obtain a consistent orientation. Meaningful on orientable
  /// components; the first quad of every orientation patch keeps its orientation.
  std::vector<bool> orientation_flips;
  /// Per non-orientable component, one manifold edge where the propagated orientation
  /// conflicts with itself (a witness of non-orientability).
  std::vector<EdgeId> orientation_conflicts;

  [[nodiscard]] std::size_t num_quads() const { return quad_components.size(); }
  [[nodiscard]] const SurfaceEdge& edge(EdgeId e) const { return edges[e.index()]; }
  /// The quad sides lying on edge `e`.
  [[nodiscard]] std::span<const QuadSide> uses(EdgeId e) const {
    const SurfaceEdge& edge = edges[e.index()];
    return {edge_uses.data() + edge.first_use, edge.num_uses};
  }
  /// The edge of side `s`, invalid when the side is degenerate.
  [[nodiscard]] EdgeId edge_of(QuadSide s) const { return side_edges[s.index()]; }
  /// The quad side across `s` when its edge is manifold, else an invalid QuadSide.
  [[nodiscard]] QuadSide neighbour(QuadSide s) const { return neighbours[s.index()]; }

  [[nodiscard]] bool is_closed() const { return open_edges.empty() && nonmanifold_edges.empty(); }
  [[nodiscard]] bool is_manifold() const {
    return nonmanifold_edges.empty() && nonmanifold_nodes.empty();
  }
  [[nodiscard]] bool is_orientable() const { return orientation_conflicts.empty(); }
  [[nodiscard]] bool is_consistently_oriented() const { return inconsistent_edges.empty(); }
  /// nodes used - edges + quads, over the whole surface.
  [[nodiscard]] long euler_characteristic() const {
    return static_cast<long>(num_nodes_used) - static_cast<long>(edges.size()) +
           static_cast<long>(num_quads());
  }
  /// The sum of the components' genus when every component has one (closed, manifold,
  /// orientable), else nothing.
  [[nodiscard]] std::optional<int> genus() const;
};

/// Computes the topology of `surface` in O(n log n) (one sort of the quad sides, then
/// linear passes: union-find for components and node fans, a breadth-first propagation
/// of orientation across manifold edges).
/// \throw InvalidInput when a quad refers to a node id outside `0 .. num_nodes-1`.
[[nodiscard]] SurfaceTopology surface_topology(const QuadSurface& surface);

/// The two nodes of side `s` in the order the quad traverses them.
[[nodiscard]] inline std::array<NodeId, 2> side_nodes(const QuadSurface& surface, QuadSide s) {
  const Quad& q = surface.quad(s.quad);
  return {q[static_cast<std::size_t>(s.side)], q[static_cast<std::size_t>((s.side + 1) % 4)]};
}

/// `surface` with the quads marked in `topology.orientation_flips` reversed: consistently
/// oriented when the surface is orientable. Says nothing about inside and outside
/// (`primal::orient_outward` uses the geometry for that).
[[nodiscard]] QuadSurface consistently_oriented(const QuadSurface& surface,
                                                const SurfaceTopology& topology);

}  // namespace stcweave::stc
