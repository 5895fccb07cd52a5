/// The thresholded second convex filter (see second_convex_threshold.hpp).

#include "stcweave/weave/second_convex_threshold.hpp"

namespace stcweave::weave {

Filter second_convex_threshold_filter(double min_weight) {
  Filter f = second_convex_filter();
  f.cost = [min_weight](const TraceCandidate& c) {
    return -side_elimination_weight(c, nullptr, min_weight, false);
  };
  return f;
}

}  // namespace stcweave::weave
