// Genus > 0 files of the shared corpus (label `corpus`): the handle diagnosis finds one even
// handle cycle per handle on every loop-clean one, and the Gmsh block-structured solids are
// cut, woven and glued into Gmsh's structured hex counts (boxhole 36, part 25), the O-grid
// torus into a valid complex without inverted hexes, MFEM's toroid into its 6 hexes.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>

#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/primal/pillow.hpp"
#include "stcweave/primal/pipeline.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/corpus.hpp"

namespace stcweave {
namespace {

TEST(CorpusGenus, EveryLoopCleanHandleIsDecidedAndEven) {
  const auto files = test::expected_files([](const nlohmann::json& v) {
    return v.value("genus", nlohmann::json()).is_number() && v.value("genus", 0) > 0 &&
           v.value("self_intersecting_loops", -1) == 0 &&
           v.value("orientable", nlohmann::json()) != false;
  });
  if (files.empty()) GTEST_SKIP() << "shared data not found at " << STCWEAVE_SHARED_DATA;
  EXPECT_GE(files.size(), 20u);
  for (const auto& name : files) {
    SCOPED_TRACE(name);
    const primal::SurfaceDiagnosis d =
        primal::diagnose(primal::read_mesh(test::shared_data() / name));
    ASSERT_TRUE(d.handles);
    ASSERT_TRUE(d.handles->decided) << d.handles->undecided_reason;
    EXPECT_EQ(d.handles->genus, test::expected_figures()[name]["genus"].get<int>());
    EXPECT_EQ(d.handles->handles.size() + d.handles->combined_lengths.size(),
              static_cast<std::size_t>(d.handles->genus));
    EXPECT_TRUE(d.handles->all_even());
  }
}

TEST(CorpusGenus, StructuredSolidsWithAHoleGetTheirKnownCounts) {
  if (!std::filesystem::exists(test::shared_data() / "gmsh/boxhole_tf_coarse.obj"))
    GTEST_SKIP() << "shared data not found at " << STCWEAVE_SHARED_DATA;
  // 0 = no known count: a valid complex without inverted hexes is what is asserted.
  const std::map<std::string, std::size_t> known = {{"gmsh/boxhole_tf_coarse.obj", 36},
                                                    {"gmsh/part_tf_coarse.obj", 25},
                                                    {"gmsh/torus_tf_coarse.obj", 0},
                                                    {"real/mfem/toroid-hex.mesh", 6}};
  for (const auto& [name, hexes] : known) {
    SCOPED_TRACE(name);
    const auto file = primal::read_mesh(test::shared_data() / name);
    primal::MeshResult r;
    ASSERT_NO_THROW(r = primal::mesh_file(file));
    EXPECT_TRUE(r.validation.valid) << r.validation.summary();
    EXPECT_TRUE(r.validation.boundary_compared);
    EXPECT_EQ(r.quality.inverted, 0u);
    EXPECT_EQ(r.solids.cuts.size(), 1u);
    if (hexes > 0) EXPECT_EQ(r.mesh.complex.hexes.size(), hexes);
  }
}

// The depth filter is off in the weaves of cut balls (CutOptions::ball_depth_filter): the
// rocker arm's disc copies have depth 0 like its boundary, and with the filter the weave peels
// layers off them. Woven hexes without the pillow or positioning: about 5,800 without the
// filter (reliable: 5,830), about 10,000 with it, when the non-convex filter lets every side
// through where each has a non-convex edge (as it did when this was measured). Keeping the
// sides with the fewest (the default since) gives 5,140 without and 5,164 with the filter.
TEST(CorpusGenus, CutBallsAreWovenWithoutTheDepthFilter) {
  const auto path = test::shared_data() / "real/cinolib/rockerarm.boundary.obj";
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << "shared data not found at " << STCWEAVE_SHARED_DATA;
  const auto file = primal::read_mesh(path);
  primal::MeshOptions o;
  o.untangle = false;
  o.pillow.mode = primal::PillowMode::Never;
  o.weave.extended.nonconvex_least = false;
  ASSERT_TRUE(o.weave.extended.depth_filter) << "an uncut solid keeps the seed's depth filter";
  const primal::MeshResult without = primal::mesh_file(file, o);
  o.cut.ball_depth_filter = true;
  const primal::MeshResult with = primal::mesh_file(file, o);
  EXPECT_TRUE(without.validation.valid) << without.validation.summary();
  EXPECT_TRUE(with.validation.valid) << with.validation.summary();
  EXPECT_LT(without.mesh.complex.hexes.size(), 6000u);
  EXPECT_GT(with.mesh.complex.hexes.size(), 9000u);
}

// The second convex filter's threshold (ExtendedParameters::second_convex_min_weight, default
// 0.1): in the kitty's cut ball the seed's rule kept sides with 3 sharp edges along loops of
// 40 and 60 quads over cheaper ones, 7,643 hexes in all; by default 7,083, the count of
// `reliable` and of the reference mesh.
TEST(CorpusGenus, KittyGetsItsReferenceCountWithTheSecondConvexThreshold) {
  const auto path = test::shared_data() / "real/hexalab/l1pc2014_kitty.boundary.obj";
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << "shared data not found at " << STCWEAVE_SHARED_DATA;
  const auto file = primal::read_mesh(path);
  const std::size_t reference_hexes = 7083;
  const primal::MeshResult r = primal::mesh_file(file, primal::MeshOptions{});
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.mesh.complex.hexes.size(), reference_hexes);
  EXPECT_EQ(r.quality.inverted, 0u) << r.position.stop;
  primal::MeshOptions seed;
  seed.weave.extended.second_convex_min_weight = 0.0;
  seed.untangle = false;
  const primal::MeshResult s = primal::mesh_file(file, seed);
  EXPECT_TRUE(s.validation.valid) << s.validation.summary();
  EXPECT_GT(s.mesh.complex.hexes.size(), reference_hexes) << "the seed's rule";
}

// The non-convex filter's relaxation (ExtendedParameters::nonconvex_least): in the ball of
// the hexalab rocker arm most selections find a non-convex edge on every side. Relaxed
// entirely, the second convex filter then picks sides of 250 to 360 faces with 24 non-convex
// edges; keeping the sides with the fewest, the weave stays near `reliable`'s 11,664 woven
// hexes. Woven hexes, no pillow, no positioning: 11,754 against 15,074.
TEST(CorpusGenus, RockerArmBallKeepsTheSidesWithTheFewestNonConvexEdges) {
  const auto path = test::shared_data() / "real/hexalab/cfip2016_rockerarm-hex.boundary.obj";
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << "shared data not found at " << STCWEAVE_SHARED_DATA;
  const auto file = primal::read_mesh(path);
  primal::MeshOptions o;
  o.untangle = false;
  o.pillow.mode = primal::PillowMode::Never;
  const primal::MeshResult least = primal::mesh_file(file, o);
  o.weave.extended.nonconvex_least = false;
  const primal::MeshResult all = primal::mesh_file(file, o);
  EXPECT_TRUE(least.validation.valid) << least.validation.summary();
  EXPECT_TRUE(all.validation.valid) << all.validation.summary();
  EXPECT_LT(least.mesh.complex.hexes.size(), 12500u);
  EXPECT_GT(all.mesh.complex.hexes.size(), 14000u);
}

TEST(CorpusGenus, HollowHandlebodiesAreRefusedAsUnsupported) {
  if (!std::filesystem::exists(test::shared_data() / "real/hexalab/cfip2016_hollow-eight-hex.vtk"))
    GTEST_SKIP() << "shared data not found at " << STCWEAVE_SHARED_DATA;
  // A hollow double torus: a cavity with handles. (part_a6_trisubdiv_coarse, refused here
  // before, is meshed by the slab route: corpus_genus3_test.cpp.)
  const std::map<std::string, std::string> refused = {
      {"real/hexalab/cfip2016_hollow-eight-hex.vtk", "a cavity with handles"}};
  for (const auto& [name, why] : refused) {
    SCOPED_TRACE(name);
    try {
      (void)primal::mesh_file(primal::read_mesh(test::shared_data() / name));
      ADD_FAILURE() << "expected Unsupported";
    } catch (const Unsupported& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace stcweave
