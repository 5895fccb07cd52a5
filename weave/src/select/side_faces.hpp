#pragma once
/// The faces on each side of every loop, for all loops at once, without flooding a side
/// (select/properties.cpp's `CandidateSet::bound_faces` reads it before any flood).
///
/// Why: the extended ranking ends by the fewest faces collapsed (seed Fig. 15), so every
/// candidate left after the filters needs a face count or a bound on it. `bound_faces` used to
/// flood each side up to the least count found so far; on a structured box every loop is still
/// in play there, so each selection flooded (loops x that least count) faces, the largest part
/// of a box's selection (12 % of the whole run on the 205,379-hex cube, docs/benchmarks.md).
///
/// How: on a front component that is a sphere (nodes - faces = 2) a loop that does not cross
/// itself is a simple closed curve, and a node's side is the parity of the number of the
/// loop's crossings on a path from a fixed node (select/side_parity.hpp uses the same fact).
/// Take one depth-first tree per component and give each face to its first node. The tree
/// edges a loop crosses lead into subtrees; a node lies on the side away from the root iff an
/// odd number of those edges are on its path from the root, so the faces given to nodes on
/// that side are the alternating sum of the subtree totals below those edges, each signed by
/// how many of the loop's tree edges lie above it (+ when even). A face off the strip has its
/// four nodes on one side (its edges are not crossed by the loop); a strip face is given to a
/// node of one side or the other, known from where that node sits in the step. So each side's
/// faces off the strip are its nodes' faces less the strip faces given to them: exactly the
/// faces the side's flood reaches (`faces_collapsed_at_least` with no limit), in (nodes +
/// faces + strip steps) for all loops together.
///
/// `CandidateSet` checks the counts against the floods when `WeaveOptions::check` is on, and
/// tests/weave/side_faces_test.cpp at every selection of several weaves.

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "face_table.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

/// Per loop, the faces collapsed of each side (the side's faces plus the strip's), as the
/// floods of `extended_properties` count them.
struct SideFaces {
  /// Per loop: 1 when the counts below are exact (the loop does not cross itself and its
  /// component is a sphere), 0 when the caller must flood.
  std::vector<char> known;
  /// Per loop, per side (A, B): faces on that side plus the strip's faces.
  std::vector<std::array<std::size_t, 2>> faces_collapsed;
};

/// The counts for every loop of `loops` (`table`: the incidence lists and face nodes are read;
/// `component_faces`: the alive faces per component, `ComponentTotals::faces`). Loops crossing
/// themselves (`self_intersecting[l]` non-zero) and loops on a component that is not a sphere
/// are left unknown, and so is every loop when a front edge is crossed by no loop.
[[nodiscard]] SideFaces side_faces(const Front& front, const FaceTable& table,
                                   const FrontLoops& loops, const FrontComponents& components,
                                   std::span<const std::size_t> component_faces,
                                   const std::vector<char>& self_intersecting);

}  // namespace stcweave::weave
