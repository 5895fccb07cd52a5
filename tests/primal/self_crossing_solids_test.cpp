#include "stcweave/primal/self_crossing_solids.hpp"

#include <gtest/gtest.h>

#include <array>
#include <iostream>
#include <optional>
#include <string>

#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/pipeline.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/loops.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/quadrangulations.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

using test::file_of;

std::size_t self_intersecting(const SurfaceMesh& m) {
  return stc::find_loops(m.surface, {.sides = false}).num_self_intersecting();
}

// Every single edge rotation of `start` (in quad, corner, diagonal order) that keeps a strong
// quadrangulation and makes a loop cross itself, with its handle cycles decided and even.
std::vector<SurfaceMesh> self_crossing_rotations(const SurfaceMesh& start) {
  std::vector<SurfaceMesh> out;
  for (std::size_t q = 0; q < start.surface.quads.size(); ++q) {
    for (std::size_t corner = 0; corner < 4; ++corner) {
      for (const bool other : {false, true}) {
        auto m = test::rotate_edge(start, q, corner, other);
        if (!m || self_intersecting(*m) == 0) continue;
        const SurfaceDiagnosis d = diagnose(file_of(*m, "rotated"));
        if (!d.handles || !d.handles->decided || !d.handles->all_even()) continue;
        out.push_back(std::move(*m));
      }
    }
  }
  return out;
}

// The square ring (3x3x1 block minus its centre column: 32 quads, genus 1) with one edge
// rotated so that a loop crosses itself, for the first rotations in (quad, corner, diagonal)
// order: each is cut along its handle and the balls go through the front moves; each gives a
// certified complex with the input as its boundary, or a clean refusal (a WeaveError naming
// the shared search pool and the disc search). Never an invalid complex. With a pool of
// 300,000 evaluations instead of the default 10 million, so that a refusal takes seconds.
TEST(SelfCrossingSolids, RotatedRingsGiveCertifiedComplexesOrCleanRefusals) {
  const std::vector<SurfaceMesh> rotated =
      self_crossing_rotations(test::voxel_surface(test::ring_cells()));
  ASSERT_GE(rotated.size(), 4u);
  std::size_t valid = 0;
  std::size_t refused = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    SCOPED_TRACE("rotation " + std::to_string(k));
    SurfaceMesh ring = rotated[k];
    (void)orient_outward(ring);
    SharedSearchBudget budget;
    budget.evaluations = 300000;
    SolidsReport solids;
    SelfCrossingReport report;
    weave::WeaveOptions weave_options;
    weave_options.rules = weave::RuleSet::Extended;
    try {
      const weave::WeaveResult woven =
          weave_solids_self_crossing(ring, weave_options, {}, {}, &solids, report, budget);
      const stc::ValidationReport v = stc::validate_hex_complex(woven.complex, &ring.surface);
      EXPECT_TRUE(v.valid) << v.summary();
      EXPECT_EQ(solids.cuts.size(), 1u);
      if (v.valid) ++valid;
    } catch (const WeaveError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("shared budget"), std::string::npos) << what;
      EXPECT_NE(what.find("no choice of discs"), std::string::npos) << what;
      ++refused;
    }
  }
  std::cout << "first 4 self-crossing rotations of the square ring: " << valid
            << " certified complexes, " << refused << " refused\n";
  // Measured 2026-12-07: 1 certified, 3 refused. Until hex contacts were checked, 4 of 4 gave
  // a "certified" complex (at most 361 hexes), each holding two hexes that share four nodes
  // off a face; now most balls' weaves block (docs/self-intersecting-loops.md). A regression
  // lowers the count.
  EXPECT_EQ(valid + refused, 4u);
  EXPECT_GE(valid, 1u);
}

// A thicker ring (3x3x2 block minus its centre column: 48 quads, genus 1) with one edge
// rotated so that a loop crosses itself: through the pipeline with default options (the
// default shared search pool), a certified complex with the input as its boundary. Measured
// 2026-12-07: 106 hexes before the pillow layer, about two minutes; the thin ring above has
// too little room for its balls' weaves since hex contacts are checked.
TEST(SelfCrossingSolids, RotatedThickRingGivesACertifiedComplex) {
  std::vector<std::array<int, 3>> cells = test::ring_cells();
  for (const auto& c : test::ring_cells()) cells.push_back({c[0], c[1], 1});
  const std::vector<SurfaceMesh> rotated = self_crossing_rotations(test::voxel_surface(cells));
  ASSERT_FALSE(rotated.empty());
  MeshOptions options;
  options.untangle = false;
  const MeshResult r = mesh_file(file_of(rotated.front(), "rotated thick ring"), options);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_TRUE(r.self_crossing.used);
  EXPECT_TRUE(r.validation.boundary_compared);
  EXPECT_EQ(r.solids.cuts.size(), 1u);
  EXPECT_GT(r.self_crossing.attached_hexes, 0u);
}

