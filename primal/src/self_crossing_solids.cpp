#include "stcweave/primal/self_crossing_solids.hpp"

#include <algorithm>
#include <string>

#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/stc/loops.hpp"

namespace stcweave::primal {

// Why cut first (route (a) of the task): the cut discs are planned on the input's loops and
// its handle diagnosis reads the input's points, both of which the front moves would change
// (the attached hexes' nodes have no position of their own); once cut, every ball is a genus-0
// surface, which is exactly what `weave_self_crossing` takes. A cut that adds self-crossing
// quads is discarded, so the moves never face more crossings than the input has.
weave::WeaveResult weave_solids_self_crossing(const SurfaceMesh& mesh,
                                              const weave::WeaveOptions& weave_options,
                                              const CutOptions& cut_options,
                                              const SelfCrossingOptions& options,
                                              SolidsReport* solids, SelfCrossingReport& report) {
  report = SelfCrossingReport{};
  report.used = true;
  SelfCrossingReport sum;  // times of every ball, kept or not
  CutOptions cut = cut_options;
  cut.allow_self_crossing = true;
  cut.ball_weaver = [&](const SurfaceMesh& ball,
                        const weave::WeaveOptions& ball_options) -> weave::WeaveResult {
    const std::vector<std::array<double, 4>> angles = ball_options.rules == weave::RuleSet::Extended
                                                          ? dihedral_angles(ball)
                                                          : std::vector<std::array<double, 4>>{};
    if (stc::find_loops(ball.surface, stc::FindLoopsOptions{false}).num_self_intersecting() == 0)
      return weave::weave(ball.surface, ball_options, angles);
    SelfCrossingReport one;
    const auto add_times = [&] {
      sum.search_seconds += one.search_seconds;
      sum.weave_seconds += one.weave_seconds;
      sum.join_seconds += one.join_seconds;
    };
    try {
      weave::WeaveResult r = weave_self_crossing(ball, ball_options, angles, options, one);
      add_times();
      const double search = sum.search_seconds;
      const double weave = sum.weave_seconds;
      const double join = sum.join_seconds;
      sum = one;  // the last ball woven through the moves
      sum.search_seconds = search;
      sum.weave_seconds = weave;
      sum.join_seconds = join;
      return r;
    } catch (...) {
      add_times();
      throw;
    }
  };
  weave::WeaveResult result = weave_solids(mesh, weave_options, cut, solids);
  report = sum;
  report.used = true;
  report.attached_hexes = static_cast<std::size_t>(
      std::count(result.hex_rule.begin(), result.hex_rule.end(), std::string("attached")));
  report.pillow_hexes = static_cast<std::size_t>(
      std::count(result.hex_rule.begin(), result.hex_rule.end(), std::string("pillow")));
  report.woven_hexes = result.complex.hexes.size() - report.attached_hexes - report.pillow_hexes;
  report.pillowed = report.pillow_hexes > 0;
  return result;
}

}  // namespace stcweave::primal
