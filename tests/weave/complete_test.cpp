// A weave that always completes (issue 11): the block recovery (WeaveOptions::block_recovery,
// on by default) on every sphere quadrangulation of a closure enumerated in the test
// (tests/weave/sphere_enum.hpp: from the cube by every node split and every cut in five, each
// map once; up to 18 quads by default, 20 on request), the 12-quad case of the issue and the seeded
// family of sphere_quads.hpp, under both rule sets. Every sphere quadrangulation with an even
// number of quads has a hex mesh, so a weave that still throws here is a defect of the weaver, and
// fails the test.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "sphere_enum.hpp"
#include "sphere_quads.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/validate.hpp"
#include "stcweave/weave/weave.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

/// `check` (the front's invariants after every rule) costs most of the time of the family
/// tests; the result is certified by `stc::validate_hex_complex` either way.
WeaveOptions options_for(RuleSet rules, BlockRecovery recovery = BlockRecovery::Auto,
                         bool check = false, bool retry = true) {
  WeaveOptions o;
  o.rules = rules;
  o.check = check;
  o.block_recovery = recovery;
  o.undo_seam_blocking_on_block = retry;
  return o;
}

/// What one shape gave: blocked without recovery (and without the retry that undoes the
/// shrinks leaving a seam blocked), completed with both, its hexes.
struct Outcome {
  bool blocked_before = false;
  bool completed = false;
  bool retried = false;     ///< the weave kept is the retry undoing those shrinks
  bool filled = false;      ///< ... is completed by the fill of its first blocked front
  bool from_start = false;  ///< ... is the reliable one from the start (extended only)
  std::size_t hexes = 0;
  std::size_t recoveries = 0;
  std::string error;
};

Outcome weave_both_ways(const stc::QuadSurface& s, RuleSet rules) {
  Outcome out;
  try {
    (void)weave(s, options_for(rules, BlockRecovery::Off, false, false));
  } catch (const WeaveError&) {
    out.blocked_before = true;
  }
  try {
    const WeaveResult r = weave(s, options_for(rules));
    const stc::ValidationReport v = stc::validate_hex_complex(r.complex, &s);
    EXPECT_TRUE(v.valid) << v.summary();
    out.completed = v.valid;
    out.hexes = r.complex.hexes.size();
    out.recoveries = r.stats.recoveries;
    out.filled = r.stats.fill_hexes > 0;
    out.from_start = r.stats.reliable_from_start > 0;
    out.retried = r.stats.seam_undo_retries > 0 && !out.filled && !out.from_start;
    if (out.filled) {
      const auto fill = std::count(r.hex_rule.begin(), r.hex_rule.end(), "fill");
      EXPECT_EQ(static_cast<std::size_t>(fill), r.stats.fill_hexes) << "hexes of rule fill";
    }
    EXPECT_EQ(r.recoveries.size(), r.stats.recoveries);
    // The recovery, the retry, the fill and the reliable weave from the start act only when
    // the weave would block, and one of them then.
    EXPECT_EQ(out.recoveries > 0 || out.retried || out.filled || out.from_start, out.blocked_before)
        << "the recovery, the retry, the fill or the reliable weave act exactly when the weave "
           "would block";
  } catch (const WeaveError& e) {
    out.error = e.what();
  }
  return out;
}

const std::map<std::size_t, std::vector<stc::QuadSurface>>& closure() {
  static const auto c = test::sphere_closure(18);
  return c;
}

TEST(SphereClosure, CountsAreThoseOfTheEnumeration) {
  // Distinct maps (up to relabelling and rotation; mirror images count twice) with 6..18
  // quads. Pinned so that a change of the generator is seen.
  std::map<std::size_t, std::size_t> counts;
  for (const auto& [n, shapes] : closure()) counts[n] = shapes.size();
  const std::map<std::size_t, std::size_t> expected = {
      {6, 1},   {7, 0},   {8, 1},    {9, 1},    {10, 4},    {11, 3},   {12, 16},
      {13, 26}, {14, 99}, {15, 256}, {16, 895}, {17, 2789}, {18, 9740}};
  for (const auto& [n, c] : counts) std::cout << "quads " << n << ": " << c << "\n";
  EXPECT_EQ(counts, expected);
}

TEST(SphereClosure, HoldsTheIssueCase) {
  const stc::QuadSurface issue = test::issue11_twelve_quads();
  stc::QuadSurface mirror = issue;
  for (stc::Quad& q : mirror.quads) q = stc::reversed(q);
  const auto code = test::canonical_code(issue);
  const auto mirror_code = test::canonical_code(mirror);
  bool found = false;
  for (const auto& s : closure().at(12)) {
    const auto c = test::canonical_code(s);
    found = found || c == code || c == mirror_code;
  }
  EXPECT_TRUE(found);
}