// Two shells, one a sphere whose loops cross themselves, the other a ring with a handle: each
// solid on its own, the sphere through the moves, the ring through its cut.
TEST(SelfCrossingSolids, SeveralShellsOneSelfCrossingAreBothMeshed) {
  std::optional<SurfaceMesh> sphere;
  for (std::uint32_t seed = 0; seed < 300 && !sphere; ++seed) {
    auto m = test::random_quadrangulation(seed, 8 + static_cast<int>(seed % 14), 40);
    if (m && m->surface.quads.size() % 2 == 0 && self_intersecting(*m) > 0) {
      try {
        SelfCrossingReport rep;
        (void)weave_self_crossing(*m, {}, {}, {}, rep);
        sphere = std::move(m);
      } catch (const WeaveError&) {
      }
    }
  }
  ASSERT_TRUE(sphere.has_value());
  const SurfaceMesh ring = test::voxel_surface(test::ring_cells());
  const SurfaceMesh both =
      test::merged_surfaces({ring, test::translated(*sphere, {10.0, 0.0, 0.0})});
  const MeshResult r = mesh_file(file_of(both, "ring and sphere"));
  EXPECT_EQ(r.solids.solids, 2u);
  EXPECT_TRUE(r.self_crossing.used);
  EXPECT_GT(r.self_crossing.attached_hexes, 0u);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  // Against the input oriented outward: the generated sphere's quads may face inward, and
  // the pipeline weaves (and reports) the outward surface.
  SurfaceMesh outward = both;
  (void)orient_outward(outward);
  const stc::ValidationReport v = stc::validate_hex_complex(r.mesh.complex, &outward.surface);
  EXPECT_TRUE(v.valid) << v.summary();
}

// The front-move searches of the disc choices share one budget: once a search uses it up, no
// later ball is searched, and the disc search ends with a WeaveError (exit code 3) that says
// so, instead of rerunning a whole search per disc choice.
TEST(SelfCrossingSolids, SharedSearchBudgetEndsTheDiscSearchWithAWeaveError) {
  const std::vector<SurfaceMesh> rotated =
      self_crossing_rotations(test::voxel_surface(test::ring_cells()));
  ASSERT_FALSE(rotated.empty());
  SurfaceMesh ring = rotated.front();
  (void)orient_outward(ring);
  SharedSearchBudget budget;
  budget.work = 1;  // the first search stops at once
  SolidsReport solids;
  SelfCrossingReport report;
  try {
    (void)weave_solids_self_crossing(ring, {}, {}, {}, &solids, report, budget);
    FAIL() << "expected WeaveError";
  } catch (const WeaveError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("used up their shared budget"), std::string::npos) << what;
    EXPECT_NE(what.find("1 cut balls went through the front moves"), std::string::npos) << what;
    EXPECT_NE(what.find("no choice of discs"), std::string::npos) << what;
  }
  // The pool of evaluations counts every search of a ball, the fills and the rounds during
  // its weaves too: on this ring the untangling searches alone took 726,000 evaluations over
  // 60 balls (measured 2026-12-07), so a pool of 300,000 runs dry only because the others
  // are counted, and the disc search ends after a few balls instead of 20 minutes.
  SharedSearchBudget pool;
  pool.evaluations = 300000;
  try {
    (void)weave_solids_self_crossing(ring, {}, {}, {}, &solids, report, pool);
    FAIL() << "expected WeaveError";
  } catch (const WeaveError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("used up their shared budget"), std::string::npos) << what;
    EXPECT_NE(what.find("300000 moves, "), std::string::npos) << what;
  }
}

TEST(SelfCrossingSolids, MovesOffStillRefusesSelfCrossingLoopsOnAHandle) {
  const std::vector<SurfaceMesh> rotated =
      self_crossing_rotations(test::torus_surface(8, 12, 3.0, 1.0));
  ASSERT_FALSE(rotated.empty());
  MeshOptions options;
  options.self_crossing_moves = false;
  EXPECT_THROW((void)mesh_file(file_of(rotated.front(), "rotated torus"), options), TopologyError);
}

// An odd handle cycle stays refused as impossible when a loop also crosses itself.
TEST(SelfCrossingSolids, OddHandleCycleWithASelfCrossingLoopIsRefusedAsImpossible) {
  const SurfaceMesh tri = test::torus_surface(3, 8, 3.0, 1.0);
  std::optional<SurfaceMesh> crossed;
  for (std::size_t q = 0; q < tri.surface.quads.size() && !crossed; ++q)
    for (std::size_t corner = 0; corner < 4 && !crossed; ++corner)
      if (auto m = test::rotate_edge(tri, q, corner, false); m && self_intersecting(*m) > 0) {
        const SurfaceDiagnosis d = diagnose(file_of(*m, "rotated"));
        if (d.handles && d.handles->decided && !d.handles->all_even()) crossed = std::move(m);
      }
  ASSERT_TRUE(crossed.has_value()) << "no rotation of the triangular torus crosses a loop";
  try {
    (void)mesh_file(file_of(*crossed, "tri-torus.obj"));
    FAIL() << "expected TopologyError";
  } catch (const TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("no hex mesh with this boundary exists"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace stcweave::primal
