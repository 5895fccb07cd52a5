/// The thresholded second convex filter (see second_convex_threshold.hpp).

#include "stcweave/weave/second_convex_threshold.hpp"

#include <algorithm>

namespace stcweave::weave {

Filter second_convex_threshold_filter(double min_weight) {
  Filter f = second_convex_filter();
  f.cost = [min_weight](const TraceCandidate& c) {
    const double w =
        static_cast<double>(c.side_sharp) / static_cast<double>(std::max<std::size_t>(1, c.length));
    return w + 1e-12 >= min_weight ? -w : 0.0;
  };
  return f;
}

}  // namespace stcweave::weave