/// Loop-clean shapes of the closure with `quads` quads, and how many stay blocked with the
/// recovery (pinned).
struct ClosureCase {
  std::size_t quads;
  std::size_t loop_clean;
  std::size_t blocked_reliable;
  std::size_t blocked_extended;
  std::size_t extended_every = 1;  ///< under extended, every n-th loop-clean shape only
};

/// The quad count names a case (in gtest's and ctest's test names).
// NOLINTNEXTLINE(readability-identifier-naming): gtest looks the printer up by this name.
void PrintTo(const ClosureCase& c, std::ostream* os) {
  *os << c.quads << "_quads";
}

/// What the loop-clean shapes of one count gave under one rule set.
struct Tally {
  std::size_t shapes = 0;
  std::size_t blocked = 0;                   ///< without recovery
  std::size_t still = 0;                     ///< with it
  std::size_t retried = 0;                   ///< completed by the retry undoing the shrinks
  std::size_t filled = 0;                    ///< completed by the fill of a blocked front
  std::size_t from_start = 0;                ///< the reliable weave from the start (extended)
  std::vector<std::size_t> recovered_hexes;  ///< of the shapes it recovered, sorted
};

/// Weaves every `every`-th loop-clean shape of `shapes` (1: all) under `rules`, each without and
/// with the recovery, certifying what completes.
Tally weave_loop_clean(const std::vector<stc::QuadSurface>& shapes, RuleSet rules,
                       std::size_t every) {
  Tally t;
  std::size_t index = 0;
  for (const auto& s : shapes) {
    if (stc::find_loops(s).num_self_intersecting() != 0) continue;
    if (index++ % every != 0) continue;
    ++t.shapes;
    const Outcome o = weave_both_ways(s, rules);
    t.blocked += o.blocked_before ? 1 : 0;
    t.retried += o.retried ? 1 : 0;
    t.filled += o.filled ? 1 : 0;
    t.from_start += o.from_start ? 1 : 0;
    if (!o.completed) {
      ++t.still;
      std::cout << s.quads.size() << " quads, " << to_string(rules) << ", loop-clean shape "
                << index - 1 << " still blocked: " << o.error.substr(0, 200) << "\n";
    } else if (o.blocked_before) {
      t.recovered_hexes.push_back(o.hexes);
    }
  }
  std::sort(t.recovered_hexes.begin(), t.recovered_hexes.end());
  const auto& h = t.recovered_hexes;
  std::cout << (shapes.empty() ? 0 : shapes.front().quads.size()) << " quads, " << to_string(rules)
            << ": " << t.shapes << " loop-clean shapes woven (every " << every
            << "), blocked without recovery " << t.blocked << ", completed by the retry "
            << t.retried << ", by the fill " << t.filled << ", reliable from the start "
            << t.from_start << ", still blocked " << t.still << ", recovered hexes max "
            << (h.empty() ? 0 : h.back()) << " median " << (h.empty() ? 0 : h[h.size() / 2])
            << "\n";
  return t;
}

class EveryEvenSphere : public ::testing::TestWithParam<ClosureCase> {};

TEST_P(EveryEvenSphere, WeavesUnderBothRuleSets) {
  const ClosureCase& c = GetParam();
  const Tally reliable = weave_loop_clean(closure().at(c.quads), RuleSet::Reliable, 1);
  const Tally extended =
      weave_loop_clean(closure().at(c.quads), RuleSet::Extended, c.extended_every);
  EXPECT_EQ(reliable.shapes, c.loop_clean);
  // Known defects left (docs/weave-recovery.md): one more fails the test, one fewer asks for
  // the pinned count to be lowered.
  EXPECT_EQ(reliable.still, c.blocked_reliable) << "reliable, still blocked";
  EXPECT_EQ(extended.still, c.blocked_extended) << "extended, still blocked";
}

// Since the hex-making rules and the recovery's pillows check their contacts (2026-12-07: no
// hex sharing four nodes off a face with another), 2 of the 18 loop-clean 16-quad shapes stay
// blocked under reliable and 1 under extended, and 7 and 6 of the 95 18-quad ones (about 50 s
// and 5 minutes). Before, every shape up to 18 quads completed, but those complexes held hexes
// sharing four nodes off a face (valid only under the old certificate; docs/weave-recovery.md).
INSTANTIATE_TEST_SUITE_P(Closure, EveryEvenSphere,
                         ::testing::Values(ClosureCase{6, 1, 0, 0}, ClosureCase{8, 0, 0, 0},
                                           ClosureCase{10, 1, 0, 0}, ClosureCase{12, 4, 0, 0},
                                           ClosureCase{14, 4, 0, 0}, ClosureCase{16, 18, 2, 1},
                                           ClosureCase{18, 95, 7, 6}),
                         [](const auto& info) { return std::to_string(info.param.quads); });

