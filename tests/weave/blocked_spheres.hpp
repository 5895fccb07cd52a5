#pragma once
/// \file
/// Loop-clean sphere quadrangulations of the closure of sphere_enum.hpp whose weave blocks with
/// the block recovery and the seam-undo retry: only the last ways of `weave::weave` complete
/// them (docs/weave-recovery.md "The fill"). Written out because enumerating the closure takes
/// time (minutes at 20 quads); the numbers are the loop-clean order of the closure.

#include <array>
#include <cstddef>
#include <vector>

#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::test {

inline stc::QuadSurface surface_of_quads(std::size_t nodes,
                                         const std::vector<std::array<int, 4>>& quads) {
  stc::QuadSurface s;
  s.num_nodes = nodes;
  for (const auto& q : quads)
    s.quads.push_back({NodeId(q[0]), NodeId(q[1]), NodeId(q[2]), NodeId(q[3])});
  return s;
}

/// Loop-clean shape 3 of the 12-quad closure (14 nodes): since the hex-making rules check
/// their contacts (2026-12-07), its weave blocks under both rule sets with the block recovery
/// and the seam-undo retry, and the fill of the input completes it (16 hexes).
inline stc::QuadSurface blocked_sphere_12() {
  return surface_of_quads(14, {{8, 9, 10, 11},
                               {7, 1, 0, 5},
                               {6, 2, 3, 4},
                               {7, 3, 2, 1},
                               {6, 4, 5, 0},
                               {7, 5, 4, 3},
                               {6, 12, 9, 8},
                               {12, 1, 10, 9},
                               {1, 13, 11, 10},
                               {13, 6, 8, 11},
                               {12, 6, 0, 1},
                               {13, 1, 2, 6}});
}

/// Loop-clean shape 7 of the 16-quad closure (18 nodes): blocks like `blocked_sphere_12`; its
/// fill completes it on top of one woven hex (17 hexes).
inline stc::QuadSurface blocked_sphere_16() {
  return surface_of_quads(18, {{8, 9, 10, 11},
                               {7, 1, 0, 5},
                               {6, 2, 3, 4},
                               {7, 3, 2, 1},
                               {6, 4, 5, 0},
                               {7, 5, 4, 3},
                               {6, 12, 9, 8},
                               {12, 1, 10, 9},
                               {1, 13, 11, 10},
                               {13, 6, 8, 11},
                               {14, 15, 16, 17},
                               {13, 1, 2, 6},
                               {12, 6, 15, 14},
                               {6, 0, 16, 15},
                               {0, 1, 17, 16},
                               {1, 12, 14, 17}});
}

/// Loop-clean shape 17 of the 18-quad closure (20 nodes): under `extended` it blocks with the
/// block recovery and the seam-undo retry, its fill stalls, and the reliable weave from the
/// start completes it.
inline stc::QuadSurface blocked_sphere_18() {
  return surface_of_quads(20, {{12, 0, 1, 2},
                               {13, 1, 0, 11},
                               {12, 2, 3, 4},
                               {13, 3, 2, 1},
                               {12, 4, 5, 6},
                               {13, 5, 4, 3},
                               {12, 6, 7, 8},
                               {13, 7, 6, 5},
                               {14, 8, 9, 10},
                               {13, 9, 8, 7},
                               {14, 10, 11, 0},
                               {15, 16, 17, 18},
                               {14, 0, 12, 8},
                               {19, 11, 16, 15},
                               {11, 10, 17, 16},
                               {10, 9, 18, 17},
                               {9, 19, 15, 18},
                               {19, 9, 13, 11}});
}

}  // namespace stcweave::test
