#pragma once
/// \file
/// The driver's entry for callers inside weave/ that start from a state of their own (the
/// hexes attached before the weave, attached.cpp): `weave` is `run_weave` on the input's front.

#include <array>
#include <cstddef>
#include <functional>
#include <vector>

#include "stcweave/weave/kernel.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::weave {

/// The front of `surface` with the input's angles (`side_angles`, empty or one entry per quad),
/// checked. \throw InvalidInput as `weave`.
WeaveState initial_state(const stc::QuadSurface& surface, const WeaveOptions& options,
                         const std::vector<std::array<double, 4>>& side_angles);

/// The rule budget of `weave`: `options.max_rules`, or 8 * quads^1.5 + 20000.
std::size_t rule_budget(const stc::QuadSurface& surface, const WeaveOptions& options);

/// Runs the driver (weave.cpp) on `state` with `options` and a budget of `max_rules` rule
/// applications. `prepare`, when set, is called once with the state and the context before the
/// first seam pass (the rules it applies count against the budget and are traced).
/// `on_blocked`, when set, is called when every (loop, side) is blocked, before the recovery
/// pillows: when it changed the front (and returns true) the weave goes on from there.
/// \throw as `weave`.
WeaveResult run_weave(WeaveState state, const WeaveOptions& options, std::size_t max_rules,
                      const std::function<void(WeaveState&, WeaveContext&)>& prepare,
                      const std::function<bool(WeaveState&, WeaveContext&)>& on_blocked);

}  // namespace stcweave::weave
