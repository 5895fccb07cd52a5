#include "stcweave/primal/self_crossing_solids.hpp"

#include <algorithm>
#include <memory>
#include <string>

#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/stc/errors.hpp"
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
                                              SolidsReport* solids, SelfCrossingReport& report,
                                              const SharedSearchBudget& budget) {
  report = SelfCrossingReport{};
  report.used = true;
  SelfCrossingReport sum;  // times of every ball, kept or not
  CutOptions cut = cut_options;
  cut.allow_self_crossing = true;
  // The shared budget (SharedSearchBudget): what is left, the balls that went through the
  // moves, and the last search that gave up.
  std::size_t work_left = budget.work;
  // Every search of every ball draws its evaluations from one pool: the untangling, and also
  // the fills and the rounds during the weaves of the ways (stc::LoopMoveOptions::
  // shared_evaluations), whose deepenings on small fronts are where the time goes when the
  // weaves block (up to 300,000 evaluations each, several seconds).
  const auto pool = std::make_shared<std::size_t>(budget.evaluations);
  std::size_t searched_balls = 0;
  std::size_t gave_up = 0;
  bool exhausted = false;
  std::string last_stop;
  cut.ball_weaver = [&](const SurfaceMesh& ball,
                        const weave::WeaveOptions& ball_options) -> weave::WeaveResult {
    if (exhausted) {
      throw WeaveError(
          "self-intersecting loops: the shared budget of the front-move searches is "
          "used up; this ball is not searched");
    }
    const std::vector<std::array<double, 4>> angles = ball_options.rules == weave::RuleSet::Extended
                                                          ? dihedral_angles(ball)
                                                          : std::vector<std::array<double, 4>>{};
    if (stc::find_loops(ball.surface, stc::FindLoopsOptions{false}).num_self_intersecting() == 0)
      return weave::weave(ball.surface, ball_options, angles);
    SelfCrossingOptions ball_search = options;
    ball_search.search.max_work = std::min(ball_search.search.max_work, work_left);
    ball_search.search.max_evaluations = std::min(ball_search.search.max_evaluations, *pool);
    ball_search.search.shared_evaluations = pool;
    ++searched_balls;
    SelfCrossingReport one;
    const auto charge = [&] {
      sum.search_seconds += one.search_seconds;
      sum.weave_seconds += one.weave_seconds;
      sum.join_seconds += one.join_seconds;
      // The search's own work count is not reported: evaluations times the ball's faces is
      // (a little under) it; a search stopped at the bound used all it was given.
      const std::size_t evaluations = one.moves.evaluations;
      const std::size_t work = evaluations * ball.surface.num_quads();
      const bool at_bound = one.moves.stop_reason.rfind("evaluation bound", 0) == 0;
      const std::size_t charged = at_bound && evaluations < ball_search.search.max_evaluations
                                      ? std::max(work, ball_search.search.max_work)
                                      : work;
      work_left -= std::min(work_left, charged);
      if (work_left == 0 || *pool == 0) exhausted = true;
    };
    try {
      weave::WeaveResult r = weave_self_crossing(ball, ball_options, angles, ball_search, one);
      charge();
      const double search = sum.search_seconds;
      const double weave = sum.weave_seconds;
      const double join = sum.join_seconds;
      sum = one;  // the last ball woven through the moves
      sum.search_seconds = search;
      sum.weave_seconds = weave;
      sum.join_seconds = join;
      return r;
    } catch (const WeaveError& e) {
      charge();
      if (!one.moves.simple) {
        ++gave_up;
        last_stop = one.moves.stop_reason + " (" + std::to_string(one.moves.moves.size()) +
                    " hexes attached, " + std::to_string(one.moves.self_crossing_quads_after) +
                    " of " + std::to_string(one.moves.self_crossing_quads_before) +
                    " self-crossing quads left)";
      }
      throw;
    } catch (...) {
      charge();
      throw;
    }
  };
  const auto budget_words = [&] {
    return std::to_string(searched_balls) + " cut balls went through the front moves, " +
           std::to_string(gave_up) + " of whose searches gave up (the last: " + last_stop +
           "); shared budget " + std::to_string(budget.work) + " face evaluations and " +
           std::to_string(budget.evaluations) + " moves, " + std::to_string(work_left) + " and " +
           std::to_string(*pool) + " left";
  };
  weave::WeaveResult result;
  try {
    result = weave_solids(mesh, weave_options, cut, solids);
  } catch (const Unsupported& e) {
    // A refusal after searches that gave up is a search that gave up (exit code 3), not an
    // input outside what is supported.
    if (gave_up == 0 && !exhausted) throw;
    throw WeaveError(std::string("self-intersecting loops on a solid with handles: ") +
                     (exhausted ? "the front-move searches used up their shared budget"
                                : "the front-move searches gave up") +
                     " (" + budget_words() +
                     "); re-mesh the surface so that fewer loops cross themselves. The disc "
                     "search said: " +
                     e.what());
  }
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
