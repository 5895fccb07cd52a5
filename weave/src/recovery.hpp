#pragma once
/// \file
/// The block recovery of the driver (`WeaveOptions::block_recovery`, issue 11): what
/// `weave` calls when every (loop, side) of the front is blocked. Private to the library.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "stcweave/weave/kernel.hpp"

namespace stcweave::weave {

/// Weaves `state` on until its front is empty (nothing returned) or it is blocked again (why).
using WeaveRun = std::function<std::optional<std::string>(WeaveState&, WeaveContext&)>;

/// The pillows tried at a blocked front, in the order tried: one face at a time at the first
/// `limits.nodes_per_block` valence-2 nodes (lowest id first; each of their faces, lowest slot
/// first), then at the lowest-valence nodes when there are fewer valence-2 ones, then the whole
/// front; a pillow with a `pillow_conflict` is left out. Each entry: the blocked node
/// (invalid for the whole front) and the faces.
struct RecoveryMove {
  NodeId node;
  std::vector<FaceIndex> faces;
};
[[nodiscard]] std::vector<RecoveryMove> recovery_moves(const WeaveState& state,
                                                       const RecoveryLimits& limits);

/// From the blocked `state` (`why` it is blocked), a depth-first search over `recovery_moves`:
/// each trial is a copy of the state, one pillow, seams, then `run`; a trial that blocks again
/// is searched from where it blocked, up to `ctx.options.recovery` limits. The first trial that
/// completes replaces `state`; its events reach the observer then (those of abandoned trials
/// never do), and the rule count and shrink index continue from it. Returns the pillows kept.
/// \throw WeaveError when no trial completes within the limits (with `why`).
std::vector<Recovery> recover_blocked(WeaveState& state, WeaveContext& ctx, const WeaveRun& run,
                                      const std::string& why);

/// The fill of a blocked front (`WeaveOptions::fill_up_to`, fill.cpp): when the front has at
/// most `up_to` faces (and an even number), the front moves of stc/loop_moves.hpp
/// (`stc::fill_front`) attach hexes to it until nothing is left, knowing the woven hexes at its
/// nodes (no hex on two faces of one of them, no edge or face one of them has); their hexes
/// are then built on the front by `make_hex` (rule "fill"), each checked against the woven
/// complex. Returns nothing when the front is empty now; otherwise why not, with `state` as it
/// was. Counted in `WeaveStats::fill_hexes`.
std::optional<std::string> fill_blocked_front(WeaveState& state, WeaveContext& ctx,
                                              std::size_t up_to);

}  // namespace stcweave::weave
