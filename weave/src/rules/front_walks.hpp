#pragma once
/// The loops and the connected components of a front, written once for two ways of reading
/// its adjacency: the front's own incidence lists (`front_loops`, `front_components`, public)
/// and a selection's `FaceTable` (select/face_table.hpp), which answers the same questions by
/// lookup instead of by scanning a node's faces. Both give the same loops, numbered alike,
/// and the same components.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave::detail {

/// `trace_strip` with `across(f, k)` giving the face side across side k of face f.
template <typename Across>
Strip trace_strip_with(const Front& front, FaceIndex f, int entry, const Across& across) {
  Strip out;
  const stc::StripStep start{QuadId(f), entry};
  stc::StripStep cur = start;
  const std::size_t limit = 2 * front.num_faces() + 4;
  do {
    out.push_back(cur);
    const FaceSide next = across(face_of(cur), cur.exit());
    if (next.face == kNoFace) throw InternalError("weave: open front edge while tracing a loop");
    cur = stc::StripStep{QuadId(next.face), next.index};
    if (out.size() > limit) throw InternalError("weave: runaway loop trace");
  } while (cur != start);
  return out;
}

/// `front_loops` with `across` as above.
template <typename Across>
FrontLoops front_loops_with(const Front& front, const Across& across) {
  FrontLoops out;
  out.loop_of.assign(front.face_capacity(), {-1, -1});
  for (std::size_t fi = 0; fi < front.face_capacity(); ++fi) {
    const auto f = static_cast<FaceIndex>(fi);
    if (!front.is_alive(f)) continue;
    for (int dir = 0; dir < 2; ++dir) {
      if (out.loop_of[fi][static_cast<std::size_t>(dir)] >= 0) continue;
      Strip loop = trace_strip_with(front, f, dir, across);
      const auto id = static_cast<std::int32_t>(out.strips.size());
      for (const stc::StripStep& p : loop) {
        out.loop_of[static_cast<std::size_t>(face_of(p))][static_cast<std::size_t>(p.direction())] =
            id;
      }
      out.strips.push_back(std::move(loop));
    }
  }
  return out;
}

/// `front_components` with `faces_at(v)` the faces at node v (in `Front::faces_at` order) and
/// `nodes_of(f)` the nodes of face f.
template <typename FacesAt, typename NodesOf>
FrontComponents front_components_with(const Front& front, Marks& marks, const FacesAt& faces_at,
                                      const NodesOf& nodes_of) {
  FrontComponents out;
  out.component_of.assign(front.num_nodes(), 0);
  const std::uint32_t mark = marks.fresh(front.num_nodes());
  // From the live faces, not from every node ever made (the front is a small part of them
  // late in a weave); the components are then numbered by their smallest node, as a scan of
  // the nodes in order numbers them.
  std::vector<NodeId> stack;
  std::vector<std::pair<std::size_t, std::size_t>> found;  // per component: smallest node, size
  std::vector<std::pair<NodeId, std::size_t>> members;     // node, component found
  for (std::size_t fi = 0; fi < front.face_capacity(); ++fi) {
    const auto f = static_cast<FaceIndex>(fi);
    if (!front.is_alive(f)) continue;
    const NodeId start = nodes_of(f)[0];
    if (marks.is(start.index(), mark)) continue;
    const std::size_t comp = found.size();
    found.emplace_back(start.index(), 0);
    marks.set(start.index(), mark);
    stack.push_back(start);
    while (!stack.empty()) {
      const NodeId n = stack.back();
      stack.pop_back();
      members.emplace_back(n, comp);
      found[comp].first = std::min(found[comp].first, n.index());
      ++found[comp].second;
      for (FaceIndex g : faces_at(n)) {
        for (NodeId m : nodes_of(g)) {
          if (marks.is(m.index(), mark)) continue;
          marks.set(m.index(), mark);
          stack.push_back(m);
        }
      }
    }
  }
  std::vector<std::size_t> order(found.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return found[a].first < found[b].first; });
  std::vector<std::size_t> id(found.size());
  out.size.resize(found.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    id[order[k]] = k;
    out.size[k] = found[order[k]].second;
  }
  for (const auto& [n, comp] : members) out.component_of[n.index()] = id[comp];
  return out;
}

}  // namespace stcweave::weave::detail
