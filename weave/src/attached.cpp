/// Weaving after attached hexes (stcweave/weave/attached.hpp): replay them with `make_hex` on
/// the input's front, run the driver, and when it blocks on loops that cross themselves, attach
/// more hexes to the weave's own front by the same moves (stc/loop_moves.hpp) and go on.

#include "stcweave/weave/attached.hpp"

#include <algorithm>
#include <string>

#include "driver.hpp"
#include "replay.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/loops.hpp"
#include "stcweave/weave/kernel.hpp"

namespace stcweave::weave {
namespace {

/// One round of front moves on a blocked weave whose front has loops crossing themselves:
/// true when hexes were attached (the weave goes on).
bool untangle_round(WeaveState& state, WeaveContext& ctx, const AttachedWeaveOptions& more,
                    AttachedWeaveReport* report, std::size_t& rounds) {
  if (rounds >= more.untangle_rounds) return false;
  std::vector<NodeId> nodes;
  const stc::QuadSurface s = front_surface(state.front, nodes);
  if (stc::find_loops(s, {.sides = false}).num_self_intersecting() == 0) return false;
  ++rounds;
  stc::LoopMoveResult moves;
  try {
    moves = stc::untangle_loops(s, more.search);
  } catch (const InvalidInput& e) {
    if (report != nullptr) report->refusals.emplace_back(e.what());
    return false;
  }
  if (moves.moves.empty()) return false;
  WeaveState::Checkpoint saved = state.checkpoint();
  if (auto why = replay(state, ctx, moves.hexes, nodes, true, "attached")) {
    state.roll_back(std::move(saved));
    if (report != nullptr) report->refusals.push_back(*why);
    return false;
  }
  state.release(std::move(saved));
  if (report != nullptr) {
    ++report->rounds;
    report->hexes += moves.moves.size();
  }
  return true;
}

}  // namespace

WeaveResult weave_attached(const stc::QuadSurface& surface, const stc::HexComplex& attached,
                           const WeaveOptions& options,
                           const std::vector<std::array<double, 4>>& side_angles,
                           const AttachedWeaveOptions& more, AttachedWeaveReport* report) {
  std::size_t rounds = 0;
  if (report != nullptr) *report = AttachedWeaveReport{};
  std::vector<NodeId> input(surface.num_nodes);
  for (std::size_t v = 0; v < input.size(); ++v) input[v] = NodeId(v);
  return run_weave(
      initial_state(surface, options, side_angles), options,
      rule_budget(surface, options) + attached.hexes.size(),
      [&](WeaveState& state, WeaveContext& ctx) {
        (void)replay(state, ctx, attached, input, false, "attached");
      },
      [&](WeaveState& state, WeaveContext& ctx) {
        return untangle_round(state, ctx, more, report, rounds);
      });
}

}  // namespace stcweave::weave
