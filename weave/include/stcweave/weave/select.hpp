#pragma once
/// \file
/// Loop selection as data (seed sect. 4 and 7, Fig. 15).
///
/// Every (loop, side) of the front is a candidate with its properties (`TraceCandidate`).
/// A `Selection` ranks them: a stable order first, loops that cross themselves last, then its
/// filters in turn, each keeping the candidates that pass. A filter is a value: a name, a
/// predicate (or a cost to minimise), whether it may be relaxed when it would leave none,
/// and, for a deciding filter, the reason it gives. `reliable_selection()` and
/// `extended_selection()` are the two lists of the CLI; a library user builds a third and
/// passes it as `WeaveOptions::selection`. Variants without a stability promise live in
/// `weave::experimental`.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "stcweave/weave/kernel.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

/// The candidate properties that cost a flood of the candidate's side of the front (all the
/// others are read off its strip): what a filter may declare it reads (`Filter::reads`), so
/// that the driver computes them only for the candidates such a filter sees
/// (select/candidates.hpp).
namespace side_property {
inline constexpr unsigned kFaces = 1U;      ///< faces_collapsed
inline constexpr unsigned kDepth = 2U;      ///< depth
inline constexpr unsigned kNonconvex = 4U;  ///< nonconvex_on_side
inline constexpr unsigned kWeight = 8U;     ///< strictly_on_side, on_strip, weight
/// nonconvex_on_side as a count; `kNonconvex` alone may leave it as 1 for "at least one"
inline constexpr unsigned kNonconvexCount = 16U;
inline constexpr unsigned kAll = kFaces | kDepth | kNonconvex | kWeight | kNonconvexCount;
}  // namespace side_property

/// One filter of Fig. 15.
struct Filter {
  enum class Kind {
    /// Keeps the candidates for which `keep` holds.
    Keep,
    /// Keeps the candidates whose `cost` is at most the least cost plus `slack`.
    Least,
    /// When some candidate passes `keep`, those are the choice and the later filters are
    /// skipped (the parallel rules, which "directly define the loop to shrink").
    Decide,
  };
  std::string name;
  Kind kind = Kind::Keep;
  std::function<bool(const TraceCandidate&)> keep;    ///< Keep, Decide
  std::function<double(const TraceCandidate&)> cost;  ///< Least
  /// Least: used instead of `cost` when set; also reads the candidate for the other side of
  /// the same loop (nullptr when that one is not among the candidates ranked).
  std::function<double(const TraceCandidate&, const TraceCandidate*)> cost_with_other;
  double slack = 1e-12;  ///< Least, and a Keep filter's `relax_cost`
  /// When it would leave no candidate it is skipped for this selection (traced "relaxed").
  bool may_relax = false;
  /// Keep: when `keep` would leave no candidate and this is set, the candidates of least
  /// `relax_cost` (within `slack`) are kept instead (traced "name:N->least:M"), and
  /// `may_relax` is then never used; `relax_reads` gives the `side_property` bits it reads
  /// (unset: all of them). Ignored on Least and Decide filters.
  std::function<double(const TraceCandidate&)> relax_cost;
  std::function<unsigned(const TraceCandidate&)> relax_reads;
  /// Decide: the reason traced, given the candidates it kept.
  std::function<std::string(const std::vector<TraceCandidate>&)> reason;
  /// The `side_property` bits its verdict on a candidate may read, of the candidate or of the
  /// other side of its loop (`cost_with_other`). Unset: all of them. A filter that reads a
  /// property it does not declare may see it unset (zero) in a weave without an observer.
  std::function<unsigned(const TraceCandidate&)> reads;
};

/// A rule set's loop selection: an order, then filters.
struct Selection {
  std::string name;
  /// The candidates need the extended properties (faces collapsed, depth, sharp and
  /// non-convex edges, parallel loops), computed from the carried angles.
  bool geometric = false;
  /// The order before filtering (stable; ties keep the enumeration order).
  std::function<bool(const TraceCandidate&, const TraceCandidate&)> order;
  std::vector<Filter> filters;
  /// What decides among the candidates left ("weight", "topological").
  std::string last = "weight";
  /// The reason given when `last` decides.
  std::string last_reason;
  /// Trace the filters (`name:before->after`) and `last:N`, and name them in the reason.
  bool list_filters = false;
  /// `order` compares `faces_collapsed` first, fewer first (as `extended_selection`'s does).
  /// A weave whose observers read only the chosen candidate (`stcweave mesh` without
  /// `--trace`) then floods the sides of the candidates the filters leave only until they
  /// hold more faces than the best one found (select/candidates.hpp); clear
  /// it when you give `order` another first key, or the first candidate may be wrong.
  bool order_fewest_faces_first = false;
};

/// Reliable Whisker Weaving: the smallest topological weight (nodes strictly on that side
/// plus nodes on the strip). \cite seed sect. 2.2.
[[nodiscard]] Selection reliable_selection();

/// The seed's Fig. 15 with the switches of `parameters`: parallel crossing (decides), then
/// the non-convex (the fewest when none is free of them, `nonconvex_least`; else may relax),
/// first convex (with the rim condition, `first_convex_rim`; may relax), second convex
/// (threshold `second_convex_min_weight`, the smaller side) and depth filters
/// (depth before the convex filters, the seed's order, when `depth_after_convex` is false);
/// among those left, the fewest faces collapsed, then the smaller weight.
/// \cite seed sect. 4.1-4.5, 7.
[[nodiscard]] Selection extended_selection(const ExtendedParameters& parameters);

