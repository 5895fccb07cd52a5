#include "stcweave/primal/self_crossing.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include "stcweave/primal/diagnose.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/loops.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/quadrangulations.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

MeshFile file_of(const SurfaceMesh& s, const std::string& name) {
  MeshFile f;
  f.path = name;
  f.format = "memory";
  f.points = s.points;
  f.quads = s.surface.quads;
  return f;
}

// The generated catalogue: seeds 0..kSeeds-1, 8..21 quads, 40 edge rotations each.
constexpr std::uint32_t kSeeds = 300;
int target_of(std::uint32_t seed) {
  return 8 + static_cast<int>(seed % 14);
}

TEST(SelfCrossing, EveryEvenGeneratedSphereWithSelfCrossingLoopsGivesAValidComplex) {
  std::size_t generated = 0, self_crossing = 0, even = 0, valid = 0, pillowed = 0;
  std::size_t max_hexes = 0, total_hexes = 0;
  std::vector<std::uint32_t> failed;
  for (std::uint32_t seed = 0; seed < kSeeds; ++seed) {
    const auto mesh = test::random_quadrangulation(seed, target_of(seed), 40);
    if (!mesh) continue;
    ++generated;
    const stc::LoopSet loops = stc::find_loops(mesh->surface, {.sides = false});
    if (loops.num_self_intersecting() == 0) continue;
    ++self_crossing;
    if (mesh->surface.quads.size() % 2 == 1) continue;
    ++even;
    SelfCrossingReport report;
    try {
      const weave::WeaveResult r = weave_self_crossing(*mesh, {}, {}, {}, report);
      const stc::ValidationReport v = stc::validate_hex_complex(r.complex, &mesh->surface);
      EXPECT_TRUE(v.valid) << "seed " << seed << ": " << v.summary();
      if (v.valid) ++valid;
      pillowed += report.pillowed ? 1 : 0;
      max_hexes = std::max(max_hexes, r.complex.hexes.size());
      total_hexes += r.complex.hexes.size();
    } catch (const Error& e) {
      failed.push_back(seed);
      std::cout << "seed " << seed << " (" << mesh->surface.quads.size() << " quads): " << e.what()
                << "\n";
    }
  }
  std::cout << "generated " << generated << ", with self-crossing loops " << self_crossing
            << ", even " << even << ", valid complexes " << valid << " (" << pillowed
            << " through the pillow layer), hexes max " << max_hexes << " mean "
            << (valid > 0 ? static_cast<double>(total_hexes) / static_cast<double>(valid) : 0.0)
            << "\n";
  EXPECT_GT(even, 20u);
  EXPECT_EQ(valid, even) << failed.size() << " failed";
}

}  // namespace
}  // namespace stcweave::primal
namespace stcweave::primal {
namespace {
TEST(SelfCrossingDebug, Gen) {
  EXPECT_TRUE(test::is_strong_quadrangulation(test::box_surface(1, 1, 1).surface));
  EXPECT_TRUE(test::random_quadrangulation(1, 6, 10).has_value());
  int ok = 0;
  for (std::uint32_t s = 0; s < 50; ++s)
    ok += test::random_quadrangulation(s, 10, 0).has_value() ? 1 : 0;
  std::cout << "no flips ok " << ok << "\n";
  ok = 0;
  for (std::uint32_t s = 0; s < 50; ++s)
    ok += test::random_quadrangulation(s, 10, 200).has_value() ? 1 : 0;
  std::cout << "200 flips ok " << ok << "\n";
}
}  // namespace
}  // namespace stcweave::primal
