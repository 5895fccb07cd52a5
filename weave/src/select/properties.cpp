/// The properties of each (loop, side) candidate that the selection filters read: the
/// reliable weights (seed sect. 2.2) and, for the extended rule set, faces collapsed, depth
/// (sect. 4.1), sharp edges crossed (4.2), side elimination weight (4.3), non-convex edges on
/// that side (4.4) and the loop it runs parallel to (4.5).

#include <algorithm>
#include <cmath>

#include <iterator>
#include <limits>
#include <numeric>
#include <optional>
#include <span>
#include <utility>

#include "../rules/front_walks.hpp"
#include "bounded.hpp"
#include "candidates.hpp"
#include "face_table.hpp"
#include "one_flood.hpp"
#include "side_parity.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/select.hpp"

namespace stcweave::weave {
FrontComponents front_components(const Front& front, Marks& marks) {
  return detail::front_components_with(
      front, marks, [&](NodeId v) -> const auto& { return front.faces_at(v); },
      [&](FaceIndex f) -> const stc::Quad& { return front.face(f).nodes; });
}

namespace {

/// The faces of a strip stamped with a fresh stamp of `faces`, and whether the strip passes a
/// face twice (its loop crosses itself there).
struct StripFaces {
  std::uint32_t stamp = 0;
  bool self_intersecting = false;
};
StripFaces stamp_strip_faces(const Front& front, const Strip& strip, Marks& faces) {
  StripFaces out;
  out.stamp = faces.fresh(front.face_capacity());
  for (const stc::StripStep& p : strip) {
    const auto f = static_cast<std::size_t>(face_of(p));
    if (faces.is(f, out.stamp)) out.self_intersecting = true;
    faces.set(f, out.stamp);
  }
  return out;
}

}  // namespace

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
  const StripFaces strip_faces = stamp_strip_faces(front, strip, faces);
  const std::uint32_t strip_stamp = strip_faces.stamp;
  c[0].self_intersecting = c[1].self_intersecting = strip_faces.self_intersecting;
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
  const bool bounded = pruned != nullptr && !strip_faces.self_intersecting;
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

/// The strip's own edges: sharp edges it crosses, and per side (0: entry + 3, 1: entry + 1)
/// the sharp and the non-convex edges along it.
struct StripEdges {
  std::size_t crossed = 0;
  std::array<std::size_t, 2> side_sharp{0, 0};
  std::array<std::size_t, 2> nonconvex{0, 0};
};

StripEdges count_strip_edges(const FaceTable& table, const Strip& strip,
                             const ExtendedParameters& par) {
  StripEdges e;
  for (const stc::StripStep& p : strip) {
    if (table.angle_of(face_of(p), p.entry) <= par.little_sharp) ++e.crossed;
    for (std::size_t d = 0; d < 2; ++d) {
      const int side = d == 0 ? (p.entry + 3) % 4 : (p.entry + 1) % 4;
      const double a = table.angle_of(face_of(p), side);
      if (a <= par.sharp) ++e.side_sharp[d];
      if (a > par.flat) ++e.nonconvex[d];
    }
  }
  return e;
}

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
  const StripEdges strip_edges = count_strip_edges(table, strip, par);
  const std::size_t crossed = strip_edges.crossed;
  const std::array<std::size_t, 2> side_sharp = strip_edges.side_sharp;
  std::array<std::size_t, 2> nonconvex = strip_edges.nonconvex;
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
// ---------------------------------------------------------------------------------------
// the sides kept between selections

void SideCache::begin(const Front& front, const FaceTable& table) {
  std::vector<Slot> now(front.face_capacity());
  for (std::size_t i = 0; i < now.size(); ++i) {
    const auto f = static_cast<FaceIndex>(i);
    Slot& x = now[i];
    x.alive = front.is_alive(f);
    if (!x.alive) continue;
    x.nodes = table.nodes_of(f);
    x.depth = front.face(f).depth;
    for (int k = 0; k < 4; ++k) {
      x.across[static_cast<std::size_t>(k)] = table.across_of(f, k);
      x.angle[static_cast<std::size_t>(k)] = table.angle_of(f, k);
    }
  }
  // The nodes of every slot that changed, before and after: a kept side none of whose nodes
  // (nor its strip's) is among them reads the same faces, depths and angles as then.
  std::vector<NodeId> touched;
  std::vector<char> is_touched(front.num_nodes(), 0);
  const auto touch = [&](const Slot& x) {
    if (!x.alive) return;
    for (NodeId n : x.nodes) {
      if (n.index() >= is_touched.size()) is_touched.resize(n.index() + 1, 0);
      if (is_touched[n.index()] != 0) continue;
      is_touched[n.index()] = 1;
      touched.push_back(n);
    }
  };
  const Slot dead;
  for (std::size_t i = 0; i < std::max(now.size(), slots_.size()); ++i) {
    const Slot& was = i < slots_.size() ? slots_[i] : dead;
    const Slot& is = i < now.size() ? now[i] : dead;
    if (was.alive == is.alive && (!is.alive || (was.nodes == is.nodes && was.depth == is.depth &&
                                                was.angle == is.angle && same_across(was, is))))
      continue;
    touch(was);
    touch(is);
  }
  slots_ = std::move(now);
  if (touched.size() > front.num_nodes() / 4) {
    entries_.clear();  // another front, or most of it changed
    return;
  }
  for (auto it = entries_.begin(); it != entries_.end();) {
    const std::vector<std::uint64_t>& bits = it->second.bits;
    const bool hit = std::any_of(touched.begin(), touched.end(), [&](NodeId n) {
      const std::size_t w = n.index() / 64;
      return w < bits.size() && ((bits[w] >> (n.index() % 64)) & 1U) != 0;
    });
    if (hit) {
      it = entries_.erase(it);
    } else {
      it->second.used = false;
      ++it;
    }
  }
}

bool SideCache::same_across(const Slot& a, const Slot& b) {
  for (std::size_t k = 0; k < 4; ++k)
    if (a.across[k].face != b.across[k].face || a.across[k].index != b.across[k].index)
      return false;
  return true;
}

void SideCache::end() {
  for (auto it = entries_.begin(); it != entries_.end();)
    it = it->second.used ? std::next(it) : entries_.erase(it);
}

std::uint64_t SideCache::key(const Strip& strip) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(face_of(strip.front()))) << 2U) |
         static_cast<std::uint64_t>(strip.front().entry & 3);
}