TEST(SphereClosureSlow, TwentyQuads) {
  // The closure up to 20 quads (115,024 maps with 20, about 1.5 minutes to enumerate) and
  // its 420 loop-clean 20-quad shapes under both rule sets: minutes, so only on request.
  if (std::getenv("STCWEAVE_SLOW_TESTS") == nullptr)
    GTEST_SKIP() << "set STCWEAVE_SLOW_TESTS=1 to run the 20-quad closure (slow)";
  const auto c = test::sphere_closure(20);
  EXPECT_EQ(c.at(19).size(), 32799U);
  ASSERT_EQ(c.at(20).size(), 115024U);
  // Every completed weave is certified (weave_both_ways). Since the hex-making rules and the
  // pillows check their contacts (2026-12-07), 49 of the 420 stay blocked under reliable; the
  // retry undoing the shrinks that leave a seam blocked completes 25, the fill of the first
  // blocked front 18 (docs/weave-recovery.md "The fill"). Before, none stayed blocked, but
  // several complexes held hexes sharing four nodes off a face.
  const Tally reliable = weave_loop_clean(c.at(20), RuleSet::Reliable, 1);
  EXPECT_EQ(reliable.shapes, 420U);
  EXPECT_EQ(reliable.still, 49U) << "reliable, still blocked";
  EXPECT_EQ(reliable.retried, 25U) << "reliable, completed by the retry";
  EXPECT_EQ(reliable.filled, 18U) << "reliable, completed by the fill";
  // The extended pins below are those of before 2026-12-07, not measured again: the run of
  // this test that day was stopped after 255 of the 420 shapes under extended, 16 of them
  // still blocked, so this part fails until it is re-pinned.
  const Tally extended = weave_loop_clean(c.at(20), RuleSet::Extended, 1);
  EXPECT_EQ(extended.still, 0U) << "extended, still blocked";
  EXPECT_EQ(extended.retried, 3U) << "extended, completed by the retry";
  EXPECT_EQ(extended.filled, 2U) << "extended, completed by the fill";
  EXPECT_EQ(extended.from_start, 4U) << "extended, the reliable weave from the start";
}

TEST(BlockRecovery, CompletesTheIssueCase) {
  const stc::QuadSurface s = test::issue11_twelve_quads();
  for (RuleSet rules : {RuleSet::Reliable, RuleSet::Extended}) {
    EXPECT_THROW((void)weave(s, options_for(rules, BlockRecovery::Off, true)), WeaveError);
    const WeaveResult r = weave(s, options_for(rules, BlockRecovery::Auto, true));
    const stc::ValidationReport v = stc::validate_hex_complex(r.complex, &s);
    EXPECT_TRUE(v.valid) << to_string(rules) << ": " << v.summary();
    EXPECT_GT(r.stats.recoveries, 0U);
    ASSERT_FALSE(r.recoveries.empty());
    EXPECT_NE(r.recoveries.front().why.find("blocked"), std::string::npos);
    std::cout << to_string(rules) << ": " << r.complex.hexes.size() << " hexes, "
              << r.stats.recoveries << " recoveries, " << r.stats.recovery_trials << " trials\n";
  }
}

TEST(BlockRecovery, CompletesTheSeededFamily) {
  // The seeded family of recovery_test.cpp up to 16 quads: how many stay blocked with the
  // recovery (pinned; without it 1 + 6 of 3 + 10 shapes block at 12 and 16 quads). At 20
  // quads one shape stays blocked under reliable (docs/weave-recovery.md; too slow here).
  std::array<std::size_t, 2> still_blocked{};
  for (std::size_t n : {10, 12, 14, 16}) {
    for (const auto& s : test::seeded_family(n, 400, 11)) {
      for (RuleSet rules : {RuleSet::Reliable, RuleSet::Extended}) {
        const Outcome o = weave_both_ways(s, rules);
        if (o.completed) continue;
        ++still_blocked[rules == RuleSet::Reliable ? 0 : 1];
        std::cout << n << " quads, " << to_string(rules) << ": " << o.error.substr(0, 200) << "\n";
      }
    }
  }
  EXPECT_EQ(still_blocked[0], 0U) << "reliable";
  EXPECT_EQ(still_blocked[1], 0U) << "extended";
}