/// The selection `options` asks for: `options.selection` when set, else the rule set's.
[[nodiscard]] Selection selection_for(const WeaveOptions& options);

// The filters of Fig. 15 as the seed gives them, each a named value; `extended_selection`
// lists the variants below them, with our conditions as `ExtendedParameters` sets them.
[[nodiscard]] Filter parallel_crossing_filter();  ///< sect. 4.5: runs along another loop
[[nodiscard]] Filter nonconvex_filter();          ///< sect. 4.4: no non-convex edge that side
[[nodiscard]] Filter depth_filter();              ///< sect. 4.1: least depth
[[nodiscard]] Filter first_convex_filter();       ///< sect. 4.2: crosses a sharp edge
[[nodiscard]] Filter second_convex_filter();      ///< sect. 4.3: highest side elimination weight

/// The non-convex filter with our relaxation when `least` is true: when every side has a
/// non-convex edge, the sides with the fewest are kept (`Filter::relax_cost`), instead of
/// all of them (ExtendedParameters::nonconvex_least). With `least` false it is
/// `nonconvex_filter()`.
[[nodiscard]] Filter nonconvex_filter(bool least);

/// The first convex filter with our condition when `rim` is true: a side whose every side
/// edge is sharp convex (`side_sharp >= length`) is kept as well (ExtendedParameters::
/// first_convex_rim). With `rim` false it is `first_convex_filter()`, the seed's rule.
[[nodiscard]] Filter first_convex_filter(bool rim);

/// The side elimination weight of `c` (sharp convex side edges / loop length, seed sect.
/// 4.3), 0 when it is below `min_weight`, or, with `smaller_side`, when `c`'s side collapses
/// more faces than `other`, the other side of the same loop (nullptr: not known, no test).
[[nodiscard]] double side_elimination_weight(const TraceCandidate& c, const TraceCandidate* other,
                                             double min_weight, bool smaller_side);

/// The second convex filter with our two conditions (`side_elimination_weight`): a weight
/// below `min_weight` counts as 0; with `smaller_side`, so does the weight of the larger side
/// of a loop. Traced as "second_convex". With (0, false) it ranks as `second_convex_filter`.
[[nodiscard]] Filter second_convex_filter(double min_weight, bool smaller_side);

/// The outcome of ranking the candidates of one selection.
struct Ranking {
  /// Every candidate, in the order to try them: those the filters kept first.
  std::vector<TraceCandidate> order;
  /// The filters applied, as traced ("depth:4->2", "nonconvex:3->relaxed", ...).
  std::vector<std::string> filters;
  std::string reason;      ///< why the first is chosen
  std::string decided_by;  ///< the filter after which one candidate was left, or `last`
};
/// Ranks `candidates` by `selection`. Pure: depends only on its arguments.
/// The filters run on the candidates in enumeration order and the candidates they keep are
/// then put in `selection.order` (stable); every filter's verdict depends on the set it is
/// given, not on its order, so this is the order-then-filter of the seed's Fig. 15.
[[nodiscard]] Ranking rank(const Selection& selection, std::vector<TraceCandidate> candidates);

/// The candidates of one selection: two per loop of `loops`, side A then side B, with the
/// reliable weights and, for a geometric selection, the extended properties (and
/// `parallel_to` when `parameters.parallel_crossing`).
[[nodiscard]] std::vector<TraceCandidate> loop_candidates(
    const Front& front, const FrontLoops& loops, const FrontComponents& components, bool geometric,
    const ExtendedParameters& parameters, Marks& nodes, Marks& faces, Marks& faces2);

/// The reliable weights of shrinking `strip` to side A and to side B (`faces` receives the
/// strip faces under a fresh stamp). \cite seed sect. 2.2.
[[nodiscard]] std::array<TraceCandidate, 2> weigh(const Front& front, const Strip& strip,
                                                  const FrontComponents& components, Marks& nodes,
                                                  Marks& faces);

/// `weigh` plus the properties of the extended filters for both sides.
[[nodiscard]] std::array<TraceCandidate, 2> extended_properties(
    const Front& front, const Strip& strip, const FrontComponents& components,
    const ExtendedParameters& parameters, Marks& nodes, Marks& faces, Marks& faces2);

/// The loop that `strip` runs along on side `side` across sharp convex edges only, of the
/// same length (parallel crossing, seed sect. 4.5), or -1.
[[nodiscard]] std::int32_t parallel_loop(const Front& front, const Strip& strip, stc::LoopSide side,
                                         const FrontLoops& loops,
                                         const ExtendedParameters& parameters);

namespace experimental {
/// A variant of the depth rule: keeps the candidates whose depth is at most one above the
/// least (a softer "closer to the boundary first"). No stability promise.
[[nodiscard]] Filter depth_within_one_filter();
/// `extended_selection` with the depth filter replaced by `depth_within_one_filter`.
[[nodiscard]] Selection extended_soft_depth_selection(const ExtendedParameters& parameters);
}  // namespace experimental

}  // namespace stcweave::weave