const FloodedSide* SideCache::find(const Strip& strip) {
  const auto it = entries_.find(key(strip));
  if (it == entries_.end() || it->second.strip != strip) {
    ++misses;
    return nullptr;
  }
  it->second.used = true;
  ++hits;
  return &it->second.side;
}

bool SideCache::contains(const Strip& strip) const {
  const auto it = entries_.find(key(strip));
  return it != entries_.end() && it->second.strip == strip;
}

void SideCache::keep(const Strip& strip, const FloodedSide& side, std::span<const NodeId> nodes) {
  Entry e;
  e.strip = strip;
  e.side = side;
  e.used = true;
  for (NodeId n : nodes) {
    const std::size_t w = n.index() / 64;
    if (w >= e.bits.size()) e.bits.resize(w + 1, 0);
    e.bits[w] |= std::uint64_t{1} << (n.index() % 64);
  }
  entries_[key(strip)] = std::move(e);
}

std::optional<std::array<TraceCandidate, 2>> one_flood_properties(
    const Front& front, const FaceTable& table, const Strip& strip,
    const FrontComponents& components, ComponentTotals& totals, const ExtendedParameters& par,
    Marks& nodes, Marks& faces, Marks& faces2, SideCache* cache) {
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
  const StripEdges strip_edges = count_strip_edges(table, strip, par);
  const std::size_t crossed = strip_edges.crossed;
  const std::array<std::size_t, 2> side_sharp = strip_edges.side_sharp;
  std::array<std::size_t, 2> nonconvex = strip_edges.nonconvex;
  // Node stamps: strip corners of side A only, of side B only, of both; reached from A, B.
  const std::array<std::uint32_t, 2> corner{nodes.fresh(front.num_nodes()),
                                            nodes.fresh(front.num_nodes())};
  const std::uint32_t both = nodes.fresh(front.num_nodes());
  const std::array<std::uint32_t, 2> reached{nodes.fresh(front.num_nodes()),
                                             nodes.fresh(front.num_nodes())};
  std::array<std::vector<NodeId>, 2> stack;
  std::vector<NodeId> strip_nodes;
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
        strip_nodes.push_back(m);
      }
    }
    stack[0].push_back(quad_at(n, p.entry));
    stack[0].push_back(quad_at(n, p.entry + 3));
    stack[1].push_back(quad_at(n, p.entry + 1));
    stack[1].push_back(quad_at(n, p.entry + 2));
  }
  const std::size_t on_strip = strip_nodes.size();

  FloodedSide flooded;
  if (const FloodedSide* kept = cache != nullptr ? cache->find(strip) : nullptr) {
    flooded = *kept;
  } else {
    const std::array<std::uint32_t, 2> seen{faces2.fresh(front.face_capacity()),
                                            faces2.fresh(front.face_capacity())};
    std::array<std::vector<FaceIndex>, 2> side_faces;
    std::array<std::vector<NodeId>, 2> side_nodes;
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
          side_nodes[d].push_back(m);
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
    // The flooded side, as `extended_properties_in` counts it; with what the other side needs:
    // its faces' non-convex edges counted with no strip, and those across a strip face from a
    // lower slot (the strip counts them on the side, the totals did not).
    flooded.side = done;
    flooded.nodes = side_nodes[done].size();
    flooded.faces = side_faces[done].size();
    std::vector<std::size_t>& count = totals.depth_count;
    for (FaceIndex f : side_faces[done]) {
      const std::int32_t fd = front.face(f).depth;
      if (fd > 0) {
        if (flooded.depth == 0 || fd < flooded.depth) flooded.depth = fd;
        if (count[static_cast<std::size_t>(fd)]++ == 0) flooded.depths.emplace_back(fd, 0);
      }
      for (int k = 0; k < 4; ++k) {
        if (table.angle_of(f, k) <= par.flat) continue;
        const FaceSide& g = table.across_of(f, k);
        const bool plain = g.face == kNoFace || f < g.face;
        const bool to_strip = g.face != kNoFace && on_strip_face(g.face);
        if (plain || to_strip) ++flooded.nonconvex;
        if (plain) ++flooded.plain;
        if (to_strip && !plain) ++flooded.to_strip;
      }
    }
    std::sort(flooded.depths.begin(), flooded.depths.end());
    for (auto& [d, n] : flooded.depths) {
      n = count[static_cast<std::size_t>(d)];
      count[static_cast<std::size_t>(d)] = 0;
    }
    if (cache != nullptr) {
      side_nodes[done].insert(side_nodes[done].end(), strip_nodes.begin(), strip_nodes.end());
      cache->keep(strip, flooded, side_nodes[done]);
    }
  }
  const std::size_t done = flooded.side;
  const std::size_t other = 1 - done;
  const std::size_t comp =
      components.component_of[front.face(face_of(strip.front())).nodes[0].index()];
  const std::size_t total = components.size[comp];
  const std::size_t component_faces = totals.faces[comp];
  if (total < on_strip + flooded.nodes || component_faces < strip.size() + flooded.faces)
    return std::nullopt;
  nonconvex[done] += flooded.nonconvex;

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
  const std::size_t other_plain = totals.nonconvex[comp] - flooded.plain - strip_plain;
  nonconvex[other] += other_plain + (all_to_strip - flooded.to_strip);

  // The other side's least positive depth: the component's depths less the flooded side's and
  // the strip's.
  std::vector<std::size_t>& strip_depths = totals.depth_count;
  const auto tally = [&](int delta) {
    for (const stc::StripStep& p : strip) {
      const std::int32_t fd = front.face(face_of(p)).depth;
      if (fd > 0) strip_depths[static_cast<std::size_t>(fd)] += static_cast<std::size_t>(delta);
    }
  };
  tally(1);
  std::int32_t other_depth = 0;
  auto side_at = flooded.depths.begin();
  for (const auto& [d, n] : totals.depths[comp]) {
    while (side_at != flooded.depths.end() && side_at->first < d) ++side_at;
    const std::size_t on_side =
        side_at != flooded.depths.end() && side_at->first == d ? side_at->second : 0;
    if (n > on_side + strip_depths[static_cast<std::size_t>(d)]) {
      other_depth = d;
      break;
    }
  }
  tally(-1);

  std::array<TraceCandidate, 2> c;
  for (std::size_t d = 0; d < 2; ++d) {
    TraceCandidate& x = c[d];
    const bool is_done = d == done;
    x.faces_collapsed =
        (is_done ? flooded.faces : component_faces - strip.size() - flooded.faces) + strip.size();
    x.depth = is_done ? flooded.depth : other_depth;
    x.crossed_sharp = crossed;
    x.side_sharp = side_sharp[d];
    x.nonconvex_on_side = nonconvex[d];
    x.side = static_cast<int>(d);
    x.length = strip.size();
    x.self_intersecting = false;
    x.on_strip = on_strip;
    x.strictly_on_side = is_done ? flooded.nodes : total - on_strip - flooded.nodes;
    x.weight = x.strictly_on_side + on_strip;
  }
  return c;
}

