#include "stcweave/stc/loops.hpp"

#include <algorithm>

namespace stcweave::stc {
namespace {

/// Node-to-quads incidence (compressed rows) plus stamped marks reused from loop to loop,
/// so that computing the sides of a loop costs the size of its component, not of the
/// whole surface, and nothing is cleared between loops.
class SideFinder {
 public:
  SideFinder(const QuadSurface& surface, const SurfaceTopology& topology)
      : surface_(surface),
        topology_(topology),
        first_(surface.num_nodes + 1, 0),
        quad_stamp_(surface.num_quads(), 0),
        quad_side_(surface.num_quads(), 0),
        node_stamp_(surface.num_nodes, 0),
        node_side_(surface.num_nodes, 0) {
    for (const Quad& q : surface.quads)
      for (NodeId v : q) ++first_[v.index() + 1];
    for (std::size_t v = 0; v < surface.num_nodes; ++v) first_[v + 1] += first_[v];
    incident_.resize(first_.back());
    std::vector<std::size_t> next(first_.begin(), first_.end() - 1);
    for (std::size_t q = 0; q < surface.num_quads(); ++q) {
      for (NodeId v : surface.quads[q]) {
        // A degenerate quad repeating v is listed twice; harmless for a traversal.
        incident_[next[v.index()]++] = QuadId(q);
      }
    }
  }

  /// See `loop_sides`.
  std::optional<LoopSides> sides(const Loop& loop) {
    if (!loop.closed || loop.is_self_intersecting() || loop.strip.empty()) return std::nullopt;
    const ComponentTopology& comp = topology_.components[loop.component.index()];
    if (!comp.closed || !comp.manifold || !comp.consistently_oriented || comp.genus != 0)
      return std::nullopt;
    ++stamp_;
    LoopSides out;
    // Strip quads (stamped, side 2 = "strip") and strip nodes with their side.
    for (const StripStep& step : loop.strip) {
      quad_stamp_[step.quad.index()] = stamp_;
      quad_side_[step.quad.index()] = 2;
    }
    for (const StripStep& step : loop.strip) {
      const Quad& f = surface_.quad(step.quad);
      const auto at = [&](int k) { return f[static_cast<std::size_t>((step.entry + k) % 4)]; };
      const std::array<std::array<NodeId, 2>, 2> by_side = {{{at(0), at(3)}, {at(1), at(2)}}};
      for (std::size_t d = 0; d < 2; ++d) {
        for (NodeId v : by_side[d]) {
          if (node_stamp_[v.index()] == stamp_) {
            if (node_side_[v.index()] != d) return std::nullopt;  // both sides: not a Jordan curve
            continue;
          }
          node_stamp_[v.index()] = stamp_;
          node_side_[v.index()] = d;
          out.strip_nodes[d].push_back(v);
        }
      }
    }
    // Flood each side from its strip nodes through non-strip quads.
    std::vector<NodeId> queue;
    for (std::size_t d = 0; d < 2; ++d) {
      queue.assign(out.strip_nodes[d].begin(), out.strip_nodes[d].end());
      for (std::size_t head = 0; head < queue.size(); ++head) {
        const NodeId v = queue[head];
        for (std::size_t k = first_[v.index()]; k < first_[v.index() + 1]; ++k) {
          const QuadId g = incident_[k];
          if (quad_stamp_[g.index()] == stamp_) {
            if (quad_side_[g.index()] == 2 || quad_side_[g.index()] == d) continue;
            return std::nullopt;  // reached from both sides
          }
          quad_stamp_[g.index()] = stamp_;
          quad_side_[g.index()] = d;
          out.quads[d].push_back(g);
          for (NodeId w : surface_.quad(g)) {
            if (node_stamp_[w.index()] == stamp_) {
              if (node_side_[w.index()] != d) return std::nullopt;
              continue;
            }
            node_stamp_[w.index()] = stamp_;
            node_side_[w.index()] = d;
            out.nodes[d].push_back(w);
            queue.push_back(w);
          }
        }
      }
    }
    for (std::size_t d = 0; d < 2; ++d) {
      std::sort(out.quads[d].begin(), out.quads[d].end());
      std::sort(out.nodes[d].begin(), out.nodes[d].end());
      std::sort(out.strip_nodes[d].begin(), out.strip_nodes[d].end());
    }
    return out;
  }