TEST(BlockRecovery, LeavesAWeaveThatCompletesAlone) {
  // Boxes complete without recovery: the result is the one with the recovery off, unchanged.
  for (const int k : {2, 3}) {
    const auto box = test::box_surface(k, k + 1, 2);
    for (RuleSet rules : {RuleSet::Reliable, RuleSet::Extended}) {
      const WeaveResult on = weave(box.surface, options_for(rules));
      const WeaveResult off = weave(box.surface, options_for(rules, BlockRecovery::Off));
      EXPECT_EQ(on.complex.hexes, off.complex.hexes);
      EXPECT_EQ(on.stats.recoveries, 0U);
      EXPECT_EQ(on.stats.recovery_trials, 0U);
      EXPECT_TRUE(on.recoveries.empty());
    }
  }
}

TEST(BlockRecovery, TheTraceHoldsOnlyTheKeptTrial) {
  // Watching the weave changes nothing: with a trace, the recovered complex is the same, and
  // the trace has one rule event per rule applied on the kept path (abandoned trials' events
  // are dropped).
  const stc::QuadSurface s = test::issue11_twelve_quads();
  for (RuleSet rules : {RuleSet::Reliable, RuleSet::Extended}) {
    WeaveOptions traced = options_for(rules);
    traced.trace = true;
    const WeaveResult a = weave(s, options_for(rules));
    const WeaveResult b = weave(s, traced);
    EXPECT_EQ(a.complex.hexes, b.complex.hexes) << to_string(rules);
    std::size_t pillow_hexes = 0;
    std::size_t rule_events = 0;
    for (const TraceEvent& e : b.trace) rule_events += e.kind == TraceEvent::Kind::Rule ? 1 : 0;
    for (const Recovery& r : b.recoveries) pillow_hexes += r.pillowed;
    EXPECT_GT(pillow_hexes, 0U);
    std::size_t pillow_events = 0;
    for (const TraceEvent& e : b.trace) pillow_events += e.rule == "pillow" ? 1 : 0;
    EXPECT_EQ(pillow_events, b.recoveries.size()) << "one pillow event per kept recovery";
    EXPECT_GT(rule_events, 0U);
    // The history the weave records itself (WeaveResult::hex_node, ::shrinks) is the same with
    // and without a trace, and says what the kept path's events say: per hex, the node of the
    // last rule event that made it (a pillow batch's on its last hex), none where no event did.
    EXPECT_EQ(a.hex_node, b.hex_node) << to_string(rules);
    ASSERT_EQ(a.shrinks.size(), b.shrinks.size()) << to_string(rules);
    for (std::size_t i = 0; i < a.shrinks.size(); ++i) {
      EXPECT_EQ(a.shrinks[i].shrink, b.shrinks[i].shrink);
      EXPECT_EQ(a.shrinks[i].loop, b.shrinks[i].loop);
      EXPECT_EQ(a.shrinks[i].failed, b.shrinks[i].failed);
    }
    std::vector<NodeId> from_trace(b.complex.hexes.size(), NodeId::invalid());
    for (const TraceEvent& e : b.trace) {
      if (e.kind == TraceEvent::Kind::Rule && e.hex.is_valid())
        from_trace.at(e.hex.index()) = e.node;
    }
    ASSERT_EQ(b.hex_node.size(), b.complex.hexes.size());
    EXPECT_EQ(b.hex_node, from_trace) << to_string(rules);
    std::size_t selections = 0;
    for (const TraceEvent& e : b.trace) selections += e.kind == TraceEvent::Kind::Selection ? 1 : 0;
    EXPECT_GT(b.shrinks.size(), 0U);
    EXPECT_LE(b.shrinks.size(), selections);
  }
}

TEST(BlockRecovery, NoTrialLeftIsAWeaveError) {
  WeaveOptions o = options_for(RuleSet::Reliable);
  o.recovery.max_trials = 0;
  try {
    (void)weave(test::issue11_twelve_quads(), o);
    ADD_FAILURE() << "expected a WeaveError";
  } catch (const WeaveError& e) {
    EXPECT_NE(std::string(e.what()).find("block recovery"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is blocked"), std::string::npos) << e.what();
  }
}

TEST(BlockRecovery, NamesRoundTrip) {
  for (BlockRecovery r : {BlockRecovery::Auto, BlockRecovery::Off})
    EXPECT_EQ(block_recovery_from_name(to_string(r)), r);
  EXPECT_THROW((void)block_recovery_from_name("sometimes"), InvalidInput);
}

}  // namespace
}  // namespace stcweave::weave
