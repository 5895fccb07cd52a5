/// A pillow of the whole front (see front_pillow.hpp). The hexes are put on all at once:
/// one at a time, two hexes on faces that meet only at a node would share their copy of it
/// and pinch the front in between.

#include "stcweave/weave/front_pillow.hpp"

#include <algorithm>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/hex_complex.hpp"
#include "stcweave/stc/shared_nodes.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

std::size_t pillow_faces(WeaveState& state, WeaveContext& ctx,
                         const std::vector<FaceIndex>& faces) {
  Front& front = state.front;
  WovenComplex& woven = state.woven;
  if (faces.empty()) return 0;
  {
    // Two pillowed faces sharing two edges (a valence-2 node) would give two hexes sharing
    // two faces: the caller must not ask for it.
    std::map<std::pair<NodeId, NodeId>, std::vector<FaceIndex>> by_edge;
    for (FaceIndex f : faces) {
      const stc::Quad q = front.face(f).nodes;
      for (std::size_t k = 0; k < 4; ++k) by_edge[std::minmax(q[k], q[(k + 1) % 4])].push_back(f);
    }
    std::map<std::pair<FaceIndex, FaceIndex>, int> shared;
    for (const auto& [edge, at] : by_edge) {
      if (at.size() == 2 && ++shared[std::minmax(at[0], at[1])] > 1)
        throw InternalError("pillow: two of the faces to pillow share two edges");
    }
  }
  std::vector<NodeId> copy(front.num_nodes(), NodeId::invalid());
  const auto copy_of = [&](NodeId n) {
    if (!copy[n.index()].is_valid()) copy[n.index()] = state.new_node();
    return copy[n.index()];
  };
  struct Added {
    HexId id;
    int top = -1;
    Propagated carried;
  };
  std::vector<Added> added;
  std::vector<FaceOwner> whiskers;
  struct Side {
    FaceOwner owner;
    std::size_t added;  // index in `added`
  };
  std::map<std::array<NodeId, 4>, Side> open_sides;  // side faces not yet glued
  for (FaceIndex f : faces) {
    const stc::Quad q = front.face(f).nodes;
    const stc::Hex hex{q[0],          q[3],          q[2],          q[1],
                       copy_of(q[0]), copy_of(q[3]), copy_of(q[2]), copy_of(q[1])};
    const HexId id(woven.hexes.size());
    woven.hexes.push_back(hex);
    woven.dual.emplace_back();
    woven.hex_shrink.push_back(ctx.shrink_index);
    woven.hex_rule.emplace_back("pillow");
    woven.hex_node.push_back(NodeId::invalid());
    std::array<FaceIndex, 6> used{};
    used.fill(kNoFace);
    Added a{id, -1, {}};
    const auto bottom = quad_sorted(q);
    for (int lf = 0; lf < 6; ++lf) {
      const auto key = quad_sorted(stc::hex_face(hex, lf));
      const FaceOwner mine{FaceOwner::Kind::Hex, id.value(), static_cast<std::int8_t>(lf)};
      if (key == bottom) {
        used[static_cast<std::size_t>(lf)] = f;
        state.link(mine, front.face(f).owner);
        continue;
      }
      const bool is_top = std::none_of(key.begin(), key.end(), [&](NodeId n) {
        return std::find(q.begin(), q.end(), n) != q.end();
      });
      if (is_top) {
        a.top = lf;
        continue;
      }
      const auto it = open_sides.find(key);
      if (it == open_sides.end()) {
        open_sides.emplace(key, Side{mine, added.size()});
      } else {
        state.link(mine, it->second.owner);
        open_sides.erase(it);
      }
    }
    if (a.top < 0) throw InternalError("pillow: no top face on the hex of a front face");
    a.carried = propagate(front, hex, used);
    added.push_back(a);
    whiskers.push_back(front.face(f).owner);
    for (NodeId n : hex) woven.hexes_at[n.index()].push_back(id);
  }
  for (FaceIndex f : faces) {
    state.push_nodes_of(f);
    front.remove_face(f);
  }
  for (const Added& a : added) {
    const auto lf = static_cast<std::size_t>(a.top);
    const stc::Hex& hex = woven.hexes[a.id.index()];
    const FaceIndex g = front.add_face(
        stc::reversed(stc::hex_face(hex, a.top)),
        FaceOwner{FaceOwner::Kind::Hex, a.id.value(), static_cast<std::int8_t>(a.top)},
        a.carried.depth[lf], a.carried.side_angle[lf]);
    state.push_nodes_of(g);
  }
  // The side faces along the region's rim join the front (none for a closed front).
  for (const auto& [key, side] : open_sides) {
    const Added& a = added[side.added];
    const auto lf = static_cast<std::size_t>(static_cast<unsigned char>(side.owner.local_face));
    const FaceIndex g = front.add_face(
        stc::reversed(stc::hex_face(woven.hexes[a.id.index()], side.owner.local_face)), side.owner,
        a.carried.depth[lf], a.carried.side_angle[lf]);
    state.push_nodes_of(g);
  }
  // The batch is reported as one rule at its first copy node, on its last hex (as the trace's
  // rule event says).
  const NodeId reported = woven.hexes[added.front().id.index()][4];
  woven.hex_node[added.back().id.index()] = reported;
  ctx.after_rule(state, "pillow", reported, whiskers, added.back().id);
  return added.size();
}

