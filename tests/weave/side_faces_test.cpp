// The side face counts of every loop at once (weave/src/select/side_faces.hpp) against the
// floods they stand in for: for every loop they count, each side's faces collapsed is exactly
// the one `extended_properties` floods; loops crossing themselves and loops on a front with a
// handle are left to the floods.
#include "select/side_faces.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <iostream>
#include <string>
#include <vector>

#include "driver.hpp"
#include "select/bounded.hpp"
#include "select/face_table.hpp"
#include "select/one_flood.hpp"
#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/weave/rules.hpp"
#include "stcweave/weave/select.hpp"
#include "support/quadrangulations.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

struct Counts {
  std::size_t counted = 0;        ///< loops side_faces counts
  std::size_t left = 0;           ///< loops it leaves to the floods
  std::size_t self_crossing = 0;  ///< loops crossing themselves
  std::size_t unequal = 0;        ///< counted loops whose two sides differ
};

/// Compares `side_faces` with the floods on `front`, loop by loop. `sphere`: every component
/// of the front is a sphere, so every loop that does not cross itself must be counted.
Counts compare_on(const Front& front, bool sphere, const std::string& where) {
  Counts n;
  const ExtendedParameters par;
  Marks nodes, faces, faces2;
  const FrontLoops loops = front_loops(front);
  const FrontComponents components = front_components(front, nodes);
  const FaceTable table = face_table(front);
  std::vector<std::array<TraceCandidate, 2>> flooded;
  std::vector<char> self(loops.strips.size(), 0);
  for (std::size_t l = 0; l < loops.strips.size(); ++l) {
    flooded.push_back(
        extended_properties(front, loops.strips[l], components, par, nodes, faces, faces2));
    self[l] = flooded.back()[0].self_intersecting ? 1 : 0;
  }
  const ComponentTotals totals = component_totals(front, table, components, par.flat);
  const SideFaces counts = side_faces(front, table, loops, components, totals.faces, self);
  for (std::size_t l = 0; l < loops.strips.size(); ++l) {
    if (self[l] != 0) {
      EXPECT_EQ(counts.known[l], 0) << where << ": loop " << l << " crosses itself";
      ++n.self_crossing;
      continue;
    }
    if (sphere) EXPECT_EQ(counts.known[l], 1) << where << ": loop " << l << " left uncounted";
    if (counts.known[l] == 0) {
      ++n.left;
      continue;
    }
    ++n.counted;
    for (std::size_t d = 0; d < 2; ++d) {
      EXPECT_EQ(counts.faces_collapsed[l][d], flooded[l][d].faces_collapsed)
          << where << ": loop " << l << " side "
          << "AB"[d];
      // And the bounded flood `bound_faces` used before, with no limit.
      EXPECT_EQ(counts.faces_collapsed[l][d],
                faces_collapsed_at_least(front, table, loops.strips[l], 1U << d, kNoLimit, nodes,
                                         faces, faces2)[d])
          << where << ": loop " << l << " side "
          << "AB"[d] << " (bounded flood)";
    }
    if (counts.faces_collapsed[l][0] != counts.faces_collapsed[l][1]) ++n.unequal;
  }
  return n;
}

WeaveState state_of(const primal::SurfaceMesh& mesh) {
  WeaveOptions options;
  options.rules = RuleSet::Extended;
  return initial_state(mesh.surface, options, primal::dihedral_angles(mesh));
}

TEST(SideFaces, EqualTheFloodsOnInputFronts) {
  const std::vector<std::pair<std::string, primal::SurfaceMesh>> shapes = {
      {"box 6x5x4", test::box_surface(6, 5, 4)},
      {"l-block", test::voxel_surface(test::lblock_cells())},
      {"rhombic dodecahedron", test::rhombic_dodecahedron()},
      {"ogrid cylinder",
       test::boundary_of(test::extruded_hexes(test::ogrid_disk(), {0.0, 0.5, 1.0}))},
      {"triangle-split box", test::triangle_split_of(test::box_surface(2, 3, 2))},
      {"two boxes",
       test::merged_surfaces({test::box_surface(2, 2, 2),
                              test::translated(test::box_surface(3, 1, 2), {5.0, 0.0, 0.0})})}};
  Counts all;
  for (const auto& [name, mesh] : shapes) {
    const Counts n = compare_on(state_of(mesh).front, true, name);
    all.counted += n.counted;
    all.unequal += n.unequal;
  }
  std::cout << all.counted << " loops counted, " << all.unequal << " with unequal sides\n";
  EXPECT_GT(all.counted, 40U);
  EXPECT_GT(all.unequal, 10U) << "the two sides always agree: the test shows little";
}

