/// The block recovery (see recovery.hpp and docs/weave-recovery.md): a bounded depth-first
/// search over pillows of front faces at the blocked nodes, each trial on a copy of the state.

#include "recovery.hpp"

#include <algorithm>
#include <utility>

#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/front_pillow.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

std::string to_string(BlockRecovery recovery) {
  return recovery == BlockRecovery::Off ? "off" : "auto";
}

BlockRecovery block_recovery_from_name(const std::string& name) {
  if (name == "auto") return BlockRecovery::Auto;
  if (name == "off") return BlockRecovery::Off;
  throw InvalidInput("unknown block recovery '" + name + "' (expected auto or off)");
}

namespace {

/// Holds a trial's observer calls until the trial is kept (then they reach `parent`).
class Deferred final : public WeaveObserver {
 public:
  explicit Deferred(WeaveObserver* parent) : parent_(parent) {}
  void on_selection(std::size_t step, std::int32_t shrink,
                    std::span<const TraceCandidate> candidates, std::size_t chosen,
                    const std::string& reason, std::span<const std::string> filters,
                    const std::string& decided_by) override {
    calls_.emplace_back(
        [=, c = std::vector<TraceCandidate>(candidates.begin(), candidates.end()),
         f = std::vector<std::string>(filters.begin(), filters.end())](WeaveObserver& o) {
          o.on_selection(step, shrink, c, chosen, reason, f, decided_by);
        });
  }
  void on_rule(std::size_t step, std::int32_t shrink, const char* rule, NodeId node,
               std::span<const FaceOwner> faces, HexId hex) override {
    calls_.emplace_back([=, f = std::vector<FaceOwner>(faces.begin(), faces.end())](
                            WeaveObserver& o) { o.on_rule(step, shrink, rule, node, f, hex); });
  }
  void on_shrink_failed(std::size_t step, std::int32_t shrink, const std::string& reason) override {
    calls_.emplace_back([=](WeaveObserver& o) { o.on_shrink_failed(step, shrink, reason); });
  }
  [[nodiscard]] bool reads_every_candidate() const override {
    return parent_ != nullptr && parent_->reads_every_candidate();
  }
  /// Hands every held call to the parent, in order.
  void flush() {
    if (parent_ != nullptr)
      for (const auto& call : calls_) call(*parent_);
    calls_.clear();
  }

 private:
  WeaveObserver* parent_;
  std::vector<std::function<void(WeaveObserver&)>> calls_;
};

/// The first line of a block message, at most 300 characters (for `Recovery::why`).
std::string first_refusals(const std::string& why) {
  std::string s = why.substr(0, why.find("\n  ", why.find('\n') + 1));
  std::replace(s.begin(), s.end(), '\n', ' ');
  if (s.size() > 300) s = s.substr(0, 300) + "...";
  return s;
}

/// Rules a recovery trial may apply per face of the front it starts from.
constexpr std::size_t kRulesPerFace = 64;

struct Search {
  WeaveContext& ctx;
  const WeaveRun& run;
  const RecoveryLimits& limits;
  std::size_t trials = 0;

  /// True when the blocked `state` was woven to the end; `path` then ends with the pillows.
  bool from(WeaveState& state, const std::string& why, std::size_t depth,
            std::vector<Recovery>& path) {
    if (depth >= limits.max_depth) return false;
    for (RecoveryMove& m : recovery_moves(state, limits)) {
      if (trials >= limits.max_trials) return false;
      ++trials;
      const std::size_t rules = ctx.rules_applied;
      const std::int32_t shrink = ctx.shrink_index;
      WeaveObserver* const observer = ctx.observer;
      Deferred events(observer);
      if (observer != nullptr) ctx.observer = &events;
      const Recovery kept{state.woven.hexes.size(), state.front.num_faces(), m.faces.size(), m.node,
                          first_refusals(why)};
      WeaveState trial = state;
      std::optional<std::string> again;
      bool gave_up = false;
      // A trial's own rule budget: kRulesPerFace per face of its front (a weave of a front of
      // F faces that needs more is running away; without it an `extended` trial could spend the
      // whole budget of the input, up to minutes on a 18-quad sphere).
      const std::size_t max_rules = ctx.max_rules;
      ctx.max_rules = std::min(
          max_rules, rules + kRulesPerFace * (state.front.num_faces() + 4 * m.faces.size()));
      try {
        ctx.relax_geometry = false;
        pillow_faces(trial, ctx, m.faces);
        seam_fixpoint(trial, ctx);
        again = run(trial, ctx);
      } catch (const WeaveError& e) {  // the rule budget
        again = e.what();
        gave_up = true;
      }
      ctx.max_rules = max_rules;
      std::vector<Recovery> rest;
      const bool done = !again || (!gave_up && from(trial, *again, depth + 1, rest));
      ctx.observer = observer;
      ctx.relax_geometry = false;
      if (done) {
        events.flush();
        state = std::move(trial);
        path.push_back(kept);
        path.insert(path.end(), rest.begin(), rest.end());
        return true;
      }
      ctx.rules_applied = rules;
      ctx.shrink_index = shrink;
    }
    return false;
  }
};

}  // namespace

