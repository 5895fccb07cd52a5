/// The driver: the seed's Fig. 15 in code (extended Reliable Whisker Weaving, sect. 7).
///
/// Read it top to bottom; every step names the file that holds it:
///
///   seams over the whole front                            rules/seam.cpp
///   until the front is empty:
///     non-convexity seams where they apply (extended)     rules/nonconvexity_seam.cpp
///     the loops of the front and their properties         rules/front_loops.cpp,
///                                                         select/properties.cpp
///     parallel merging (extended): closes a layer         rules/parallel_merging.cpp
///     rank the (loop, side) candidates by the filters     select/filters.cpp
///     shrink the first that shrinks (backtracking)        rules/shrink.cpp (cross.cpp,
///                                                         blind_chord.cpp, seam.cpp)
///     seams                                               rules/seam.cpp
///
/// Why it ends with a closed complex: every rule replaces front faces by faces of a new hex
/// (cross, blind chord formation, parallel merging) or glues two front faces that met (seam,
/// non-convexity seam), so the front stays a closed oriented quad surface (checked after
/// every rule with `check`); each shrink builds one sheet of hexes and removes its loop. The
/// weave ends when the front is empty: every hex face is then glued to another hex face or is
/// an input quad. Propagation of depth and angles (sect. 6, rules/propagate.cpp) happens
/// inside `make_hex`, which every hex-making rule calls (kernel.cpp).
///
/// The trace is not written here: the driver tells its observer (trace.cpp) what it did.

#include "stcweave/weave/weave.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "driver.hpp"
#include "recovery.hpp"
#include "select/bounded.hpp"
#include "select/candidates.hpp"
#include "select/face_table.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/front_pillow.hpp"
#include "stcweave/weave/kernel.hpp"
#include "stcweave/weave/rules.hpp"
#include "stcweave/weave/select.hpp"
#include "trace.hpp"