TEST(SideFaces, EqualTheFloodsOnRandomSphereQuadrangulations) {
  // Irregular fronts, most with loops crossing themselves (left to the floods).
  Counts all;
  std::size_t surfaces = 0;
  for (std::uint32_t seed = 1; seed <= 300; ++seed) {
    const auto mesh = test::random_quadrangulation(seed, 10 + static_cast<int>(seed % 12), 30);
    if (!mesh) continue;
    ++surfaces;
    const Counts n = compare_on(state_of(*mesh).front, true, "seed " + std::to_string(seed));
    all.counted += n.counted;
    all.self_crossing += n.self_crossing;
    all.unequal += n.unequal;
  }
  std::cout << surfaces << " surfaces, " << all.counted << " loops counted, " << all.self_crossing
            << " crossing themselves, " << all.unequal << " with unequal sides\n";
  EXPECT_GT(surfaces, 30U);
  EXPECT_GT(all.counted, 30U);
  EXPECT_GT(all.self_crossing, 10U);
  EXPECT_GT(all.unequal, 10U);
}

TEST(SideFaces, EqualTheFloodsAtEverySelectionOfAWeave) {
  // The fronts a weave goes through: the first candidate of the extended ranking shrunk, seams
  // closed, again, until the front is empty (components split off along the way).
  const ExtendedParameters par;
  const Selection selection = extended_selection(par);
  std::size_t fronts = 0;
  Counts all;
  for (const auto& [name, mesh] : std::vector<std::pair<std::string, primal::SurfaceMesh>>{
           {"box 4x3x5", test::box_surface(4, 3, 5)},
           {"l-block", test::voxel_surface(test::lblock_cells())},
           {"ogrid cylinder",
            test::boundary_of(test::extruded_hexes(test::ogrid_disk(), {0.0, 0.5, 1.0}))}}) {
    WeaveOptions options;
    options.rules = RuleSet::Extended;
    WeaveState state = initial_state(mesh.surface, options, primal::dihedral_angles(mesh));
    WeaveContext ctx(options, nullptr, 1000000);
    for (int step = 0; step < 200 && state.front.num_faces() > 0; ++step) {
      const Counts n = compare_on(state.front, true, name + ", step " + std::to_string(step));
      ++fronts;
      all.counted += n.counted;
      const FrontLoops loops = front_loops(state.front);
      const FrontComponents components = front_components(state.front, ctx.nodes);
      const Ranking r = rank(selection, loop_candidates(state.front, loops, components, true, par,
                                                        ctx.nodes, ctx.faces, ctx.faces2));
      ASSERT_FALSE(r.order.empty()) << name;
      const TraceCandidate& c = r.order.front();
      const auto blocked = shrink(state, ctx, loops.strips[static_cast<std::size_t>(c.loop)],
                                  static_cast<stc::LoopSide>(c.side));
      if (blocked) break;  // the driver's other rules would go on; the fronts so far count
      seam_fixpoint(state, ctx);
    }
  }
  std::cout << fronts << " fronts, " << all.counted << " loops counted\n";
  EXPECT_GT(fronts, 15U);
  EXPECT_GT(all.counted, 60U);
}

TEST(SideFaces, LeavesTheLoopsOfAFrontWithAHandleToTheFloods) {
  // A square ring (genus 1): a loop round the tube does not separate the front, and no loop
  // is counted (the flood of such a loop reaches both its sides).
  const Counts n =
      compare_on(state_of(test::voxel_surface(test::ring_cells())).front, false, "square ring");
  EXPECT_EQ(n.counted, 0U);
  EXPECT_GT(n.left, 0U);
}

}  // namespace
}  // namespace stcweave::weave
