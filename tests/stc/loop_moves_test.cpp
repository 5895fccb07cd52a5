#include "stcweave/stc/loop_moves.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include "stcweave/stc/loops.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/shapes.hpp"

namespace stcweave::stc {
namespace {

LoopMoveResult filled(const QuadSurface& s, LoopMoveOptions o = {}) {
  return fill_front(untangle_loops(s, o), o);
}

TEST(LoopMoves, BoxesAreFilledByMovesAlone) {
  for (const auto& [a, b, c] :
       std::vector<std::array<int, 3>>{{1, 1, 1}, {2, 1, 1}, {3, 1, 1}, {2, 2, 1}, {2, 2, 2}}) {
    const QuadSurface s = test::box_surface(a, b, c).surface;
    const LoopMoveResult r = filled(s);
    std::cout << a << b << c << ": " << r.stop_reason << " hexes " << r.hexes.hexes.size()
              << " front " << r.front.quads.size() << "\n";
    EXPECT_TRUE(r.simple) << r.stop_reason;
    if (r.simple) {
      const ValidationReport v = validate_hex_complex(r.hexes, &s);
      EXPECT_TRUE(v.valid) << v.summary();
    }
  }
}

}  // namespace
}  // namespace stcweave::stc
