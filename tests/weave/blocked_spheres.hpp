#pragma once
/// \file
/// Loop-clean 20-quad sphere quadrangulations (22 nodes) of the closure of sphere_enum.hpp
/// whose weave blocks under one rule set with the block recovery and the seam-undo retry: only
/// the last ways of `weave::weave` complete them (docs/weave-recovery.md "The fill"). Written
/// out because enumerating the 20-quad closure takes minutes; the numbers are the loop-clean
/// order of `SphereClosureSlow.TwentyQuads`.

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

inline stc::QuadSurface blocked_sphere_170() {  // blocks under reliable
  return surface_of_quads(
      22, {{8, 0, 1, 2},    {12, 13, 14, 15}, {8, 2, 3, 4},     {9, 3, 2, 1},     {10, 4, 5, 6},
           {9, 5, 4, 3},    {10, 6, 7, 11},   {9, 7, 6, 5},     {17, 18, 19, 20}, {11, 1, 0, 10},
           {9, 1, 13, 12},  {1, 11, 14, 13},  {11, 16, 15, 14}, {16, 9, 12, 15},  {16, 11, 7, 9},
           {10, 0, 18, 17}, {0, 21, 19, 18},  {21, 4, 20, 19},  {4, 10, 17, 20},  {21, 0, 8, 4}});
}
inline stc::QuadSurface blocked_sphere_377() {  // blocks under extended
  return surface_of_quads(
      22, {{10, 0, 1, 2},   {11, 1, 0, 9},   {14, 2, 3, 4},    {11, 3, 2, 1},    {14, 4, 5, 6},
           {11, 5, 4, 3},   {12, 6, 7, 8},   {11, 7, 6, 5},    {12, 8, 9, 13},   {11, 9, 8, 7},
           {12, 20, 14, 6}, {13, 9, 0, 19},  {15, 16, 17, 18}, {14, 20, 16, 15}, {13, 19, 21, 16},
           {10, 2, 18, 17}, {2, 14, 15, 18}, {19, 0, 10, 21},  {20, 12, 13, 16}, {21, 10, 17, 16}});
}
inline stc::QuadSurface
blocked_sphere_158() {  // extended runs away (the rule budget), the fill stalls
  return surface_of_quads(
      22, {{12, 13, 14, 15}, {11, 1, 0, 9},   {10, 2, 3, 4},    {11, 3, 2, 1},    {10, 4, 5, 6},
           {11, 5, 4, 3},    {10, 6, 7, 8},   {17, 18, 19, 20}, {10, 8, 9, 0},    {11, 9, 8, 7},
           {10, 16, 13, 12}, {16, 1, 14, 13}, {1, 2, 15, 14},   {2, 10, 12, 15},  {16, 10, 0, 1},
           {11, 7, 18, 17},  {7, 6, 19, 18},  {6, 21, 20, 19},  {21, 11, 17, 20}, {21, 6, 5, 11}});
}

}  // namespace stcweave::test