std::size_t pillow_front(WeaveState& state, WeaveContext& ctx) {
  std::vector<FaceIndex> faces;
  for (std::size_t f = 0; f < state.front.face_capacity(); ++f)
    if (state.front.is_alive(static_cast<FaceIndex>(f))) faces.push_back(static_cast<FaceIndex>(f));
  return pillow_faces(state, ctx, faces);
}

std::optional<std::string> pillow_conflict(const WeaveState& state,
                                           const std::vector<FaceIndex>& faces) {
  const Front& front = state.front;
  std::vector<stc::Quad> quads;
  quads.reserve(faces.size());
  for (FaceIndex f : faces) {
    const stc::Quad& q = front.face(f).nodes;
    const std::array<FaceIndex, 1> glued{f};
    if (auto conflict = state.contact_conflict(q, glued))
      return "pillow of " + front.face(f).owner.str() + ": " + *conflict;
    quads.push_back(q);
  }
  // Faces sharing one node: their two hexes share the node and its copy. The pairs sharing
  // more, in order of their face indices (whichever order `faces` lists them in).
  std::vector<std::tuple<FaceIndex, FaceIndex, std::size_t>> pairs;
  for (const stc::SharedNodesPair& p : stc::pairs_sharing_nodes(quads, 2)) {
    const auto [f, g] = std::minmax(faces[p.first], faces[p.second]);
    pairs.emplace_back(f, g, p.shared);
  }
  std::sort(pairs.begin(), pairs.end());
  for (const auto& [f, g, shared] : pairs) {
    if (shared > 2) {
      return "pillow of " + front.face(f).owner.str() + " and " + front.face(g).owner.str() +
             ": the two faces share " + std::to_string(shared) + " nodes (two edges)";
    }
    // Two shared nodes: fine when they are an edge of f (then of g too, on a manifold front).
    if (!stc::shares_a_side(front.face(f).nodes, front.face(g).nodes)) {
      return "pillow of " + front.face(f).owner.str() + " and " + front.face(g).owner.str() +
             ": the two faces share two nodes that are not an edge";
    }
  }
  return std::nullopt;
}

std::size_t pillow_blocked_node(WeaveState& state, WeaveContext& ctx) {
  bool valence_two = false;
  for (std::size_t n = 0; n < state.front.num_nodes(); ++n) {
    const NodeId v(n);
    if (state.front.find(v) != v || state.front.valence(v) != 2) continue;
    valence_two = true;
    std::vector<FaceIndex> at = state.front.faces_at(v);
    std::sort(at.begin(), at.end());
    for (FaceIndex f : at)
      if (!pillow_conflict(state, {f})) return pillow_faces(state, ctx, {f});
  }
  if (valence_two) return 0;
  std::vector<FaceIndex> faces;
  for (std::size_t f = 0; f < state.front.face_capacity(); ++f)
    if (state.front.is_alive(static_cast<FaceIndex>(f))) faces.push_back(static_cast<FaceIndex>(f));
  if (pillow_conflict(state, faces)) return 0;
  return pillow_faces(state, ctx, faces);
}

}  // namespace stcweave::weave
