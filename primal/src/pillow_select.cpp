/// \file
/// Auto pillowing's comparison (docs/pillowing.md, "When"): which of the pillowed and the
/// unpillowed complex the pipeline keeps when the boundary does not force the pillow.
#include <cstdio>
#include <string>

#include "stcweave/primal/pillow.hpp"

namespace stcweave::primal {
namespace {

std::string figures(const PillowCandidate& c) {
  char text[160];
  std::snprintf(text, sizeof text, "%zu hexes, %zu inverted, min scaled Jacobian %.3f, mean %.3f",
                c.hexes, c.inverted, c.min_scaled_jacobian, c.mean_scaled_jacobian);
  return text;
}

}  // namespace

bool pillow_worth_comparing(const PillowReport& report, const PillowOptions& options) {
  return options.mode == PillowMode::Auto && options.compare && report.applied &&
         report.worst_fixed_corner > 0.0;
}

bool choose_pillowed(const PillowCandidate& pillowed, const PillowCandidate& unpillowed) {
  if (pillowed.inverted != unpillowed.inverted) return pillowed.inverted < unpillowed.inverted;
  return pillowed.min_scaled_jacobian >= unpillowed.min_scaled_jacobian - 1e-9;
}

PillowReport compared_pillow_report(PillowReport pillowed, bool keep_pillow,
                                    const PillowCandidate& with, const PillowCandidate& without) {
  pillowed.compared = true;
  const std::string both = "pillowed: " + figures(with) + "; not pillowed: " + figures(without);
  if (keep_pillow) {
    pillowed.reason += " (compared, pillow kept: " + both + ")";
    return pillowed;
  }
  pillowed.applied = false;
  pillowed.shells_pillowed = 0;
  pillowed.nodes_added = 0;
  pillowed.hexes_added = 0;
  pillowed.reason =
      "auto: not pillowed: every bad fixed corner is positive and the woven "
      "complex positions better (" +
      both + ")";
  return pillowed;
}

}  // namespace stcweave::primal
