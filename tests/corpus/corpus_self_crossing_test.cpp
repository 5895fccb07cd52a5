// The genus-0 files of the shared corpus whose loops cross themselves (label `corpus`): each
// gives a certified complex whose boundary is the input, or a clean WeaveError naming the bound
// that stopped the search for front moves. Known answer: hexalab's sweep2017_Example_3 (one
// loop crossing itself twice) is meshed. Positioning is left out (its figures are in
// docs/self-intersecting-loops.md).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "stcweave/primal/io.hpp"
#include "stcweave/primal/pipeline.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/corpus.hpp"

namespace stcweave {
namespace {

TEST(CorpusSelfCrossing, GenusZeroFilesWithSelfCrossingLoopsAreMeshedOrRefusedCleanly) {
  const auto files = test::expected_files([](const nlohmann::json& v) {
    return v.value("genus", nlohmann::json()) == 0 && v.value("components", 0) == 1 &&
           v.value("self_intersecting_loops", 0) > 0 && v.value("quads", 0) % 2 == 0 &&
           v.value("quads", 0) <= 6000;
  });
  // One file per surface: the .boundary.obj beside each hex mesh has the same quads.
  if (files.empty()) GTEST_SKIP() << "shared data not found at " << STCWEAVE_SHARED_DATA;
  bool sweep_seen = false;
  for (const auto& name : files) {
    if (name.find(".boundary.obj") == std::string::npos) continue;
    SCOPED_TRACE(name);
    const auto file = primal::read_mesh(test::shared_data() / name);
    primal::MeshOptions options;
    options.untangle = false;
    options.self_crossing.search.max_work = 100000000;
    try {
      const primal::MeshResult r = primal::mesh_file(file, options);
      EXPECT_TRUE(r.validation.valid) << r.validation.summary();
      EXPECT_TRUE(r.validation.boundary_compared);
      EXPECT_TRUE(r.self_crossing.used);
      EXPECT_GT(r.self_crossing.attached_hexes, 0U);
      if (name.find("sweep2017_Example_3") != std::string::npos) sweep_seen = true;
    } catch (const WeaveError& e) {
      EXPECT_NE(std::string(e.what()).find("self-intersecting loops"), std::string::npos)
          << e.what();
      EXPECT_EQ(name.find("sweep2017_Example_3"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(sweep_seen) << "sweep2017_Example_3 was not meshed (or not in expected.json)";
}

}  // namespace
}  // namespace stcweave
