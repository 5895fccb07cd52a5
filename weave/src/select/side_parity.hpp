#pragma once
/// Which side of every loop holds a non-convex edge, for all loops at once, without flooding a
/// side (select/properties.cpp's `CandidateSet` asks it before the non-convex filter).
///
/// Why: the non-convex filter (seed sect. 4.4) keeps the candidates whose side has no
/// non-convex edge. Counting those edges takes a flood of the side, and the filter comes
/// first, so on a surface with non-convex edges every loop's floods were paid at every
/// selection (`cfip2016_KPDloekr-hex`: 1,122 loops and 13,428 faces, 83 s of weave for 3 s
/// under `reliable`). The filter reads only whether the count is 0; its relaxation to the
/// fewest (`nonconvex_least`), when no side has 0, reads the counts and floods those sides.
///
/// How: on a front component that is a sphere (nodes - faces = 2), a loop that does not
/// cross itself is a simple closed curve (Jordan), and a node's side is the parity of the
/// number of times a path from a fixed node crosses the loop, i.e. of the path's edges that
/// the loop crosses (every front edge is crossed by exactly one loop: the one through it).
/// One depth-first tree per component gives every node, in one pass, the parities for every
/// loop as a bit vector (a tree edge flips one bit). A non-convex edge that the loop does not
/// cross has both ends on one side, and it is on that side's faces or along the strip on that
/// side, which is what the flood counts; an edge the loop crosses (two strip faces) is
/// counted by neither side. So a side has a non-convex edge iff some non-convex edge of the
/// component, not crossed by the loop, has its ends on that side. Only the ends of
/// non-convex edges and one corner per loop get their bit vectors stored.
///
/// `CandidateSet` checks the answer against the floods when `WeaveOptions::check` is on.

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "face_table.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

/// Per loop, whether each side holds a non-convex edge (angle above `flat`), as the floods of
/// `extended_properties` would count them (0 or not).
struct SideNonconvex {
  /// Per loop: 1 when the answer below is exact (the loop does not cross itself and its
  /// component is a sphere), 0 when the caller must flood.
  std::vector<char> known;
  /// Per loop, per side (A, B): the side holds a non-convex edge.
  std::vector<std::array<char, 2>> has;
};

/// The answer for every loop of `loops` (`table` with angles; `component_faces`: the alive
/// faces per component, `ComponentTotals::faces`). Loops crossing themselves
/// (`self_intersecting[l]` non-zero) and loops on a component that is not a sphere are left
/// unknown.
[[nodiscard]] SideNonconvex side_nonconvex(const Front& front, const FaceTable& table,
                                           const FrontLoops& loops,
                                           const FrontComponents& components,
                                           std::span<const std::size_t> component_faces,
                                           const std::vector<char>& self_intersecting, double flat);

}  // namespace stcweave::weave
