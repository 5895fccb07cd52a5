#pragma once
/// The reliable selection's candidates computed with branch and bound (select/properties.cpp).
///
/// `reliable` keeps the candidate of least weight, the earliest in the enumeration among
/// equals (loops that cross themselves only when every loop does). A candidate's weight is at
/// least the nodes its side's flood has reached (plus the strip's nodes), so once both sides
/// of a loop have reached more than the best weight found so far, neither can be chosen and
/// its flood stops. The first candidate of `rank(reliable_selection(), ...)` is then the same
/// as with every weight computed; the rest of the order is not: a pruned candidate carries
/// the weight `kNoLimit` and no side count. The driver uses this only when nothing reads the
/// other candidates (no trace, no observer, the built-in reliable selection) and computes
/// every weight again, on the same front, when the first candidate fails to shrink.

#include <array>
#include <cstddef>
#include <limits>
#include <vector>

#include "face_table.hpp"
#include "stcweave/weave/select.hpp"

namespace stcweave::weave {

/// No bound: the weight of a candidate that was not computed, and the limit that prunes nothing.
inline constexpr std::size_t kNoLimit = std::numeric_limits<std::size_t>::max();

/// `weigh`, stopping when both sides' floods have reached more nodes than `limit[side]` minus
/// the strip's nodes; `*pruned` then says so and the counts are partial. A loop that crosses
/// itself is always weighed in full. With `pruned` null, exactly `weigh`.
/// The front's neighbours and incidence are read from `table` (`face_table(front)`).
std::array<TraceCandidate, 2> weigh_within(const Front& front, const FaceTable& table,
                                           const Strip& strip, const FrontComponents& components,
                                           Marks& nodes, Marks& faces,
                                           std::array<std::size_t, 2> limit, bool* pruned);

/// The candidates of `loop_candidates` under `reliable` (same enumeration, loop l's sides at
/// 2l and 2l + 1), pruned by branch and bound: the candidate `rank` puts first is exact and
/// is the one it would put first with every weight; pruned candidates weigh `kNoLimit`.
/// Floods are first capped at `hint` (the previous selection's best weight; 0: four times the
/// shortest strip), the cap doubled until a best weight within it is found; `hint` receives
/// this selection's best weight. The hint changes the work done, never the result.
std::vector<TraceCandidate> loop_candidates_bounded(const Front& front, const FrontLoops& loops,
                                                    const FrontComponents& components, Marks& nodes,
                                                    Marks& faces, std::size_t& hint);

}  // namespace stcweave::weave
