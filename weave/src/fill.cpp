/// The fill of a small blocked front (recovery.hpp, docs/weave-recovery.md "The fill"): the
/// front as a quad surface, the woven hexes around it as the hexes already attached, the front
/// moves of stc/loop_moves.hpp until nothing is left, and their hexes replayed on the front.

#include <algorithm>
#include <string>
#include <vector>

#include "recovery.hpp"
#include "replay.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/loop_moves.hpp"

namespace stcweave::weave {
namespace {

/// Candidate moves a fill may evaluate (`stc::LoopMoveOptions::max_evaluations`).
constexpr std::size_t kFillEvaluations = 50000;

}  // namespace

std::optional<std::string> fill_blocked_front(WeaveState& state, WeaveContext& ctx,
                                              std::size_t up_to) {
  const Front& front = state.front;
  const std::size_t faces = front.num_faces();
  if (faces > up_to) {
    return "the front has " + std::to_string(faces) + " faces, more than the " +
           std::to_string(up_to) + " a fill is tried on";
  }
  if (faces % 2 != 0) return "the front has an odd number of faces";
  // The front with compact node ids 0 .. F-1, then the other nodes of the woven hexes at its
  // nodes: the search must know those hexes (it builds no hex on two faces of one of them, no
  // edge or face that one of them already has).
  stc::LoopMoveResult start;
  std::vector<NodeId> nodes;
  start.front = front_surface(front, nodes);
  std::vector<std::int32_t> compact(front.num_nodes(), -1);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    compact[nodes[i].index()] = static_cast<std::int32_t>(i);
  std::vector<HexId> near;
  for (const NodeId n : nodes) {
    const auto& at = state.woven.hexes_at[n.index()];
    near.insert(near.end(), at.begin(), at.end());
  }
  std::sort(near.begin(), near.end());
  near.erase(std::unique(near.begin(), near.end()), near.end());
  std::vector<std::int32_t> hex_index(state.woven.hexes.size(), -1);
  for (std::size_t k = 0; k < near.size(); ++k) {
    hex_index[near[k].index()] = static_cast<std::int32_t>(k);
    stc::Hex h{};
    for (std::size_t i = 0; i < 8; ++i) {
      const NodeId v = front.find(state.woven.hexes[near[k].index()][i]);
      if (compact[v.index()] < 0) {
        compact[v.index()] = static_cast<std::int32_t>(nodes.size());
        nodes.push_back(v);
      }
      h[i] = NodeId(compact[v.index()]);
    }
    start.hexes.hexes.push_back(h);
  }
  start.hexes.num_nodes = nodes.size();
  start.front.num_nodes = nodes.size();
  // Who owns each face of the surface (the live faces in index order, as front_surface took
  // them): a woven hex, or an input quad.
  for (FaceIndex f = 0; static_cast<std::size_t>(f) < front.face_capacity(); ++f) {
    if (!front.is_alive(f)) continue;
    const FaceOwner& o = front.face(f).owner;
    const std::int32_t k = o.is_hex() ? hex_index[static_cast<std::size_t>(o.id)] : -1;
    if (o.is_hex() && k < 0)
      throw InternalError("weave: fill: front face " + std::to_string(f) + " of " + o.str() +
                          " has no hex among those at its nodes");
    start.front_hex.push_back(k);
    start.front_input.push_back(o.is_hex() ? -1 : o.id);
  }
  // The search's bounds, lowered: the fills that succeed on the closure's spheres (up to 20
  // quads) evaluate at most about 13,000 moves, the ones that fail stop at the deepening's
  // bound (300,000, several seconds) instead.
  stc::LoopMoveOptions search;
  search.max_evaluations = kFillEvaluations;
  search.tiny_evaluations = kFillEvaluations;
  search.strict_contacts = true;
  stc::LoopMoveResult filled;
  try {
    filled = stc::fill_front(start, search);
  } catch (const InvalidInput& e) {
    return std::string("the front moves refused the front: ") + e.what();
  }
  if (!filled.simple) {
    return "the front moves left " + std::to_string(filled.front.quads.size()) + " faces (" +
           filled.stop_reason + ")";
  }
  stc::HexComplex made;
  made.num_nodes = filled.hexes.num_nodes;
  made.hexes.assign(filled.hexes.hexes.begin() + static_cast<std::ptrdiff_t>(near.size()),
                    filled.hexes.hexes.end());
  WeaveState::Checkpoint saved = state.checkpoint();
  if (auto why = replay(state, ctx, made, nodes, true, "fill")) {
    state.roll_back(std::move(saved));
    return "the fill's " + *why;
  }
  if (state.front.num_faces() != 0) {
    state.roll_back(std::move(saved));
    return "the fill left " + std::to_string(state.front.num_faces()) + " faces on the front";
  }
  state.release(std::move(saved));
  state.stats.fill_hexes += made.hexes.size();
  return std::nullopt;
}

}  // namespace stcweave::weave
