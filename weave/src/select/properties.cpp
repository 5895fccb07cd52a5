/// The properties of each (loop, side) candidate that the selection filters read: the
/// reliable weights (seed sect. 2.2) and, for the extended rule set, faces collapsed, depth
/// (sect. 4.1), sharp edges crossed (4.2), side elimination weight (4.3), non-convex edges on
/// that side (4.4) and the loop it runs parallel to (4.5).

#include <algorithm>
#include <cmath>

#include <limits>
#include <numeric>
#include <optional>
#include <utility>

#include "bounded.hpp"
#include "face_table.hpp"
#include "one_flood.hpp"
#include "stcweave/weave/select.hpp"

namespace stcweave::weave {
FrontComponents front_components(const Front& front, Marks& marks) {
  FrontComponents out;
  out.component_of.assign(front.num_nodes(), 0);
  const std::uint32_t mark = marks.fresh(front.num_nodes());
  std::vector<NodeId> stack;
  for (std::size_t v = 0; v < front.num_nodes(); ++v) {
    const NodeId start(v);
    if (front.valence(start) == 0 || marks.is(v, mark)) continue;
    const std::size_t comp = out.size.size();
    out.size.push_back(0);
    marks.set(v, mark);
    stack.push_back(start);
    while (!stack.empty()) {
      const NodeId n = stack.back();
      stack.pop_back();
      out.component_of[n.index()] = comp;
      ++out.size[comp];
      for (FaceIndex f : front.faces_at(n)) {
        for (NodeId m : front.face(f).nodes) {
          if (marks.is(m.index(), mark)) continue;
          marks.set(m.index(), mark);
          stack.push_back(m);
        }
      }
    }
  }
  return out;
}

std::array<TraceCandidate, 2> weigh(const Front& front, const Strip& strip,
                                    const FrontComponents& components, Marks& nodes, Marks& faces) {
  return weigh_within(front, face_table(front, false), strip, components, nodes, faces,
                      {kNoLimit, kNoLimit}, nullptr);
}

std::array<TraceCandidate, 2> weigh_within(const Front& front, const FaceTable& table,
                                           const Strip& strip, const FrontComponents& components,
                                           Marks& nodes, Marks& faces,
                                           std::array<std::size_t, 2> limit, bool* pruned) {
  if (pruned != nullptr) *pruned = false;
  std::array<TraceCandidate, 2> c;
  c[0].side = 0;
  c[1].side = 1;
  c[0].length = c[1].length = strip.size();
  const std::uint32_t strip_stamp = faces.fresh(front.face_capacity());
  bool self_intersecting = false;
  for (const stc::StripStep& p : strip) {
    const auto f = static_cast<std::size_t>(face_of(p));
    if (faces.is(f, strip_stamp)) self_intersecting = true;
    faces.set(f, strip_stamp);
  }
  c[0].self_intersecting = c[1].self_intersecting = self_intersecting;
  // Stamps: `on` for strip nodes, `side[0]`/`side[1]` for nodes reached from either side.
  const std::uint32_t on = nodes.fresh(front.num_nodes());
  const std::array<std::uint32_t, 2> side{nodes.fresh(front.num_nodes()),
                                          nodes.fresh(front.num_nodes())};
  std::array<std::vector<NodeId>, 2> stack;
  std::size_t on_strip = 0;
  for (const stc::StripStep& p : strip) {
    const stc::Quad& n = table.nodes_of(face_of(p));
    for (NodeId m : n) {
      if (nodes.is(m.index(), on)) continue;
      nodes.set(m.index(), on);
      ++on_strip;
    }
    // side A nodes: n[i], n[i+3]; side B: n[i+1], n[i+2]
    stack[0].push_back(quad_at(n, p.entry));
    stack[0].push_back(quad_at(n, p.entry + 3));
    stack[1].push_back(quad_at(n, p.entry + 1));
    stack[1].push_back(quad_at(n, p.entry + 2));
  }
  c[0].on_strip = c[1].on_strip = on_strip;
  // Flood both sides through non-strip faces, one node at a time each, until one side is
  // exhausted: that side is then complete, and on a loop that separates its component the
  // other side is the rest of the component. If the floods meet, the loop does not separate
  // (it crosses itself): count each side by a full flood.
  std::array<std::size_t, 2> count{0, 0};
  bool met = false;
  const auto expand = [&](int d) {
    const auto di = static_cast<std::size_t>(d);
    const NodeId n = stack[di].back();
    stack[di].pop_back();
    for (FaceIndex f : table.faces_at(n)) {
      if (faces.is(static_cast<std::size_t>(f), strip_stamp)) continue;
      for (NodeId m : table.nodes_of(f)) {
        const std::uint32_t mark = nodes.get(m.index());
        if (mark == on || mark == side[di]) continue;
        if (mark == side[1 - di]) {
          met = true;
          continue;
        }
        nodes.set(m.index(), side[di]);
        ++count[di];
        stack[di].push_back(m);
      }
    }
  };
  // A side cannot win once the nodes it reached exceed its limit (every node reached is
  // counted in its weight, met or not); a loop none of whose sides can win is left here.
  const bool bounded = pruned != nullptr && !self_intersecting;
  const auto beyond = [&] {
    return on_strip + count[0] > limit[0] && on_strip + count[1] > limit[1];
  };
  if (bounded && beyond()) {
    *pruned = true;
    return c;
  }
  while (!met && !stack[0].empty() && !stack[1].empty()) {
    expand(0);
    if (!met && !stack[1].empty()) expand(1);
    if (bounded && beyond()) {
      *pruned = true;
      return c;
    }
  }
  if (!met) {
    const auto done = static_cast<std::size_t>(stack[0].empty() ? 0 : 1);
    const std::size_t total =
        components
            .size[components.component_of[front.face(face_of(strip.front())).nodes[0].index()]];
    c[done].strictly_on_side = count[done];
    c[1 - done].strictly_on_side = total - on_strip - count[done];
  } else {
    for (int d = 0; d < 2; ++d) {
      const std::uint32_t mark = nodes.fresh(front.num_nodes());
      for (const stc::StripStep& p : strip)
        for (NodeId m : table.nodes_of(face_of(p))) nodes.set(m.index(), mark);
      std::vector<NodeId> st;
      for (const stc::StripStep& p : strip) {
        const stc::Quad& n = table.nodes_of(face_of(p));
        st.push_back(quad_at(n, d == 0 ? p.entry : p.entry + 1));
        st.push_back(quad_at(n, d == 0 ? p.entry + 3 : p.entry + 2));
      }
      std::size_t strict = 0;
      while (!st.empty()) {
        const NodeId n = st.back();
        st.pop_back();
        for (FaceIndex f : table.faces_at(n)) {
          if (faces.is(static_cast<std::size_t>(f), strip_stamp)) continue;
          for (NodeId m : table.nodes_of(f)) {
            if (nodes.is(m.index(), mark)) continue;
            nodes.set(m.index(), mark);
            ++strict;
            st.push_back(m);
          }
        }
      }
      c[static_cast<std::size_t>(d)].strictly_on_side = strict;
    }
  }
  for (auto& x : c) x.weight = x.strictly_on_side + x.on_strip;
  return c;
}

namespace {

/// `extended_properties` with the front's neighbours and edge angles read from `table`.
std::array<TraceCandidate, 2> extended_properties_in(const Front& front, const FaceTable& table,
                                                     const Strip& strip,
                                                     const FrontComponents& components,
                                                     const ExtendedParameters& par, Marks& nodes,
                                                     Marks& faces, Marks& faces2) {
  // The reliable weights come from the two side floods below when they settle them (see the
  // end); `weigh` is called only otherwise.
  std::array<TraceCandidate, 2> c;
  const FaceSet strip_faces = mark_strip_faces(faces, front, strip);
  std::vector<FaceIndex> strip_face_list;
  strip_face_list.reserve(strip.size());
  for (const stc::StripStep& p : strip) strip_face_list.push_back(face_of(p));
  std::sort(strip_face_list.begin(), strip_face_list.end());
  const auto strip_face_count = static_cast<std::size_t>(
      std::unique(strip_face_list.begin(), strip_face_list.end()) - strip_face_list.begin());
  std::array<std::vector<NodeId>, 2> side_nodes;  // strictly on each side, from its flood
  std::uint32_t last_seen = 0;                    // the stamp of side B's flood
  std::size_t on_strip = 0;
  std::size_t crossed = 0;
  std::array<std::size_t, 2> side_sharp{0, 0};
  std::array<std::size_t, 2> nonconvex{0, 0};
  for (const stc::StripStep& p : strip) {
    if (table.angle_of(face_of(p), p.entry) <= par.little_sharp) ++crossed;
    for (std::size_t d = 0; d < 2; ++d) {
      const int side = d == 0 ? (p.entry + 3) % 4 : (p.entry + 1) % 4;
      const double a = table.angle_of(face_of(p), side);
      if (a <= par.sharp) ++side_sharp[d];
      if (a > par.flat) ++nonconvex[d];
    }
  }
  for (int d = 0; d < 2; ++d) {
    const auto di = static_cast<std::size_t>(d);
    // Flood side d from its strip nodes through non-strip faces: faces on that side, their
    // depths and their non-convex edges (each edge counted once).
    const std::uint32_t node_seen = nodes.fresh(front.num_nodes());
    last_seen = node_seen;
    on_strip = 0;
    for (const stc::StripStep& p : strip) {
      for (NodeId m : table.nodes_of(face_of(p))) {
        if (nodes.is(m.index(), node_seen)) continue;
        nodes.set(m.index(), node_seen);
        ++on_strip;
      }
    }
    std::vector<NodeId> stack;
    for (const stc::StripStep& p : strip) {
      const stc::Quad& n = table.nodes_of(face_of(p));
      stack.push_back(quad_at(n, d == 0 ? p.entry : p.entry + 1));
      stack.push_back(quad_at(n, d == 0 ? p.entry + 3 : p.entry + 2));
    }
    std::vector<FaceIndex> side_faces;
    const std::uint32_t face_seen = faces2.fresh(front.face_capacity());
    while (!stack.empty()) {
      const NodeId n = stack.back();
      stack.pop_back();
      for (FaceIndex f : table.faces_at(n)) {
        if (strip_faces.contains(f) || faces2.is(static_cast<std::size_t>(f), face_seen)) continue;
        faces2.set(static_cast<std::size_t>(f), face_seen);
        side_faces.push_back(f);
        for (NodeId m : table.nodes_of(f)) {
          if (nodes.is(m.index(), node_seen)) continue;
          nodes.set(m.index(), node_seen);
          stack.push_back(m);
          side_nodes[di].push_back(m);
        }
      }
    }
    std::int32_t depth = 0;
    for (FaceIndex f : side_faces) {
      const std::int32_t fd = front.face(f).depth;
      if (fd > 0 && (depth == 0 || fd < depth)) depth = fd;
      for (int k = 0; k < 4; ++k) {
        if (table.angle_of(f, k) <= par.flat) continue;
        const FaceSide& g = table.across_of(f, k);
        const bool once = g.face == kNoFace || strip_faces.contains(g.face) || f < g.face;
        if (once) ++nonconvex[di];
      }
    }
    TraceCandidate& x = c[di];
    x.faces_collapsed = side_faces.size() + strip_face_count;
    x.depth = depth;
    x.crossed_sharp = crossed;
    x.side_sharp = side_sharp[di];
    x.nonconvex_on_side = nonconvex[di];
  }
  // `weigh` counts a side by its flood too, except when its bidirectional flood stops at the
  // side it exhausts first and counts the other as the rest of the component. The two agree
  // when the loop does not cross itself, no node is on both sides and the sides and the strip
  // make up the component: then its floods cannot meet and the rest is the other side.
  const std::size_t total =
      components.size[components.component_of[front.face(face_of(strip.front())).nodes[0].index()]];
  const bool disjoint = std::none_of(side_nodes[0].begin(), side_nodes[0].end(),
                                     [&](NodeId m) { return nodes.is(m.index(), last_seen); });
  if (strip_face_count == strip.size() && disjoint &&
      side_nodes[0].size() + side_nodes[1].size() + on_strip == total) {
    for (std::size_t d = 0; d < 2; ++d) {
      c[d].side = static_cast<int>(d);
      c[d].length = strip.size();
      c[d].self_intersecting = false;
      c[d].on_strip = on_strip;
      c[d].strictly_on_side = side_nodes[d].size();
      c[d].weight = c[d].strictly_on_side + on_strip;
    }
  } else {
    const std::array<TraceCandidate, 2> w =
        weigh_within(front, table, strip, components, nodes, faces, {kNoLimit, kNoLimit}, nullptr);
    for (std::size_t d = 0; d < 2; ++d) {
      c[d].side = w[d].side;
      c[d].length = w[d].length;
      c[d].self_intersecting = w[d].self_intersecting;
      c[d].on_strip = w[d].on_strip;
      c[d].strictly_on_side = w[d].strictly_on_side;
      c[d].weight = w[d].weight;
    }
  }
  return c;
}

}  // namespace

namespace {

/// True when face side `k` of `f` counts as a non-convex edge of a side with no strip on it
/// (the test of `extended_properties_in`, with `f < g` for "counted once").
bool nonconvex_once(const FaceTable& table, FaceIndex f, int k, double flat) {
  if (table.angle_of(f, k) <= flat) return false;
  const FaceSide& g = table.across_of(f, k);
  return g.face == kNoFace || f < g.face;
}

}  // namespace

ComponentTotals component_totals(const Front& front, const FaceTable& table,
                                 const FrontComponents& components, double flat) {
  ComponentTotals t;
  const std::size_t count = components.size.size();
  t.faces.assign(count, 0);
  t.nonconvex.assign(count, 0);
  t.depths.resize(count);
  std::vector<std::pair<std::size_t, std::int32_t>> depth_of;  // (component, depth)
  std::int32_t deepest = 0;
  for (std::size_t i = 0; i < front.face_capacity(); ++i) {
    const auto f = static_cast<FaceIndex>(i);
    if (!front.is_alive(f)) continue;
    const std::size_t comp = components.component_of[table.nodes_of(f)[0].index()];
    ++t.faces[comp];
    for (int k = 0; k < 4; ++k)
      if (nonconvex_once(table, f, k, flat)) ++t.nonconvex[comp];
    const std::int32_t d = front.face(f).depth;
    if (d > 0) {
      depth_of.emplace_back(comp, d);
      deepest = std::max(deepest, d);
    }
  }
  std::sort(depth_of.begin(), depth_of.end());
  for (const auto& [comp, d] : depth_of) {
    auto& list = t.depths[comp];
    if (list.empty() || list.back().first != d) list.emplace_back(d, 0);
    ++list.back().second;
  }
  if (deepest <= kMaxDenseDepth) t.depth_count.assign(static_cast<std::size_t>(deepest) + 1, 0);
  return t;
}

// Which side is flooded, and why the rest is the other side: select/one_flood.hpp.
std::optional<std::array<TraceCandidate, 2>> one_flood_properties(
    const Front& front, const FaceTable& table, const Strip& strip,
    const FrontComponents& components, ComponentTotals& totals, const ExtendedParameters& par,
    Marks& nodes, Marks& faces, Marks& faces2) {
  if (totals.depth_count.empty()) return std::nullopt;
  const std::uint32_t strip_stamp = faces.fresh(front.face_capacity());
  for (const stc::StripStep& p : strip) {
    const auto f = static_cast<std::size_t>(face_of(p));
    if (faces.is(f, strip_stamp)) return std::nullopt;  // crosses itself
    faces.set(f, strip_stamp);
  }
  const auto on_strip_face = [&](FaceIndex f) {
    return faces.is(static_cast<std::size_t>(f), strip_stamp);
  };
  std::size_t crossed = 0;
  std::array<std::size_t, 2> side_sharp{0, 0};
  std::array<std::size_t, 2> nonconvex{0, 0};
  for (const stc::StripStep& p : strip) {
    if (table.angle_of(face_of(p), p.entry) <= par.little_sharp) ++crossed;
    for (std::size_t d = 0; d < 2; ++d) {
      const int side = d == 0 ? (p.entry + 3) % 4 : (p.entry + 1) % 4;
      const double a = table.angle_of(face_of(p), side);
      if (a <= par.sharp) ++side_sharp[d];
      if (a > par.flat) ++nonconvex[d];
    }
  }
  // Node stamps: strip corners of side A only, of side B only, of both; reached from A, B.
  const std::array<std::uint32_t, 2> corner{nodes.fresh(front.num_nodes()),
                                            nodes.fresh(front.num_nodes())};
  const std::uint32_t both = nodes.fresh(front.num_nodes());
  const std::array<std::uint32_t, 2> reached{nodes.fresh(front.num_nodes()),
                                             nodes.fresh(front.num_nodes())};
  const std::array<std::uint32_t, 2> seen{faces2.fresh(front.face_capacity()),
                                          faces2.fresh(front.face_capacity())};
  std::array<std::vector<NodeId>, 2> stack;
  std::size_t on_strip = 0;
  for (const stc::StripStep& p : strip) {
    const stc::Quad& n = table.nodes_of(face_of(p));
    for (int i = 0; i < 4; ++i) {
      const NodeId m = quad_at(n, p.entry + i);
      const std::size_t d = i == 0 || i == 3 ? 0 : 1;  // side A: n[entry], n[entry + 3]
      const std::uint32_t mark = nodes.get(m.index());
      if (mark == corner[d] || mark == both) {
      } else if (mark == corner[1 - d]) {
        nodes.set(m.index(), both);
      } else {
        nodes.set(m.index(), corner[d]);
        ++on_strip;
      }
    }
    stack[0].push_back(quad_at(n, p.entry));
    stack[0].push_back(quad_at(n, p.entry + 3));
    stack[1].push_back(quad_at(n, p.entry + 1));
    stack[1].push_back(quad_at(n, p.entry + 2));
  }
  std::array<std::vector<FaceIndex>, 2> side_faces;
  std::array<std::size_t, 2> count{0, 0};
  bool touched = false;
  const auto expand = [&](std::size_t d) {
    const NodeId n = stack[d].back();
    stack[d].pop_back();
    for (FaceIndex f : table.faces_at(n)) {
      const auto fi = static_cast<std::size_t>(f);
      if (on_strip_face(f) || faces2.is(fi, seen[d])) continue;
      if (faces2.is(fi, seen[1 - d])) {
        touched = true;
        return;
      }
      faces2.set(fi, seen[d]);
      side_faces[d].push_back(f);
      for (NodeId m : table.nodes_of(f)) {
        const std::uint32_t mark = nodes.get(m.index());
        if (mark == corner[d] || mark == reached[d]) continue;
        if (mark == corner[1 - d] || mark == both || mark == reached[1 - d]) {
          touched = true;
          return;
        }
        nodes.set(m.index(), reached[d]);
        ++count[d];
        stack[d].push_back(m);
      }
    }
  };
  while (!stack[0].empty() && !stack[1].empty()) {
    expand(0);
    if (touched) return std::nullopt;
    if (stack[1].empty()) break;
    expand(1);
    if (touched) return std::nullopt;
  }
  const std::size_t done = stack[0].empty() ? 0 : 1;
  const std::size_t other = 1 - done;
  const std::size_t comp =
      components.component_of[front.face(face_of(strip.front())).nodes[0].index()];
  const std::size_t total = components.size[comp];
  const std::size_t component_faces = totals.faces[comp];
  if (total < on_strip + count[done] || component_faces < strip.size() + side_faces[done].size())
    return std::nullopt;

  // The flooded side, as `extended_properties_in` counts it; with what the other side needs:
  // its faces' non-convex edges counted with no strip, and those across a strip face from a
  // higher slot (the strip counts them on the side, the totals did not).
  std::int32_t depth = 0;
  std::size_t done_plain = 0;     // non-convex edges of the flooded side, counted with no strip
  std::size_t done_to_strip = 0;  // its non-convex sides across a strip face of a lower slot
  for (FaceIndex f : side_faces[done]) {
    const std::int32_t fd = front.face(f).depth;
    if (fd > 0 && (depth == 0 || fd < depth)) depth = fd;
    for (int k = 0; k < 4; ++k) {
      if (table.angle_of(f, k) <= par.flat) continue;
      const FaceSide& g = table.across_of(f, k);
      const bool plain = g.face == kNoFace || f < g.face;
      const bool to_strip = g.face != kNoFace && on_strip_face(g.face);
      if (plain || to_strip) ++nonconvex[done];
      if (plain) ++done_plain;
      if (to_strip && !plain) ++done_to_strip;
    }
  }
  // The strip's faces with no strip counted, and every non-strip face side across a strip face
  // of a lower slot (found from the strip: the face across each strip side).
  std::size_t strip_plain = 0;
  std::size_t all_to_strip = 0;
  for (const stc::StripStep& p : strip) {
    const FaceIndex s = face_of(p);
    for (int j = 0; j < 4; ++j) {
      if (nonconvex_once(table, s, j, par.flat)) ++strip_plain;
      const FaceSide& g = table.across_of(s, j);
      if (g.face == kNoFace || on_strip_face(g.face)) continue;
      const FaceSide& back = table.across_of(g.face, g.index);
      if (back.face != s || back.index != j) return std::nullopt;
      if (!(table.angle_of(g.face, g.index) <= par.flat) && g.face > s) ++all_to_strip;
    }
  }
  const std::size_t other_plain = totals.nonconvex[comp] - done_plain - strip_plain;
  nonconvex[other] += other_plain + (all_to_strip - done_to_strip);

  // The other side's least positive depth: the component's depths less this side's and the
  // strip's.
  std::vector<std::size_t>& seen_depth = totals.depth_count;
  const auto tally = [&](FaceIndex f, int delta) {
    const std::int32_t fd = front.face(f).depth;
    if (fd > 0) seen_depth[static_cast<std::size_t>(fd)] += static_cast<std::size_t>(delta);
  };
  for (FaceIndex f : side_faces[done]) tally(f, 1);
  for (const stc::StripStep& p : strip) tally(face_of(p), 1);
  std::int32_t other_depth = 0;
  for (const auto& [d, n] : totals.depths[comp]) {
    if (n > seen_depth[static_cast<std::size_t>(d)]) {
      other_depth = d;
      break;
    }
  }
  for (FaceIndex f : side_faces[done]) tally(f, -1);
  for (const stc::StripStep& p : strip) tally(face_of(p), -1);

  std::array<TraceCandidate, 2> c;
  const std::array<std::size_t, 2> collapsed{
      done == 0 ? side_faces[0].size() : component_faces - strip.size() - side_faces[1].size(),
      done == 1 ? side_faces[1].size() : component_faces - strip.size() - side_faces[0].size()};
  const std::array<std::size_t, 2> strict{done == 0 ? count[0] : total - on_strip - count[1],
                                          done == 1 ? count[1] : total - on_strip - count[0]};
  for (std::size_t d = 0; d < 2; ++d) {
    TraceCandidate& x = c[d];
    x.faces_collapsed = collapsed[d] + strip.size();
    x.depth = d == done ? depth : other_depth;
    x.crossed_sharp = crossed;
    x.side_sharp = side_sharp[d];
    x.nonconvex_on_side = nonconvex[d];
    x.side = static_cast<int>(d);
    x.length = strip.size();
    x.self_intersecting = false;
    x.on_strip = on_strip;
    x.strictly_on_side = strict[d];
    x.weight = x.strictly_on_side + on_strip;
  }
  return c;
}

namespace {

/// `parallel_loop` with the front's neighbours and edge angles read from `table`.
std::int32_t parallel_loop_in(const FaceTable& table, const Strip& strip, stc::LoopSide side,
                              const FrontLoops& loops, const ExtendedParameters& parameters) {
  std::int32_t other = -1;
  const std::int32_t self = loops.loop_of[static_cast<std::size_t>(face_of(strip.front()))]
                                         [static_cast<std::size_t>(strip.front().direction())];
  for (const stc::StripStep& p : strip) {
    const int s = side == stc::LoopSide::Left ? (p.entry + 3) % 4 : (p.entry + 1) % 4;
    if (table.angle_of(face_of(p), s) > parameters.sharp) return -1;
    const FaceSide& g = table.across_of(face_of(p), s);
    if (g.face == kNoFace) return -1;
    // the loop that has this edge as a side edge enters g perpendicularly to it
    const std::int32_t l =
        loops
            .loop_of[static_cast<std::size_t>(g.face)][static_cast<std::size_t>((g.index + 1) % 2)];
    if (l < 0 || l == self || (other >= 0 && l != other)) return -1;
    other = l;
  }
  if (other < 0 || loops.strips[static_cast<std::size_t>(other)].size() != strip.size()) return -1;
  return other;
}

}  // namespace

std::array<TraceCandidate, 2> extended_properties(const Front& front, const Strip& strip,
                                                  const FrontComponents& components,
                                                  const ExtendedParameters& par, Marks& nodes,
                                                  Marks& faces, Marks& faces2) {
  return extended_properties_in(front, face_table(front), strip, components, par, nodes, faces,
                                faces2);
}

std::int32_t parallel_loop(const Front& front, const Strip& strip, stc::LoopSide side,
                           const FrontLoops& loops, const ExtendedParameters& parameters) {
  return parallel_loop_in(face_table(front), strip, side, loops, parameters);
}

std::vector<TraceCandidate> loop_candidates(const Front& front, const FrontLoops& loops,
                                            const FrontComponents& components, bool geometric,
                                            const ExtendedParameters& parameters, Marks& nodes,
                                            Marks& faces, Marks& faces2) {
  std::vector<TraceCandidate> out;
  out.reserve(loops.strips.size() * 2);
  const FaceTable table = face_table(front, geometric);
  ComponentTotals totals;
  if (geometric) totals = component_totals(front, table, components, parameters.flat);
  for (std::size_t l = 0; l < loops.strips.size(); ++l) {
    const Strip& strip = loops.strips[l];
    std::optional<std::array<TraceCandidate, 2>> one;
    if (geometric) {
      one = one_flood_properties(front, table, strip, components, totals, parameters, nodes, faces,
                                 faces2);
    }
    const auto pair = one         ? *one
                      : geometric ? extended_properties_in(front, table, strip, components,
                                                           parameters, nodes, faces, faces2)
                                  : weigh_within(front, table, strip, components, nodes, faces,
                                                 {kNoLimit, kNoLimit}, nullptr);
    for (TraceCandidate c : pair) {
      c.loop = static_cast<std::int32_t>(l);
      if (geometric && parameters.parallel_crossing && !c.self_intersecting) {
        c.parallel_to =
            parallel_loop_in(table, strip, static_cast<stc::LoopSide>(c.side), loops, parameters);
      }
      out.push_back(c);
    }
  }
  return out;
}

std::vector<TraceCandidate> loop_candidates_bounded(const Front& front, const FrontLoops& loops,
                                                    const FrontComponents& components, Marks& nodes,
                                                    Marks& faces, std::size_t& hint) {
  const std::size_t n = loops.strips.size();
  std::vector<TraceCandidate> out(n * 2);
  // The best so far among loops that do not cross themselves: its weight and its index in the
  // enumeration (side A of loop l is 2l, side B 2l + 1). A later candidate wins only with a
  // smaller weight, an earlier one also with an equal weight (the ranking's sort is stable).
  const FaceTable table = face_table(front, false);
  std::size_t best = kNoLimit;
  std::size_t best_index = kNoLimit;
  // Passes with a cap on every flood, doubled until the best weight is within it: a loop
  // stopped by the cap weighs more than the cap, so more than that best, and loses.
  std::vector<std::size_t> pending(n);
  std::iota(pending.begin(), pending.end(), std::size_t{0});
  std::size_t shortest = kNoLimit;
  for (const Strip& s : loops.strips) shortest = std::min(shortest, s.size());
  std::size_t cap = hint != 0 && hint != kNoLimit ? hint : 4 * std::max<std::size_t>(1, shortest);
  std::vector<std::size_t> next;
  while (!pending.empty()) {
    next.clear();
    for (std::size_t l : pending) {
      std::array<std::size_t, 2> limit{cap, cap};
      if (best != kNoLimit) {
        for (std::size_t d = 0; d < 2; ++d) {
          // wins with weight <= limit (best is at least the strip's node count, never 0)
          const std::size_t wins = 2 * l + d < best_index ? best : best - 1;
          limit[d] = std::min(limit[d], wins);
        }
      }
      bool pruned = false;
      std::array<TraceCandidate, 2> pair =
          weigh_within(front, table, loops.strips[l], components, nodes, faces, limit, &pruned);
      for (std::size_t d = 0; d < 2; ++d) {
        TraceCandidate& c = pair[d];
        c.loop = static_cast<std::int32_t>(l);
        if (pruned) {
          c.weight = kNoLimit;
          c.strictly_on_side = 0;
        } else if (!c.self_intersecting) {
          const std::size_t index = 2 * l + d;
          if (c.weight < best || (c.weight == best && index < best_index)) {
            best = c.weight;
            best_index = index;
          }
        }
        out[2 * l + d] = c;
      }
      if (pruned) next.push_back(l);
    }
    if (best <= cap || cap >= front.num_nodes()) break;  // beyond the node count: no cap
    // with a best known, its weight bounds every flood that is left
    cap = best != kNoLimit ? best : 2 * cap;
    pending.swap(next);
  }
  hint = best;
  return out;
}

}  // namespace stcweave::weave
