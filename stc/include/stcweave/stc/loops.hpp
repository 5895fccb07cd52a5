#pragma once
/// \file
/// The loops of a quad surface: the surface part of its Spatial Twist Continuum.
///
/// A loop is a closed dual curve: it enters a quad by one side, leaves it by the opposite
/// side and goes on into the neighbour quad, until it returns. Every quad is crossed by
/// exactly two loop passages, one through sides 0 and 2 (direction 0) and one through
/// sides 1 and 3 (direction 1). A loop that crosses some quad twice is self-intersecting;
/// the seed's algorithm requires none (\cite seed, sect. 3).

#include <array>
#include <boost/graph/adjacency_list.hpp>
#include <cstddef>
#include <optional>
#include <vector>

#include "stcweave/stc/ids.hpp"
#include "stcweave/stc/quad_surface.hpp"
#include "stcweave/stc/surface_topology.hpp"

namespace stcweave::stc {

/// One passage of a loop through a quad: it enters `quad` by side `entry` and leaves it by
/// the opposite side.
struct StripStep {
  QuadId quad;
  int entry = -1;

  [[nodiscard]] int exit() const { return (entry + 2) % 4; }
  /// 0 when the passage crosses sides 0 and 2, 1 when it crosses sides 1 and 3.
  [[nodiscard]] int direction() const { return entry % 2; }
  friend bool operator==(const StripStep&, const StripStep&) = default;
};

/// The two sides of a loop, seen from the outside of a consistently oriented surface.
///
/// DESIGN.md, "Sides of a loop": a loop entering quad F = (F0, F1, F2, F3) through its side
/// i has F[i] and F[i+3] on its left and F[i+1] and F[i+2] on its right (with quads
/// counter-clockwise seen from outside, left is left of the direction of travel).
enum class LoopSide { Left = 0, Right = 1 };

/// The regions a non-self-intersecting loop separates on a closed genus-0 component.
/// Index the arrays with `static_cast<int>(LoopSide)`; every vector is sorted.
struct LoopSides {
  std::array<std::vector<QuadId>, 2> quads;        ///< quads strictly on each side (off the strip)
  std::array<std::vector<NodeId>, 2> nodes;        ///< nodes strictly on each side (off the strip)
  std::array<std::vector<NodeId>, 2> strip_nodes;  ///< nodes of the strip on each side

  [[nodiscard]] const std::vector<QuadId>& side_quads(LoopSide d) const {
    return quads[static_cast<std::size_t>(d)];
  }
  [[nodiscard]] const std::vector<NodeId>& side_nodes(LoopSide d) const {
    return nodes[static_cast<std::size_t>(d)];
  }
  [[nodiscard]] const std::vector<NodeId>& side_strip_nodes(LoopSide d) const {
    return strip_nodes[static_cast<std::size_t>(d)];
  }
  /// The topological weight of Reliable Whisker Weaving: nodes strictly on side `d` plus
  /// the strip nodes on that side (DESIGN.md, "Loop selection").
  [[nodiscard]] std::size_t weight(LoopSide d) const {
    return side_nodes(d).size() + side_strip_nodes(d).size();
  }
};

/// Where a loop crosses another loop: the quad, the other loop and the position in the strip.
struct LoopCrossing {
  QuadId quad;
  LoopId other;
  std::size_t step = 0;  ///< index into Loop::strip
};

/// A loop with its strip (the quads it crosses, in order).
struct Loop {
  LoopId id;
  ComponentId component;
  /// The passages in order of travel. A closed loop's last step leads back to the first.
  std::vector<StripStep> strip;
  /// False when the loop runs into an open, non-manifold or degenerate side (it is then a
  /// dual path from one such side to another, its strip listed from one end to the other).
  bool closed = true;
  /// Crossings with other loops, in strip order.
  std::vector<LoopCrossing> crossings;
  /// The quads this loop crosses twice, increasing (each listed once).
  std::vector<QuadId> self_crossing_quads;
  /// Its left and right regions: set for a non-self-intersecting closed loop on a closed,
  /// manifold, consistently oriented genus-0 component (when asked for), else empty.
  std::optional<LoopSides> sides;

  [[nodiscard]] std::size_t length() const { return strip.size(); }
  [[nodiscard]] bool is_self_intersecting() const { return !self_crossing_quads.empty(); }
};

/// Bundled vertex property of the loop-crossing graph.
struct LoopVertex {
  LoopId loop;
};
/// Bundled edge property of the loop-crossing graph: the quad where the two loops cross.
struct LoopCrossingEdge {
  QuadId quad;
};

/// The loop-crossing graph: vertex i is loop i; one edge per quad, joining the two loops
/// crossing it. Parallel edges (two loops crossing several times) and self-loops (a
/// self-intersection) are kept.
using LoopCrossingGraph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS,
                                                LoopVertex, LoopCrossingEdge>;

/// The loops of a quad surface.
struct LoopSet {
  std::vector<Loop> loops;  ///< loop i has id l<i>
  /// Per quad, the loop crossing it in direction 0 (sides 0-2) and in direction 1 (1-3).
  std::vector<std::array<LoopId, 2>> quad_loops;
  LoopCrossingGraph crossing_graph;

  [[nodiscard]] std::size_t size() const { return loops.size(); }
  [[nodiscard]] const Loop& loop(LoopId l) const { return loops[l.index()]; }
  /// The length of the longest loop (0 when there is none).
  [[nodiscard]] std::size_t longest_length() const;
  [[nodiscard]] std::size_t num_self_intersecting() const;
  /// The number of quads crossed twice by the same loop.
  [[nodiscard]] std::size_t num_self_crossing_quads() const;
  [[nodiscard]] std::size_t num_open() const;
};

/// What `find_loops` computes beyond the strips.
struct FindLoopsOptions {
  /// Compute each eligible loop's sides. Costs O(component size) per loop, so O(loops x
  /// quads) in all; the diagnosis turns it off.
  bool sides = true;
};

/// Traces every loop of `surface` in O(n) (plus O(n) per loop for the sides). Loops are
/// numbered in order of their first quad (increasing quad id, direction 0 before 1), each
/// starting in that quad and entering it by side 0 or 1. Defects do not stop the tracing:
/// a loop stops at an open, non-manifold or degenerate side (`Loop::closed` is false).
/// \pre `topology == surface_topology(surface)`.
[[nodiscard]] LoopSet find_loops(const QuadSurface& surface, const SurfaceTopology& topology,
                                 const FindLoopsOptions& options = {});

/// As above, computing the topology first.
[[nodiscard]] LoopSet find_loops(const QuadSurface& surface, const FindLoopsOptions& options = {});

/// The sides of `loop`, or nothing when they are not defined (see `Loop::sides`).
/// \pre `topology == surface_topology(surface)` and `loop` is one of its loops.
[[nodiscard]] std::optional<LoopSides> loop_sides(const QuadSurface& surface,
                                                  const SurfaceTopology& topology,
                                                  const Loop& loop);

/// The transversal edges of a loop, one per step: the side it enters each quad by, as
/// (left node, right node). This is how a loop is re-found after the surface changes
/// (DESIGN.md, "Sides of a loop").
[[nodiscard]] std::vector<std::array<NodeId, 2>> loop_transversal_edges(const QuadSurface& surface,
                                                                        const Loop& loop);

}  // namespace stcweave::stc