 private:
  const QuadSurface& surface_;
  const SurfaceTopology& topology_;
  std::vector<std::size_t> first_;
  std::vector<QuadId> incident_;
  std::size_t stamp_ = 0;
  std::vector<std::size_t> quad_stamp_;
  std::vector<std::size_t> quad_side_;  // 0 left, 1 right, 2 strip
  std::vector<std::size_t> node_stamp_;
  std::vector<std::size_t> node_side_;
};

}  // namespace

std::size_t LoopSet::longest_length() const {
  std::size_t best = 0;
  for (const Loop& l : loops) best = std::max(best, l.length());
  return best;
}

std::size_t LoopSet::num_self_intersecting() const {
  return static_cast<std::size_t>(std::count_if(
      loops.begin(), loops.end(), [](const Loop& l) { return l.is_self_intersecting(); }));
}

std::size_t LoopSet::num_self_crossing_quads() const {
  std::size_t n = 0;
  for (const Loop& l : loops) n += l.self_crossing_quads.size();
  return n;
}

std::size_t LoopSet::num_open() const {
  return static_cast<std::size_t>(
      std::count_if(loops.begin(), loops.end(), [](const Loop& l) { return !l.closed; }));
}

/*
 * find_loops: what it guarantees and why it is linear.
 *
 * A directed passage is (quad, entry side). "Leave by the opposite side, enter the
 * neighbour" maps directed passages to directed passages; across manifold edges it is a
 * bijection (its inverse walks backwards), so following it from any passage returns to
 * that passage: the loop is closed. It never comes back through the same quad in the
 * opposite direction of travel (that would need a side to be its own neighbour). Where a
 * side has no neighbour (open, non-manifold or degenerate), the walk stops and the loop is
 * completed by walking backwards from its start: an open loop. Every (quad, direction) is
 * assigned to exactly one loop, so the whole tracing touches each quad twice.
 */
LoopSet find_loops(const QuadSurface& surface, const SurfaceTopology& topology,
                   const FindLoopsOptions& options) {
  const std::size_t num_quads = surface.num_quads();
  LoopSet set;
  set.quad_loops.assign(num_quads, {LoopId::invalid(), LoopId::invalid()});
  const auto assigned = [&](const StripStep& s) -> LoopId& {
    return set.quad_loops[s.quad.index()][static_cast<std::size_t>(s.direction())];
  };

  for (std::size_t f = 0; f < num_quads; ++f) {
    for (int d = 0; d < 2; ++d) {
      const StripStep start{QuadId(f), d};
      if (assigned(start).is_valid()) continue;
      Loop loop;
      loop.id = LoopId(set.loops.size());
      loop.component = topology.quad_components[f];
      assigned(start) = loop.id;
      loop.strip.push_back(start);
      // Forward.
      StripStep current = start;
      while (true) {
        const QuadSide across = topology.neighbour(QuadSide{current.quad, current.exit()});
        if (!across.is_valid()) {
          loop.closed = false;
          break;
        }
        const StripStep next{across.quad, across.side};
        if (next == start) break;
        if (assigned(next).is_valid()) break;  // unreachable on a valid topology; keeps termination
        assigned(next) = loop.id;
        loop.strip.push_back(next);
        current = next;
      }
      // Backward from the start when the forward walk hit a side without neighbour.
      if (!loop.closed) {
        std::vector<StripStep> before;
        current = start;
        while (true) {
          const QuadSide across = topology.neighbour(QuadSide{current.quad, current.entry});
          if (!across.is_valid()) break;
          const StripStep previous{across.quad, (across.side + 2) % 4};
          if (assigned(previous).is_valid()) break;
          assigned(previous) = loop.id;
          before.push_back(previous);
          current = previous;
        }
        std::reverse(before.begin(), before.end());
        loop.strip.insert(loop.strip.begin(), before.begin(), before.end());
      }
      set.loops.push_back(std::move(loop));
    }
  }

  // Crossings and self-crossings.
  for (Loop& loop : set.loops) {
    for (std::size_t k = 0; k < loop.strip.size(); ++k) {
      const StripStep& s = loop.strip[k];
      const LoopId other =
          set.quad_loops[s.quad.index()][static_cast<std::size_t>(1 - s.direction())];
      if (other == loop.id) {
        loop.self_crossing_quads.push_back(s.quad);
      } else {
        loop.crossings.push_back({s.quad, other, k});
      }
    }
    std::sort(loop.self_crossing_quads.begin(), loop.self_crossing_quads.end());
    loop.self_crossing_quads.erase(
        std::unique(loop.self_crossing_quads.begin(), loop.self_crossing_quads.end()),
        loop.self_crossing_quads.end());
  }

  // The loop-crossing graph: one vertex per loop, one edge per quad.
  set.crossing_graph = LoopCrossingGraph(set.loops.size());
  for (std::size_t l = 0; l < set.loops.size(); ++l) set.crossing_graph[l].loop = LoopId(l);
  for (std::size_t q = 0; q < num_quads; ++q) {
    const auto& pair = set.quad_loops[q];
    boost::add_edge(pair[0].index(), pair[1].index(), LoopCrossingEdge{QuadId(q)},
                    set.crossing_graph);
  }

  if (options.sides) {
    SideFinder finder(surface, topology);
    for (Loop& loop : set.loops) loop.sides = finder.sides(loop);
  }
  return set;
}

LoopSet find_loops(const QuadSurface& surface, const FindLoopsOptions& options) {
  const SurfaceTopology topology = surface_topology(surface);
  return find_loops(surface, topology, options);
}

std::optional<LoopSides> loop_sides(const QuadSurface& surface, const SurfaceTopology& topology,
                                    const Loop& loop) {
  SideFinder finder(surface, topology);
  return finder.sides(loop);
}

std::vector<std::array<NodeId, 2>> loop_transversal_edges(const QuadSurface& surface,
                                                          const Loop& loop) {
  std::vector<std::array<NodeId, 2>> out;
  out.reserve(loop.strip.size());
  for (const StripStep& s : loop.strip) {
    const Quad& f = surface.quad(s.quad);
    out.push_back(
        {f[static_cast<std::size_t>(s.entry)], f[static_cast<std::size_t>((s.entry + 1) % 4)]});
  }
  return out;
}

}  // namespace stcweave::stc
