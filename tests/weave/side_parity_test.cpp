// The side parities (weave/src/select/side_parity.hpp) against the floods they stand in for:
// for every loop they decide, a side holds a non-convex edge exactly when the flood of
// `extended_properties` counts one there.
#include "select/side_parity.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "driver.hpp"
#include "select/face_table.hpp"
#include "select/one_flood.hpp"
#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/weave/select.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

struct Counts {
  std::size_t decided = 0;        ///< loops the parities decide
  std::size_t with = 0;           ///< sides holding a non-convex edge
  std::size_t without = 0;        ///< sides holding none
  std::size_t self_crossing = 0;  ///< loops crossing themselves (left to the floods)
};

/// Compares the parities with the floods on `state`'s front, loop by loop.
Counts compare_on(const WeaveState& state, const std::string& where) {
  Counts n;
  const ExtendedParameters par;
  Marks nodes, faces, faces2;
  const FrontLoops loops = front_loops(state.front);
  const FrontComponents components = front_components(state.front, nodes);
  const FaceTable table = face_table(state.front);
  std::vector<char> self(loops.strips.size(), 0);
  for (std::size_t l = 0; l < loops.strips.size(); ++l) {
    const std::array<TraceCandidate, 2> c =
        extended_properties(state.front, loops.strips[l], components, par, nodes, faces, faces2);
    self[l] = c[0].self_intersecting ? 1 : 0;
  }
  const ComponentTotals totals = component_totals(state.front, table, components, par.flat);
  const SideNonconvex parity =
      side_nonconvex(state.front, table, loops, components, totals.faces, self, par.flat);
  for (std::size_t l = 0; l < loops.strips.size(); ++l) {
    if (self[l] != 0) {
      EXPECT_EQ(parity.known[l], 0) << where << ": loop " << l << " crosses itself";
      ++n.self_crossing;
      continue;
    }
    EXPECT_EQ(parity.known[l], 1) << where << ": loop " << l << " on a sphere left undecided";
    if (parity.known[l] == 0) continue;
    ++n.decided;
    const std::array<TraceCandidate, 2> c =
        extended_properties(state.front, loops.strips[l], components, par, nodes, faces, faces2);
    for (std::size_t d = 0; d < 2; ++d) {
      EXPECT_EQ(parity.has[l][d] != 0, c[d].nonconvex_on_side > 0)
          << where << ": loop " << l << " side "
          << "AB"[d] << " counts " << c[d].nonconvex_on_side;
      (c[d].nonconvex_on_side > 0 ? n.with : n.without) += 1;
    }
  }
  return n;
}

WeaveState state_of(const primal::SurfaceMesh& mesh) {
  WeaveOptions options;
  options.rules = RuleSet::Extended;
  return initial_state(mesh.surface, options, primal::dihedral_angles(mesh));
}

TEST(SideParity, AgreesWithTheFloodsOnVoxelSurfaces) {
  // Non-convex edges on one side, on both sides, and along strips: an L-block, a U-block, a
  // plus sign of voxels two layers high.
  const std::vector<std::pair<std::string, std::vector<std::array<int, 3>>>> shapes = {
      {"l-block", test::lblock_cells()},
      {"u-block", {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {2, 1, 0}, {0, 2, 0}, {2, 2, 0}}},
      {"plus",
       {{1, 0, 0},
        {0, 1, 0},
        {1, 1, 0},
        {2, 1, 0},
        {1, 2, 0},
        {1, 0, 1},
        {0, 1, 1},
        {1, 1, 1},
        {2, 1, 1},
        {1, 2, 1}}}};
  Counts all;
  for (const auto& [name, cells] : shapes) {
    const Counts n = compare_on(state_of(test::voxel_surface(cells)), name);
    all.decided += n.decided;
    all.with += n.with;
    all.without += n.without;
  }
  // Both answers occur, so the comparison could fail either way.
  EXPECT_GT(all.decided, 10U);
  EXPECT_GT(all.with, 0U);
  EXPECT_GT(all.without, 0U);
}

TEST(SideParity, ConvexFrontsHaveNoSideWithANonConvexEdge) {
  const Counts n = compare_on(state_of(test::box_surface(3, 4, 5)), "box");
  EXPECT_EQ(n.decided, 3U + 4U + 5U);
  EXPECT_EQ(n.with, 0U);
}

}  // namespace
}  // namespace stcweave::weave