std::array<std::size_t, 2> faces_collapsed_at_least(const Front& front, const FaceTable& table,
                                                    const Strip& strip, unsigned sides,
                                                    std::size_t limit, Marks& nodes, Marks& faces,
                                                    Marks& faces2) {
  std::array<std::size_t, 2> out{0, 0};
  const std::size_t above = limit == kNoLimit ? kNoLimit : limit + 1;
  const FaceSet strip_faces = mark_strip_faces(faces, front, strip);
  const std::size_t strip_count = strip.size();  // the loop does not cross itself
  std::vector<NodeId> stack;
  for (std::size_t d = 0; d < 2; ++d) {
    if ((sides & (1U << d)) == 0U) continue;
    if (strip_count > limit) {
      out[d] = above;
      continue;
    }
    // The flood of `extended_properties_in`: from side d's strip corners, through faces off
    // the strip, never through a strip node.
    const std::uint32_t node_seen = nodes.fresh(front.num_nodes());
    for (const stc::StripStep& p : strip)
      for (NodeId m : table.nodes_of(face_of(p))) nodes.set(m.index(), node_seen);
    stack.clear();
    for (const stc::StripStep& p : strip) {
      const stc::Quad& n = table.nodes_of(face_of(p));
      stack.push_back(quad_at(n, d == 0 ? p.entry : p.entry + 1));
      stack.push_back(quad_at(n, d == 0 ? p.entry + 3 : p.entry + 2));
    }
    const std::uint32_t face_seen = faces2.fresh(front.face_capacity());
    std::size_t count = strip_count;
    while (!stack.empty() && count <= limit) {
      const NodeId n = stack.back();
      stack.pop_back();
      for (FaceIndex f : table.faces_at(n)) {
        const auto fi = static_cast<std::size_t>(f);
        if (strip_faces.contains(f) || faces2.is(fi, face_seen)) continue;
        faces2.set(fi, face_seen);
        if (++count > limit) break;
        for (NodeId m : table.nodes_of(f)) {
          if (nodes.is(m.index(), node_seen)) continue;
          nodes.set(m.index(), node_seen);
          stack.push_back(m);
        }
      }
    }
    out[d] = std::min(count, above);
  }
  return out;
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

namespace {

/// The sides one flood found, kept between this thread's selections: a hint only, every kept
/// side is checked against the front (SideCache::begin), so it never changes a result.
thread_local SideCache side_cache;

/// The least faces collapsed the last `CandidateSet::bound_faces` found: where the next one
/// starts its limit (consecutive selections of a weave find similar figures). A hint only.
thread_local std::size_t fewest_faces_hint = 0;

}  // namespace

CandidateSet::CandidateSet(const Front& front, const FrontLoops& loops,
                           const FrontComponents& components, const ExtendedParameters& parameters,
                           Marks& nodes, Marks& faces, Marks& faces2, bool check)
    : CandidateSet(front, loops, components, parameters, nodes, faces, faces2, check,
                   face_table(front, true)) {}

CandidateSet::CandidateSet(const Front& front, const FrontLoops& loops,
                           const FrontComponents& components, const ExtendedParameters& parameters,
                           Marks& nodes, Marks& faces, Marks& faces2, bool check, FaceTable table)
    : front_(front),
      loops_(loops),
      components_(components),
      parameters_(parameters),
      nodes_(nodes),
      faces_(faces),
      faces2_(faces2),
      check_(check),
      table_(std::move(table)),
      totals_(component_totals(front, table_, components, parameters.flat)) {
  side_cache.begin(front, table_);
  const std::size_t n = loops.strips.size();
  all_.resize(2 * n);
  known_.assign(n, 0U);
  by_parity_.assign(n, 0);
  std::vector<char> crosses_itself(n, 0);
  for (std::size_t l = 0; l < n; ++l) {
    const Strip& strip = loops.strips[l];
    const bool self_intersecting = stamp_strip_faces(front, strip, faces).self_intersecting;
    crosses_itself[l] = self_intersecting ? 1 : 0;
    const StripEdges edges = count_strip_edges(table_, strip, parameters);
    const std::size_t comp =
        components.component_of[front.face(face_of(strip.front())).nodes[0].index()];
    // No non-convex edge in the component: no side of its loops holds one, and 0 is the
    // exact count (the only place, besides a flood, that sets `kNonconvexCount`).
    if (totals_.nonconvex[comp] == 0)
      known_[l] = side_property::kNonconvex | side_property::kNonconvexCount;
    for (std::size_t d = 0; d < 2; ++d) {
      TraceCandidate& c = all_[2 * l + d];
      c.loop = static_cast<std::int32_t>(l);
      c.side = static_cast<int>(d);
      c.length = strip.size();
      c.self_intersecting = self_intersecting;
      c.crossed_sharp = edges.crossed;
      c.side_sharp = edges.side_sharp[d];
      if (parameters.parallel_crossing && !self_intersecting) {
        c.parallel_to =
            parallel_loop_in(table_, strip, static_cast<stc::LoopSide>(d), loops, parameters);
      }
    }
  }
  // Where a component has non-convex edges, which sides hold one, for every loop at once
  // (select/side_parity.hpp): the non-convex filter reads only that, so it floods no side
  // (its relaxation to the fewest reads `kNonconvexCount`, which only a flood gives here).
  if (std::all_of(totals_.nonconvex.begin(), totals_.nonconvex.end(),
                  [](std::size_t k) { return k == 0; }))
    return;
  const SideNonconvex parity = side_nonconvex(front, table_, loops, components, totals_.faces,
                                              crosses_itself, parameters.flat);
  for (std::size_t l = 0; l < n; ++l) {
    if (parity.known[l] == 0 || (known_[l] & side_property::kNonconvex) != 0U) continue;
    known_[l] |= side_property::kNonconvex;
    by_parity_[l] = 1;
    // 1 stands for "at least one" until the loop is completed: the filter reads only != 0.
    // So `kNonconvexCount` is not set: only a flood (or a component without any non-convex
    // edge, above, where 0 is exact) may set it.
    for (std::size_t d = 0; d < 2; ++d)
      all_[2 * l + d].nonconvex_on_side = parity.has[l][d] != 0 ? 1 : 0;
  }
}

void CandidateSet::complete(std::int32_t loop) {
  const auto l = static_cast<std::size_t>(loop);
  if (known_[l] == side_property::kAll) return;
  const Strip& strip = loops_.strips[l];
  std::optional<std::array<TraceCandidate, 2>> one =
      one_flood_properties(front_, table_, strip, components_, totals_, parameters_, nodes_, faces_,
                           faces2_, &side_cache);
  const std::array<TraceCandidate, 2> pair =
      one ? *one
          : extended_properties_in(front_, table_, strip, components_, parameters_, nodes_, faces_,
                                   faces2_);
  for (std::size_t d = 0; d < 2; ++d) {
    TraceCandidate c = pair[d];
    TraceCandidate& slot = all_[2 * l + d];
    c.loop = loop;
    if (parameters_.parallel_crossing && !c.self_intersecting) c.parallel_to = slot.parallel_to;
    if (check_ &&
        (c.side != slot.side || c.length != slot.length ||
         c.self_intersecting != slot.self_intersecting || c.crossed_sharp != slot.crossed_sharp ||
         c.side_sharp != slot.side_sharp ||
         ((known_[l] & side_property::kNonconvex) != 0U &&
          (by_parity_[l] != 0 ? (c.nonconvex_on_side == 0) != (slot.nonconvex_on_side == 0)
                              : c.nonconvex_on_side != slot.nonconvex_on_side)))) {
      throw InternalError("weave: loop " + std::to_string(loop) + " side " + "AB"[d] +
                          ": its strip properties differ from those of its floods");
    }
    slot = c;
  }
  known_[l] = side_property::kAll;
}

void CandidateSet::bound_faces(const std::vector<std::size_t>& set) {
  std::size_t best = kNoLimit;
  std::vector<unsigned> wanted(known_.size(), 0U);  // per loop, the sides in `set`
  std::vector<std::int32_t> pending;                // loops to bound, in order of `set`
  const auto least = [&](std::int32_t loop) {
    const auto l = static_cast<std::size_t>(loop);
    for (std::size_t d = 0; d < 2; ++d)
      if ((wanted[l] & (1U << d)) != 0U) best = std::min(best, all_[2 * l + d].faces_collapsed);
  };
  for (const std::size_t i : set) {
    const TraceCandidate& c = all_[i];
    const auto l = static_cast<std::size_t>(c.loop);
    if (wanted[l] == 0U) pending.push_back(c.loop);
    wanted[l] |= 1U << static_cast<unsigned>(c.side);
  }
  // Loops known already, loops that cross themselves (always counted in full) and loops whose
  // flooded side is kept (a cheap completion) first: the least of them bounds the rest.
  std::vector<std::int32_t> rest;
  std::size_t shortest = kNoLimit;
  for (const std::int32_t loop : pending) {
    const auto l = static_cast<std::size_t>(loop);
    const Strip& strip = loops_.strips[l];
    if (known_[l] != side_property::kAll &&
        (all_[2 * l].self_intersecting || side_cache.contains(strip)))
      complete(loop);
    if (known_[l] == side_property::kAll) {
      least(loop);
    } else {
      rest.push_back(loop);
      shortest = std::min(shortest, strip.size());
    }
  }
  // Passes over the rest with a limit on every side's flood, doubled until the least faces
  // collapsed found is within it: a loop whose wanted sides all pass the limit collapses more
  // faces than that least on each of them, so it cannot be first, and is left unflooded.
  std::size_t cap = best != kNoLimit          ? best
                    : fewest_faces_hint != 0U ? fewest_faces_hint
                                              : 4 * std::max<std::size_t>(1, shortest);
  std::vector<std::int32_t> next;
  while (!rest.empty()) {
    next.clear();
    for (const std::int32_t loop : rest) {
      const auto l = static_cast<std::size_t>(loop);
      const std::size_t limit = std::min(cap, best);
      const std::array<std::size_t, 2> at_least = faces_collapsed_bound(loop, wanted[l], limit);
      bool within = false;
      for (std::size_t d = 0; d < 2; ++d)
        if ((wanted[l] & (1U << d)) != 0U && at_least[d] <= limit) within = true;
      if (within) {
        complete(loop);
        least(loop);
        continue;
      }
      for (std::size_t d = 0; d < 2; ++d)
        if ((wanted[l] & (1U << d)) != 0U) all_[2 * l + d].faces_collapsed = at_least[d];
      next.push_back(loop);
    }
    if (best <= cap) break;
    rest.swap(next);
    cap = cap > kNoLimit / 2 ? kNoLimit : 2 * cap;
  }
  if (best != kNoLimit) fewest_faces_hint = best;
}

std::array<std::size_t, 2> CandidateSet::faces_collapsed_bound(std::int32_t loop, unsigned sides,
                                                               std::size_t limit) {
  const auto l = static_cast<std::size_t>(loop);
  const Strip& strip = loops_.strips[l];
  if (!side_faces_) {
    std::vector<char> crosses_itself(loops_.strips.size(), 0);
    for (std::size_t k = 0; k < crosses_itself.size(); ++k)
      crosses_itself[k] = all_[2 * k].self_intersecting ? 1 : 0;
    side_faces_ = side_faces(front_, table_, loops_, components_, totals_.faces, crosses_itself);
  }
  if (side_faces_->known[l] == 0)
    return faces_collapsed_at_least(front_, table_, strip, sides, limit, nodes_, faces_, faces2_);
  // The flood's answer: the exact count when it is within the limit, else one above it.
  std::array<std::size_t, 2> out{0, 0};
  const std::size_t above = limit == kNoLimit ? kNoLimit : limit + 1;
  for (std::size_t d = 0; d < 2; ++d) {
    if ((sides & (1U << d)) == 0U) continue;
    const std::size_t exact = side_faces_->faces_collapsed[l][d];
    out[d] = exact <= limit ? exact : above;
  }
  if (check_) {
    const std::array<std::size_t, 2> flooded =
        faces_collapsed_at_least(front_, table_, strip, sides, limit, nodes_, faces_, faces2_);
    if (flooded != out) {
      throw InternalError("weave: loop " + std::to_string(loop) +
                          ": the faces collapsed of its sides counted over the front's tree (" +
                          std::to_string(out[0]) + ", " + std::to_string(out[1]) +
                          ") differ from its floods' (" + std::to_string(flooded[0]) + ", " +
                          std::to_string(flooded[1]) + ")");
    }
  }
  return out;
}

void CandidateSet::complete_all() {
  for (std::size_t l = 0; l < known_.size(); ++l) complete(static_cast<std::int32_t>(l));
}

std::vector<TraceCandidate> loop_candidates(const Front& front, const FrontLoops& loops,
                                            const FrontComponents& components, bool geometric,
                                            const ExtendedParameters& parameters, Marks& nodes,
                                            Marks& faces, Marks& faces2) {
  if (geometric) {
    CandidateSet set(front, loops, components, parameters, nodes, faces, faces2);
    set.complete_all();
    side_cache.end();
    return std::move(set.all());
  }
  std::vector<TraceCandidate> out;
  out.reserve(loops.strips.size() * 2);
  const FaceTable table = face_table(front, false);
  for (std::size_t l = 0; l < loops.strips.size(); ++l) {
    for (TraceCandidate c : weigh_within(front, table, loops.strips[l], components, nodes, faces,
                                         {kNoLimit, kNoLimit}, nullptr)) {
      c.loop = static_cast<std::int32_t>(l);
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
