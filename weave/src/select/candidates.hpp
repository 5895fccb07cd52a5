#pragma once
/// The candidates of a geometric selection, with their side properties computed on demand
/// (select/properties.cpp), and the ranking that asks only for those its filters read
/// (select/filters.cpp).
///
/// Why: the extended properties of a candidate that a flood of its side gives (faces
/// collapsed, depth, non-convex edges on the side, the weight) cost that side's size; over
/// every loop of a front that is about (loops x faces) per selection, the most expensive part
/// of a weave of a structured box (docs/weave-loop-properties.md). Most candidates are
/// decided by their strip alone: the first convex filter reads the sharp edges the strip
/// crosses, the second convex filter its sharp side edges, and only the few candidates left
/// after them need a depth and a face count. So the strip properties of every candidate are
/// computed, and a loop's floods only when a filter that reads them sees one of its sides.
/// A completed loop's candidates are exactly those `loop_candidates` computes (it completes
/// every loop of the same set), so the first candidate of `rank_first` is the first of
/// `rank` over every candidate. The other candidates of `rank_first`'s order are in
/// enumeration order and may be incomplete: the driver uses it only where nothing reads them
/// (no observer) and ranks every candidate again, on the same front, when the first fails to
/// shrink (as with the reliable branch and bound, select/bounded.hpp).

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "face_table.hpp"
#include "one_flood.hpp"
#include "side_faces.hpp"
#include "stcweave/weave/select.hpp"

namespace stcweave::weave {

class CandidateSet {
 public:
  /// Two candidates per loop of `loops` (side A at 2l, side B at 2l + 1) with their strip
  /// properties: loop, side, length, self_intersecting, crossed_sharp, side_sharp and
  /// parallel_to, and nonconvex_on_side where the loop's front component has no non-convex
  /// face side at all (it is 0 then) or the side parities decide it (0, or 1 for "at least
  /// one", until the loop is completed). With `check`, `complete` throws `InternalError` when a
  /// strip property differs from the one the floods give.
  CandidateSet(const Front& front, const FrontLoops& loops, const FrontComponents& components,
               const ExtendedParameters& parameters, Marks& nodes, Marks& faces, Marks& faces2,
               bool check = false);
  /// The same with the front's `face_table(front, true)` built by the caller (who read its
  /// loops and components from it too: `front_loops(front, table)`).
  CandidateSet(const Front& front, const FrontLoops& loops, const FrontComponents& components,
               const ExtendedParameters& parameters, Marks& nodes, Marks& faces, Marks& faces2,
               bool check, FaceTable table);

  [[nodiscard]] std::vector<TraceCandidate>& all() { return all_; }
  /// The `side_property` bits known for both candidates of `loop`.
  [[nodiscard]] unsigned known(std::int32_t loop) const {
    return known_[static_cast<std::size_t>(loop)];
  }
  /// Computes every property of both candidates of `loop` (no-op when they are complete).
  void complete(std::int32_t loop);
  /// Every loop completed: `loop_candidates`.
  void complete_all();
  /// For an order by fewest faces collapsed (`Selection::order_fewest_faces_first`): makes
  /// the candidates of `set` (indices into `all()`) complete where they may be first, and
  /// gives every other one a `faces_collapsed` that is a lower bound of its own and above the
  /// least of the set, so that ordering `set` puts first the candidate `complete_all` would.
  /// The sides are bounded up to a limit that starts at the least faces collapsed of the
  /// previous such call (a hint: it changes the work only) and doubles until some candidate
  /// of the set is within it; a side's bound is read from the exact counts of every loop
  /// (`side_faces`, computed once for the set) where they are known, and flooded up to the
  /// limit (`faces_collapsed_at_least`) where not.
  void bound_faces(const std::vector<std::size_t>& set);

 private:
  const Front& front_;
  const FrontLoops& loops_;
  const FrontComponents& components_;
  const ExtendedParameters& parameters_;
  Marks& nodes_;
  Marks& faces_;
  Marks& faces2_;
  bool check_ = false;
  FaceTable table_;
  ComponentTotals totals_;
  std::vector<TraceCandidate> all_;
  std::vector<unsigned> known_;
  /// Per loop: `nonconvex_on_side` is known from the side parities (select/side_parity.hpp),
  /// as 0 or 1 ("at least one"), until the loop is completed.
  std::vector<char> by_parity_;
  /// Faces collapsed of both sides of every loop, where known (`side_faces`): computed by the
  /// first `bound_faces` of the selection.
  std::optional<SideFaces> side_faces_;

  /// What `faces_collapsed_at_least` gives for the `sides` of `loop` up to `limit`, from
  /// `side_faces_` where known (checked against the flood with `check_`).
  [[nodiscard]] std::array<std::size_t, 2> faces_collapsed_bound(std::int32_t loop, unsigned sides,
                                                                 std::size_t limit);
};

/// `rank(selection, ...)`'s first candidate, its reason and its filters, computing side
/// properties only where a filter reads them (`Filter::reads`); the candidates the filters
/// keep are completed before they are ordered. `order` holds every candidate: the first,
/// then the others in enumeration order, possibly incomplete.
[[nodiscard]] Ranking rank_first(const Selection& selection, CandidateSet& candidates);

}  // namespace stcweave::weave
