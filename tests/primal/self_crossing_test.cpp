#include "stcweave/primal/self_crossing.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>

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

// The generated catalogue (tests/support/quadrangulations.hpp): seeds 0..299, 8..21 quads
// (8 + seed % 14 doublet splits of the cube's quads), 40 random edge rotations, then repair.
constexpr std::uint32_t kSeeds = 300;
int target_of(std::uint32_t seed) {
  return 8 + static_cast<int>(seed % 14);
}

// Every even member with self-crossing loops either gives a certified complex whose boundary
// is exactly the surface, or a clean WeaveError; every odd one is refused for its parity.
// The figures are printed; docs/self-intersecting-loops.md has them.
TEST(SelfCrossing, GeneratedSpheresGiveCertifiedComplexesOrCleanRefusals) {
  std::size_t generated = 0, self_crossing = 0, even = 0, valid = 0, odd_refused = 0;
  std::size_t max_hexes = 0;
  for (std::uint32_t seed = 0; seed < kSeeds; ++seed) {
    const auto mesh = test::random_quadrangulation(seed, target_of(seed), 40);
    if (!mesh) continue;
    ++generated;
    const stc::LoopSet loops = stc::find_loops(mesh->surface, {.sides = false});
    if (loops.num_self_intersecting() == 0) continue;
    ++self_crossing;
    if (mesh->surface.quads.size() % 2 == 1) {
      const SurfaceDiagnosis d = diagnose(file_of(*mesh, "odd"));
      try {
        require_weavable(d, true);
        ADD_FAILURE() << "seed " << seed << ": an odd surface was not refused";
      } catch (const TopologyError& e) {
        EXPECT_NE(std::string(e.what()).find("odd number"), std::string::npos) << e.what();
        ++odd_refused;
      }
      continue;
    }
    ++even;
    SelfCrossingReport report;
    SelfCrossingOptions options;
    options.search.max_evaluations =
        20000;  // keeps the test short; the default (200000) gives the same count
    try {
      const weave::WeaveResult r = weave_self_crossing(*mesh, {}, {}, options, report);
      const stc::ValidationReport v = stc::validate_hex_complex(r.complex, &mesh->surface);
      EXPECT_TRUE(v.valid) << "seed " << seed << ": " << v.summary();
      EXPECT_EQ(r.num_input_nodes, mesh->surface.num_nodes);
      EXPECT_EQ(r.dual.size(), r.complex.hexes.size());
      if (v.valid) ++valid;
      std::cout << "seed " << seed << " (" << mesh->surface.quads.size()
                << " quads): " << r.complex.hexes.size() << " hexes (" << report.attached_hexes
                << " attached, " << report.woven_hexes << " woven"
                << (report.pillowed ? ", pillowed" : "")
                << (report.filled ? ", filled by moves" : "") << ")\n";
      max_hexes = std::max(max_hexes, r.complex.hexes.size());
    } catch (const WeaveError& e) {
      EXPECT_NE(std::string(e.what()).find("self-intersecting loops"), std::string::npos);
    }
  }
  std::cout << "generated " << generated << " strong quadrangulations, " << self_crossing
            << " with self-crossing loops: " << even << " even, of which " << valid
            << " give a valid complex (at most " << max_hexes << " hexes); " << odd_refused
            << " odd ones refused\n";
  EXPECT_GT(even, 20U);
  EXPECT_GT(odd_refused, 20U);
  // Measured: 38 of 40 (1 of 40 before the weave of the front had recovery pillows and free
  // nodes; docs/self-intersecting-loops.md); a regression lowers it.
  EXPECT_GE(valid, 38U);
}

TEST(SelfCrossing, WhenTheSearchGivesUpTheFrontIsWrittenAndTheErrorSaysWhy) {
  const auto mesh = test::random_quadrangulation(154, target_of(154), 40);
  ASSERT_TRUE(mesh.has_value());
  ASSERT_GT(stc::find_loops(mesh->surface, {.sides = false}).num_self_intersecting(), 0U);
  const std::filesystem::path front =
      std::filesystem::temp_directory_path() / "stcweave_self_crossing_front.obj";
  std::filesystem::remove(front);
  SelfCrossingOptions options;
  options.front_on_failure = front.string();
  options.search.max_moves = 2;
  options.fill_up_to = 0;
  SelfCrossingReport report;
  try {
    (void)weave_self_crossing(*mesh, {}, {}, options, report);
    FAIL() << "two moves cannot untangle this surface";
  } catch (const WeaveError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("gave up"), std::string::npos) << what;
    EXPECT_NE(what.find(front.string()), std::string::npos) << what;
  }
  EXPECT_TRUE(std::filesystem::exists(front));
  EXPECT_LE(report.moves.moves.size(), 2U);  // the bound holds through the look-ahead too
  std::filesystem::remove(front);
}

TEST(SelfCrossing, PipelineRefusesSelfCrossingLoopsWhenTheMovesAreOff) {
  std::optional<SurfaceMesh> mesh;
  for (std::uint32_t seed = 0; seed < kSeeds && !mesh; ++seed) {
    auto m = test::random_quadrangulation(seed, target_of(seed), 40);
    if (m && m->surface.quads.size() % 2 == 0 &&
        stc::find_loops(m->surface, {.sides = false}).num_self_intersecting() > 0)
      mesh = std::move(m);
  }
  ASSERT_TRUE(mesh.has_value());
  MeshOptions options;
  options.self_crossing_moves = false;
  EXPECT_THROW((void)mesh_file(file_of(*mesh, "generated"), options), TopologyError);
}

// The pillow join on a surface the weave fills on its own: one pillow hex per quad, then the
// woven hexes of the copy; certified against the input.
TEST(SelfCrossing, ThePillowJoinIsACertifiedComplex) {
  const SurfaceMesh box = test::box_surface(2, 2, 1);
  SelfCrossingOptions options;
  options.always_pillow = true;
  SelfCrossingReport report;
  const weave::WeaveResult r = weave_self_crossing(box, {}, {}, options, report);
  EXPECT_TRUE(report.pillowed);
  EXPECT_EQ(report.pillow_hexes, box.surface.quads.size());
  EXPECT_EQ(r.complex.hexes.size(), box.surface.quads.size() + 4U);
  const stc::ValidationReport v = stc::validate_hex_complex(r.complex, &box.surface);
  EXPECT_TRUE(v.valid) << v.summary();
  EXPECT_EQ(r.num_input_nodes, box.surface.num_nodes);
}

TEST(SelfCrossing, SurfacesWithSimpleLoopsDoNotGoThroughTheMoves) {
  const MeshResult r = mesh_file(file_of(test::box_surface(2, 1, 1), "box"));
  EXPECT_FALSE(r.self_crossing.used);
  EXPECT_EQ(r.mesh.complex.hexes.size(), 2U);
}

}  // namespace
}  // namespace stcweave::primal
