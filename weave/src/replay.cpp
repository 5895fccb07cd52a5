/// Hexes made outside the driver put on a weave's front (replay.hpp).

#include "replay.hpp"

#include <algorithm>
#include <array>
#include <string>

#include "stcweave/stc/errors.hpp"

namespace stcweave::weave {
namespace {

/// True when `a` and `b` hold the same nodes in the same cyclic order.
bool same_cycle(const stc::Quad& a, const stc::Quad& b) {
  for (int r = 0; r < 4; ++r)
    if (quad_rotated(a, r) == b) return true;
  return false;
}

/// Why `hex` (canonical nodes, built on the front faces `used`) cannot join the woven complex,
/// if it cannot: two of its front faces belong to one hex, its contacts with a woven hex
/// (`WeaveState::contact_conflict`), or one of its edges between existing nodes is an edge of
/// a woven hex off the front.
std::optional<std::string> conflict(const WeaveState& state, const stc::Hex& hex,
                                    const std::vector<FaceIndex>& used, std::size_t old_nodes) {
  const Front& front = state.front;
  for (std::size_t i = 0; i < used.size(); ++i) {
    for (std::size_t j = i + 1; j < used.size(); ++j) {
      const FaceOwner& a = front.face(used[i]).owner;
      const FaceOwner& b = front.face(used[j]).owner;
      if (a.is_hex() && b.is_hex() && a.id == b.id)
        return "two of its front faces belong to hex " + std::to_string(a.id);
    }
  }
  if (auto why = state.contact_conflict(hex, used)) return why;
  std::vector<HexId> near;
  for (const NodeId n : hex) {
    if (n.index() < old_nodes) {
      near.insert(near.end(), state.woven.hexes_at[n.index()].begin(),
                  state.woven.hexes_at[n.index()].end());
    }
  }
  std::sort(near.begin(), near.end());
  near.erase(std::unique(near.begin(), near.end()), near.end());
  for (const HexId g : near) {
    std::array<NodeId, 8> gn{};
    for (std::size_t i = 0; i < 8; ++i) gn[i] = front.find(state.woven.hexes[g.index()][i]);
    for (const auto& e : stc::kHexEdges) {
      const NodeId a = hex[static_cast<std::size_t>(e[0])];
      const NodeId b = hex[static_cast<std::size_t>(e[1])];
      if (a.index() >= old_nodes || b.index() >= old_nodes) continue;
      if (front.find_edge(a, b).face != kNoFace) continue;  // a front edge
      for (const auto& ge : stc::kHexEdges) {
        const NodeId c = gn[static_cast<std::size_t>(ge[0])];
        const NodeId d = gn[static_cast<std::size_t>(ge[1])];
        if ((c == a && d == b) || (c == b && d == a))
          return "its edge " + a.str() + "-" + b.str() + " is an edge of " + g.str() +
                 " off the front";
      }
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> replay(WeaveState& state, WeaveContext& ctx,
                                  const stc::HexComplex& hexes, std::vector<NodeId> node_of,
                                  bool check, const char* rule) {
  Front& front = state.front;
  const std::size_t known = node_of.size();
  node_of.resize(std::max(hexes.num_nodes, known), NodeId::invalid());
  for (std::size_t h = 0; h < hexes.hexes.size(); ++h) {
    const std::string which = std::string(rule) + " hex " + std::to_string(h);
    const std::size_t old_nodes = front.num_nodes();
    stc::Hex hex{};
    for (std::size_t i = 0; i < 8; ++i) {
      const NodeId v = hexes.hexes[h][i];
      if (!v.is_valid() || v.index() >= node_of.size())
        throw InvalidInput("weave: " + which + " has node id " + v.str() + " out of range");
      if (!node_of[v.index()].is_valid()) {
        if (v.index() < known)
          throw InvalidInput("weave: " + which + " uses node " + v.str() + " of no front node");
        node_of[v.index()] = state.new_node();
      }
      hex[i] = front.find(node_of[v.index()]);
    }
    std::array<NodeId, 8> sorted = hex;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      throw InvalidInput("weave: " + which + " repeats a node");
    std::vector<FaceIndex> used;
    for (int lf = 0; lf < 6; ++lf) {
      const stc::Quad q = stc::hex_face(hex, lf);
      const auto key = quad_sorted(q);
      for (const FaceIndex f : front.faces_at(q[0])) {
        if (quad_sorted(front.face(f).nodes) != key) continue;
        if (!same_cycle(front.face(f).nodes, q)) {
          throw InvalidInput("weave: " + which + " lies on front face " + std::to_string(f) +
                             " with the wrong orientation (its faces on the front must be its "
                             "outward faces)");
        }
        used.push_back(f);
        break;
      }
    }
    if (used.empty())
      throw InvalidInput("weave: " + which + " has no face on the front it is attached to");
    if (check) {
      if (auto why = conflict(state, hex, used, old_nodes)) return which + ": " + *why;
    }
    make_hex(state, ctx, hex, used, rule, hex[0]);
  }
  if (auto err = front.check_invariants()) {
    throw InvalidInput("weave: the front after the " + std::to_string(hexes.hexes.size()) + " " +
                       rule + " hexes is not a closed oriented manifold quad surface: " + *err);
  }
  return std::nullopt;
}

stc::QuadSurface front_surface(const Front& front, std::vector<NodeId>& nodes) {
  std::vector<std::int32_t> compact(front.num_nodes(), -1);
  nodes.clear();
  stc::QuadSurface s;
  for (FaceIndex f = 0; static_cast<std::size_t>(f) < front.face_capacity(); ++f) {
    if (!front.is_alive(f)) continue;
    stc::Quad q{};
    for (std::size_t i = 0; i < 4; ++i) {
      const NodeId n = front.face(f).nodes[i];
      if (compact[n.index()] < 0) {
        compact[n.index()] = static_cast<std::int32_t>(nodes.size());
        nodes.push_back(n);
      }
      q[i] = NodeId(compact[n.index()]);
    }
    s.quads.push_back(q);
  }
  s.num_nodes = nodes.size();
  return s;
}

}  // namespace stcweave::weave