namespace stcweave::weave {

WeaveState initial_state(const stc::QuadSurface& surface, const WeaveOptions& options,
                         const std::vector<std::array<double, 4>>& side_angles) {
  WeaveState state(surface);
  if (options.rules == RuleSet::Extended) check_parameters(options.extended);
  if (!side_angles.empty()) {
    if (side_angles.size() != surface.quads.size()) {
      throw InvalidInput("weave: " + std::to_string(side_angles.size()) +
                         " side angle entries for " + std::to_string(surface.quads.size()) +
                         " quads");
    }
    // Input quad q is front face q: the front adds them in order into an empty slot list.
    for (std::size_t q = 0; q < side_angles.size(); ++q) {
      std::array<float, 4> angle{};
      for (std::size_t k = 0; k < 4; ++k) angle[k] = static_cast<float>(side_angles[q][k]);
      state.front.set_side_angles(static_cast<FaceIndex>(q), angle);
    }
  }
  if (auto err = state.front.check_invariants())
    throw InvalidInput("the surface is not a closed oriented manifold quad surface: " + *err);
  return state;
}

std::size_t rule_budget(const stc::QuadSurface& surface, const WeaveOptions& options) {
  if (options.max_rules != 0) return options.max_rules;
  const double q = static_cast<double>(surface.quads.size());
  return static_cast<std::size_t>(8.0 * q * std::sqrt(q)) + 20000;
}

namespace {

/// Shrinks the first candidate of `ranking` that shrinks. Backtracking: a shrink that ends
/// blocked is undone (a checkpoint of the state is taken before it) and the next candidate is
/// tried; when every candidate fails from this front, the first one's partial shrink is kept (the
/// front changed, so the selection starts again) as the last resort. False when nothing changed;
/// `failures` then says why for each candidate. When `exact` is set, only the first candidate
/// of `ranking` is known (select/bounded.hpp): after it fails on an unchanged front, `exact`
/// gives the full ranking of that front.
bool shrink_a_candidate(WeaveState& state, WeaveContext& ctx, const FrontLoops& loops,
                        Ranking ranking, std::string& failures,
                        const std::function<Ranking()>& exact = {}) {
  bool partial = static_cast<bool>(exact);
  const std::vector<TraceCandidate>& candidates = ranking.order;
  const bool backtrack = ctx.options.backtrack;
  for (std::size_t attempt = 0; attempt < (backtrack ? 2U : 1U); ++attempt) {
    const bool last_resort = backtrack && attempt == 1;
    if (last_resort && !ctx.options.keep_partial_shrink) break;
    const std::size_t count =
        last_resort ? std::min<std::size_t>(1, candidates.size()) : candidates.size();
    for (std::size_t ci = 0; ci < count; ++ci) {
      const TraceCandidate& c = candidates[ci];
      if (ctx.observer != nullptr) {
        const std::string reason =
            last_resort ? "every candidate failed: the first one's partial shrink is kept"
            : ci == 0   ? ranking.reason
                        : "previous candidates failed to shrink";
        ctx.observer->on_selection(ctx.rules_applied, ctx.shrink_index + 1, candidates, ci, reason,
                                   ranking.filters,
                                   ci == 0 && !last_resort ? ranking.decided_by : "fallback");
      }
      ++ctx.shrink_index;
      const std::size_t before = ctx.rules_applied;
      std::optional<WeaveState::Checkpoint> saved;
      if (backtrack && !last_resort) saved = state.checkpoint();
      const std::size_t blocked_before = state.blocked_seams.size();
      auto failure = shrink(state, ctx, loops.strips[static_cast<std::size_t>(c.loop)],
                            static_cast<stc::LoopSide>(c.side));
      if (!failure && saved && ctx.options.undo_seam_blocking_shrinks &&
          state.blocked_seams.size() > blocked_before) {
        failure = "it left " + std::to_string(state.blocked_seams.size() - blocked_before) +
                  " seam(s) blocked";
      }
      if (!failure) {
        if (saved) state.release(std::move(*saved));
        ++state.stats.shrinks;
        return true;
      }
      ++state.stats.failed_shrinks;
      if (ctx.observer != nullptr)
        ctx.observer->on_shrink_failed(ctx.rules_applied, ctx.shrink_index,
                                       *failure + (saved ? " (undone)" : ""));
      if (failures.size() < 2000) {
        failures +=
            "\n  loop " + std::to_string(c.loop) + " side " + "AB"[c.side] + ": " + *failure;
      }
      if (saved) {
        state.roll_back(std::move(*saved));
        ++state.stats.rolled_back_shrinks;
      } else if (ctx.rules_applied != before) {
        return true;  // the front changed: select again
      }
      if (partial) {  // the front is the selection's again: rank every candidate
        ranking = exact();
        partial = false;
      }
    }
  }
  return false;
}

/// With `check`: the bounded ranking's first candidate is the full ranking's.
void check_bounded(const Ranking& bounded, const Ranking& full) {
  if (bounded.order.size() != full.order.size())
    throw InternalError("weave: the bounded selection has " + std::to_string(bounded.order.size()) +
                        " candidates, not " + std::to_string(full.order.size()));
  if (full.order.empty()) return;
  const TraceCandidate& b = bounded.order.front();
  const TraceCandidate& f = full.order.front();
  if (b.loop != f.loop || b.side != f.side || b.weight != f.weight ||
      b.strictly_on_side != f.strictly_on_side || b.on_strip != f.on_strip ||
      b.faces_collapsed != f.faces_collapsed || b.depth != f.depth ||
      bounded.reason != full.reason || bounded.decided_by != full.decided_by) {
    throw InternalError("weave: the bounded selection chose loop " + std::to_string(b.loop) +
                        " side " + "AB"[b.side] + " (weight " + std::to_string(b.weight) +
                        ") where every weight gives loop " + std::to_string(f.loop) + " side " +
                        "AB"[f.side] + " (weight " + std::to_string(f.weight) + ")");
  }
}

/// The result: canonical node ids, input nodes unchanged, interior nodes compacted in order of
/// creation.
WeaveResult assemble(WeaveState&& state) {
  const Front& front = state.front;
  WeaveResult result;
  result.num_input_nodes = front.num_input_nodes();
  std::vector<NodeId> renumber(front.num_nodes(), NodeId::invalid());
  std::size_t next = front.num_input_nodes();
  for (std::size_t n = 0; n < front.num_input_nodes(); ++n) renumber[n] = NodeId(n);
  for (std::size_t n = front.num_input_nodes(); n < front.num_nodes(); ++n)
    if (front.find(NodeId(n)) == NodeId(n)) renumber[n] = NodeId(next++);
  result.complex.num_nodes = next;
  result.complex.hexes.reserve(state.woven.hexes.size());
  for (const stc::Hex& h : state.woven.hexes) {
    stc::Hex out{};
    for (std::size_t i = 0; i < 8; ++i) out[i] = renumber[front.find(h[i]).index()];
    result.complex.hexes.push_back(out);
  }
  result.dual = std::move(state.woven.dual);
  result.hex_shrink = std::move(state.woven.hex_shrink);
  result.hex_rule = std::move(state.woven.hex_rule);
  result.hex_node = std::move(state.woven.hex_node);
  result.stats = state.stats;
  return result;
}

using BlockedHook = std::function<bool(WeaveState&, WeaveContext&)>;

/// The loop of Fig. 15 on `state` until the front is empty (nothing returned) or every
/// (loop, side) is blocked (why, returned). `bounded`: nothing reads the candidates after the
/// first, so the reliable selection may use branch and bound (select/bounded.hpp) and a
/// geometric one computes side properties only where its filters read them
/// (select/candidates.hpp). `on_blocked`: as in `run_weave`.
std::optional<std::string> weave_front(WeaveState& state, WeaveContext& ctx,
                                       const Selection& selection, bool bounded,
                                       const BlockedHook& on_blocked) {
  const WeaveOptions& options = ctx.options;
  const ExtendedParameters& par = options.extended;
  const bool extended = options.rules == RuleSet::Extended;
  std::size_t best_weight = 0;  // the last bounded selection's, where the next one starts
  while (state.front.num_faces() > 0) {
    // Fig. 15, "apply the non-convexity seam rule if necessary".
    if (extended && par.nonconvexity_seam && nonconvexity_seams(state, ctx) > 0 &&
        state.front.num_faces() == 0)
      break;

    // "Compute the loop properties to get S": two candidates per loop, side A and side B.
    // The lazy geometric selection builds the front's face table once and reads the loops and
    // components from it too (select/face_table.hpp): lookups instead of incidence scans.
    const bool lazy_selection = bounded && selection.geometric;
    std::optional<FaceTable> table;
    if (lazy_selection) table.emplace(face_table(state.front, true));
    const FrontLoops loops = table ? front_loops(state.front, *table) : front_loops(state.front);
    const FrontComponents components = table ? front_components(state.front, *table, ctx.nodes)
                                             : front_components(state.front, ctx.nodes);
    const auto all_candidates = [&] {
      return loop_candidates(state.front, loops, components, selection.geometric, par, ctx.nodes,
                             ctx.faces, ctx.faces2);
    };
    // When only the first candidate is read: branch and bound (select/bounded.hpp), or the
    // side properties only of the candidates a filter reads them of (select/candidates.hpp).
    std::optional<CandidateSet> lazy;
    std::vector<TraceCandidate> candidates;
    if (lazy_selection) {
      lazy.emplace(state.front, loops, components, par, ctx.nodes, ctx.faces, ctx.faces2,
                   options.check, std::move(*table));
      if (extended && par.parallel_merging) {
        for (std::size_t i = 0; i + 1 < lazy->all().size(); i += 2)
          if (may_merge_in_parallel(lazy->all()[i], lazy->all()[i + 1]))
            lazy->complete(lazy->all()[i].loop);
      }
    } else if (bounded) {
      candidates = loop_candidates_bounded(state.front, loops, components, ctx.nodes, ctx.faces,
                                           best_weight);
    } else {
      candidates = all_candidates();
    }

    // "Apply the parallel merging filter": it closes a layer by itself and starts again.
    if (extended && par.parallel_merging &&
        apply_parallel_merging(state, ctx, loops, lazy ? lazy->all() : candidates, components))
      continue;

    // The high-level filters rank the candidates (parallel crossing, non-convex, depth,
    // first and second convex, topological; or the reliable weight).
    Ranking ranking = lazy ? rank_first(selection, *lazy) : rank(selection, std::move(candidates));
    ++state.stats.selections;
    const auto exact = [&] { return rank(selection, all_candidates()); };
    if (bounded && options.check) check_bounded(ranking, exact());

    // "Shrink the loop", falling back to the next candidates when it is blocked.
    std::string failures;
    if (!shrink_a_candidate(state, ctx, loops, std::move(ranking), failures,
                            bounded ? std::function<Ranking()>(exact) : nullptr)) {
      if (on_blocked && on_blocked(state, ctx)) {  // e.g. front moves (attached.cpp)
        seam_fixpoint(state, ctx);
        continue;
      }
      if (state.stats.front_pillows < options.recovery_pillows &&
          pillow_blocked_node(state, ctx) > 0) {
        ++state.stats.front_pillows;
        seam_fixpoint(state, ctx);
        continue;
      }
      return "every (loop, side) is blocked with " + std::to_string(state.front.num_faces()) +
             " front faces left and " + std::to_string(state.woven.hexes.size()) +
             " hexes built:" + failures;
    }
    seam_fixpoint(state, ctx);
  }
  return std::nullopt;
}

}  // namespace

WeaveResult weave(const stc::QuadSurface& surface, const WeaveOptions& options,
                  const std::vector<std::array<double, 4>>& side_angles) {
  const auto once = [&](const WeaveOptions& o, const BlockedHook& on_blocked = {},
                        const std::function<void(WeaveState&, WeaveContext&)>& prepare = {}) {
    return run_weave(initial_state(surface, o, side_angles), o, rule_budget(surface, o), prepare,
                     on_blocked);
  };
  // (A rule budget of the caller's is kept: no second weave.)
  if (options.undo_seam_blocking_shrinks || !options.undo_seam_blocking_on_block ||
      !options.backtrack || options.max_rules != 0)
    return once(options);
  // A weave that blocks is woven again in other ways, each from the start, until one completes
  // (docs/weave-recovery.md). The streamed trace of each is held until it is known which weave
  // the caller gets; when every way fails, the first weave's trace and error are given.
  std::vector<TraceEvent> first_trace;
  std::vector<TraceEvent> kept_trace;
  // `o` with its trace events held in `held`.
  const auto holding = [&](WeaveOptions o, std::vector<TraceEvent>& held) {
    if (options.on_trace) o.on_trace = [&held](const TraceEvent& e) { held.push_back(e); };
    return o;
  };
  const auto forward = [&](const std::vector<TraceEvent>& held) {
    for (const TraceEvent& e : held) options.on_trace(e);
  };
  const auto give = [&](WeaveResult r, const std::vector<TraceEvent>& held) {
    forward(held);
    return r;
  };
  try {
    return give(once(holding(options, first_trace)), first_trace);
  } catch (const WeaveError&) {
    const std::exception_ptr blocked = std::current_exception();
    // Undoing the shrinks that leave a seam blocked ("Seams left blocked: the retry").
    WeaveOptions undo = options;
    undo.undo_seam_blocking_shrinks = true;
    try {
      WeaveResult r = once(holding(undo, kept_trace));
      r.stats.seam_undo_retries = 1;
      return give(std::move(r), kept_trace);
    } catch (const WeaveError&) {
      kept_trace.clear();
    }
    if (options.block_recovery == BlockRecovery::Auto && options.fill_up_to > 0) {
      // The fill (docs/weave-recovery.md "The fill"): the front where every candidate first
      // fails, without and with the undoing of those shrinks, then the input itself before any
      // rule, filled by front moves.
      for (int way = 0; way < 3; ++way) {
        WeaveOptions fill = options;
        fill.undo_seam_blocking_shrinks = way == 1;
        fill.block_recovery = BlockRecovery::Off;
        fill.keep_partial_shrink = false;
        bool tried = false;
        const BlockedHook try_fill = [&](WeaveState& state, WeaveContext& ctx) {
          if (tried) return false;
          tried = true;
          return !fill_blocked_front(state, ctx, options.fill_up_to);
        };
        try {
          WeaveResult r =
              once(holding(fill, kept_trace), try_fill, [&](WeaveState& state, WeaveContext& ctx) {
                if (way == 2 && !try_fill(state, ctx))
                  throw WeaveError("weave: the fill of the input left faces");
              });
          r.stats.seam_undo_retries = way == 1 ? 1 : 0;
          return give(std::move(r), kept_trace);
        } catch (const WeaveError&) {
          kept_trace.clear();
        }
      }
    }
    if (options.block_recovery == BlockRecovery::Auto && options.rules == RuleSet::Extended &&
        !options.selection && options.reliable_from_start) {
      // Last, under `extended`: the whole weave with the reliable rules (same section).
      WeaveOptions plain = options;
      plain.rules = RuleSet::Reliable;
      plain.reliable_from_start = false;
      try {
        WeaveResult r = weave(surface, holding(plain, kept_trace), side_angles);
        r.stats.reliable_from_start = 1;
        return give(std::move(r), kept_trace);
      } catch (const WeaveError&) {
      }
    }
    forward(first_trace);
    std::rethrow_exception(blocked);
  }
}

WeaveResult run_weave(WeaveState state, const WeaveOptions& options, std::size_t max_rules,
                      const std::function<void(WeaveState&, WeaveContext&)>& prepare,
                      const BlockedHook& on_blocked) {
  TraceRecorder recorder(options);
  ShrinkRecorder shrinks;
  ObserverList observers;
  observers.add(&shrinks);
  if (options.trace || options.on_trace) observers.add(&recorder);
  if (options.observer != nullptr) observers.add(options.observer);
  WeaveObserver* observer = observers.empty()       ? nullptr
                            : observers.size() == 1 ? observers.front()
                                                    : &observers;
  WeaveContext ctx(options, observer, max_rules);
  const Selection selection = selection_for(options);
  // Nothing reads the candidates after the first one (select/bounded.hpp, candidates.hpp):
  // the built-in reliable selection or any geometric one, with no observer that reads them.
  const bool bounded =
      (observer == nullptr || !observer->reads_every_candidate()) &&
      (selection.geometric || (options.rules != RuleSet::Extended && !options.selection));

  if (prepare) prepare(state, ctx);  // e.g. hexes attached before the weave (attached.cpp)

  // Seams over the whole front first (an input may already hold valence-2 nodes).
  for (std::size_t n = state.front.num_nodes(); n-- > 0;) state.seam_work.push_back(NodeId(n));
  seam_fixpoint(state, ctx);

  std::vector<Recovery> recoveries;
  if (const auto blocked = weave_front(state, ctx, selection, bounded, on_blocked)) {
    // Only a weave that would end blocked gets here (recovery.hpp).
    if (options.block_recovery == BlockRecovery::Off) throw WeaveError("weave: " + *blocked);
    const auto run = [&](WeaveState& s, WeaveContext& c) {
      return weave_front(s, c, selection, bounded, on_blocked);
    };
    try {
      recoveries = recover_blocked(state, ctx, run, *blocked);
    } catch (const WeaveError&) {
      if (options.rules != RuleSet::Extended || options.selection) throw;
      // `extended` found nothing: the rest of the weave with the reliable selection (and its
      // preconditions), from the same blocked front, recovered the same way.
      WeaveOptions plain_options = options;
      plain_options.rules = RuleSet::Reliable;
      const Selection plain = selection_for(plain_options);
      WeaveContext plain_ctx(plain_options, ctx.observer, ctx.max_rules);
      plain_ctx.rules_applied = ctx.rules_applied;
      plain_ctx.shrink_index = ctx.shrink_index;
      const auto run_plain = [&](WeaveState& s, WeaveContext& c) {
        return weave_front(s, c, plain, false, on_blocked);
      };
      const std::size_t hexes_before = state.woven.hexes.size();
      const std::size_t faces_before = state.front.num_faces();
      if (const auto again = run_plain(state, plain_ctx))
        recoveries = recover_blocked(state, plain_ctx, run_plain, *again);
      recoveries.insert(recoveries.begin(),
                        Recovery{hexes_before, faces_before, 0, NodeId::invalid(),
                                 "extended: no pillow completed the weave; reliable from here"});
      ++state.stats.recoveries;
    }
  }

  WeaveResult result = assemble(std::move(state));
  result.trace = recorder.take();
  result.shrinks = shrinks.take();
  result.recoveries = std::move(recoveries);
  return result;
}

}  // namespace stcweave::weave