std::vector<RecoveryMove> recovery_moves(const WeaveState& state, const RecoveryLimits& limits) {
  const Front& front = state.front;
  std::vector<std::pair<std::size_t, NodeId>> nodes;  // (valence, node), canonical nodes only
  for (std::size_t n = 0; n < front.num_nodes(); ++n) {
    const NodeId v(n);
    if (front.find(v) != v || front.valence(v) == 0) continue;
    nodes.emplace_back(front.valence(v), v);
  }
  std::sort(nodes.begin(), nodes.end());
  std::vector<RecoveryMove> moves;
  for (std::size_t i = 0; i < std::min(nodes.size(), limits.nodes_per_block); ++i) {
    std::vector<FaceIndex> at = front.faces_at(nodes[i].second);
    std::sort(at.begin(), at.end());
    for (FaceIndex f : at)
      if (!pillow_conflict(state, {f})) moves.push_back({nodes[i].second, {f}});
  }
  // The whole front, unless two of its faces share two edges (a valence-2 node): their two
  // pillow hexes would then share two faces.
  if (!nodes.empty() && nodes.front().first > 2) {
    RecoveryMove all{NodeId::invalid(), {}};
    for (std::size_t f = 0; f < front.face_capacity(); ++f)
      if (front.is_alive(static_cast<FaceIndex>(f))) all.faces.push_back(static_cast<FaceIndex>(f));
    if (!pillow_conflict(state, all.faces)) moves.push_back(std::move(all));
  }
  return moves;
}

std::vector<Recovery> recover_blocked(WeaveState& state, WeaveContext& ctx, const WeaveRun& run,
                                      const std::string& why) {
  const RecoveryLimits& limits = ctx.options.recovery;
  if (state.front.num_faces() % 2 != 0) {
    // Every rule and every pillow keeps the parity of the front: no trial can complete.
    throw WeaveError("weave: " + why + "\n  block recovery: not tried, the front has an odd " +
                     "number of faces (no hex mesh has an odd quad boundary)");
  }
  Search search{ctx, run, limits};
  std::vector<Recovery> path;
  bool done = search.from(state, why, 0, path);
  std::size_t trials = search.trials;
  RecoveryLimits wider = limits;
  // A second, wider search when the first finds nothing (a weave it completes is unchanged):
  // ten times the trials and 2.5 times the depth. Not under `extended` with its reliable
  // fallback (weave.cpp), which is searched the same way, nor on a front small enough for the
  // fill of a blocked front that `weave` tries next (`WeaveOptions::fill_up_to`): measured on
  // the 16-quad spheres of tests/weave/complete_test.cpp, once the rules check their contacts
  // the wider search on a blocked 4-face front took 16 s and completed nothing.
  const bool has_fallback = ctx.options.rules == RuleSet::Extended && !ctx.options.selection;
  const bool fill_next = ctx.options.block_recovery == BlockRecovery::Auto &&
                         state.front.num_faces() <= ctx.options.fill_up_to;
  if (!done && !has_fallback && !fill_next && limits.max_trials > 0) {
    wider.max_trials = 10 * limits.max_trials;
    wider.max_depth = limits.max_depth * 5 / 2;
    Search second{ctx, run, wider};
    path.clear();
    done = second.from(state, why, 0, path);
    trials += second.trials;
  }
  if (!done) {
    throw WeaveError("weave: " + why + "\n  block recovery: no sequence of at most " +
                     std::to_string(wider.max_depth) + " pillows completed the weave in " +
                     std::to_string(trials) + " trials (a defect of the weaver: please " +
                     "report the input; --block-recovery off shows the first block alone)");
  }
  state.stats.recoveries = path.size();
  state.stats.recovery_trials = trials;
  return path;
}

}  // namespace stcweave::weave
