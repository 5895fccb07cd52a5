#include "stcweave/primal/tet_interior.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "stcweave/primal/cad.hpp"
#include "stcweave/primal/pipeline.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/cad.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

using test::triangle_split_of;

/// The voxel L-block (10 unit cubes), its quads split into triangles and those into quads:
/// a non-convex triangle-split surface like those CAD gives.
SurfaceMesh split_lblock() {
  return triangle_split_of(test::voxel_surface(test::lblock_cells()));
}

class TetInterior : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!has_tet_interior_support()) GTEST_SKIP() << "stcweave was built without Gmsh";
  }
};

TEST(TetInteriorModes, NamesRoundTripAndUnknownNamesAreRefused) {
  for (const InteriorMode m : {InteriorMode::Auto, InteriorMode::Weave, InteriorMode::Tets})
    EXPECT_EQ(interior_mode_from_name(interior_mode_name(m)), m);
  EXPECT_THROW((void)interior_mode_from_name("tet"), InvalidInput);
}

TEST_F(TetInterior, SplitsTheLBlockIntoAValidComplexBoundedByTheInput) {
  const SurfaceMesh surface = split_lblock();
  const std::optional<stc::TriangleSplit> split = stc::recognise_triangle_split(surface.surface);
  ASSERT_TRUE(split.has_value());
  Points positions;
  TetInteriorReport report;
  const weave::WeaveResult r = tet_interior(surface, *split, {}, positions, &report);
  EXPECT_EQ(report.triangles, surface.surface.quads.size() / 3);
  EXPECT_GT(report.tets, 0u);
  EXPECT_EQ(r.complex.hexes.size(), 4 * report.tets);
  EXPECT_EQ(r.num_input_nodes, surface.surface.num_nodes);
  EXPECT_EQ(r.hex_rule.size(), r.complex.hexes.size());
  EXPECT_EQ(r.hex_shrink.size(), r.complex.hexes.size());
  ASSERT_EQ(static_cast<std::size_t>(positions.rows()), r.complex.num_nodes);
  // The surface's nodes keep their coordinates exactly.
  EXPECT_TRUE(positions.topRows(surface.points.rows()).isApprox(surface.points, 0.0));
  const stc::ValidationReport v = stc::validate_hex_complex(r.complex, &surface.surface);
  EXPECT_TRUE(v.valid) << v.summary();
  EXPECT_TRUE(v.boundary_compared);
  // Gmsh's tets are positive, so the split start has no inverted hex.
  HexMesh start{positions, r.complex};
  EXPECT_EQ(summarize_quality(start).inverted, 0u);
}

TEST_F(TetInterior, PipelineKeepsTheBetterInteriorAndSaysWhy) {
  const MeshFile file = test::file_of(split_lblock(), "split-lblock");
  MeshOptions woven_only;
  woven_only.interior.mode = InteriorMode::Weave;
  const MeshResult woven = mesh_file(file, woven_only);
  EXPECT_FALSE(woven.interior.used);
  EXPECT_FALSE(woven.interior.compared);

  MeshOptions tets_only;
  tets_only.interior.mode = InteriorMode::Tets;
  const MeshResult tets = mesh_file(file, tets_only);
  EXPECT_TRUE(tets.interior.used);
  EXPECT_TRUE(tets.validation.valid) << tets.validation.summary();
  EXPECT_EQ(tets.quality.inverted, 0u);
  EXPECT_EQ(tets.woven.complex.hexes.size(), 4 * tets.interior.tets);

  const MeshResult best = mesh_file(file, MeshOptions{});
  EXPECT_TRUE(best.interior.triangle_split);
  EXPECT_TRUE(best.interior.compared);
  EXPECT_NE(best.interior.reason.find("tets: "), std::string::npos) << best.interior.reason;
  EXPECT_NE(best.interior.reason.find("woven: "), std::string::npos) << best.interior.reason;
  EXPECT_GT(best.seconds.other_interior, 0.0);
  // What auto kept is the better of the two runs above, run for run.
  const MeshResult& expected =
      better_or_equal(tets, woven) && !better_or_equal(woven, tets) ? tets : woven;
  EXPECT_EQ(best.interior.used, &expected == &tets) << best.interior.reason;
  EXPECT_EQ(best.mesh.complex.hexes, expected.mesh.complex.hexes);
  EXPECT_TRUE(best.mesh.points.isApprox(expected.mesh.points, 0.0));
}

TEST(TetInteriorChoice, ValidFirstThenInvertedThenMinimumThenHexes) {
  const auto result = [](bool valid, std::size_t inverted, double min_sj, std::size_t hexes) {
    MeshResult r;
    r.validation.valid = valid;
    r.quality.inverted = inverted;
    r.quality.min_scaled_jacobian = min_sj;
    r.quality.hexes = hexes;
    return r;
  };
  const auto strictly = [](const MeshResult& a, const MeshResult& b) {
    return better_or_equal(a, b) && !better_or_equal(b, a);
  };
  EXPECT_TRUE(strictly(result(true, 9, -0.5, 900), result(false, 0, 0.9, 10)));
  EXPECT_TRUE(strictly(result(true, 0, 0.1, 900), result(true, 1, 0.9, 10)));
  EXPECT_TRUE(strictly(result(true, 0, 0.3, 900), result(true, 0, 0.2, 10)));
  EXPECT_TRUE(strictly(result(true, 0, 0.3, 10), result(true, 0, 0.3, 11)));
  // A tie either way: auto keeps the weave.
  EXPECT_TRUE(better_or_equal(result(true, 0, 0.3, 10), result(true, 0, 0.3, 10)));
}

TEST_F(TetInterior, AFailedWeaveLeavesTheTetsAndNoTraceOfIt) {
  const MeshFile file = test::file_of(split_lblock(), "split-lblock");
  MeshOptions options;
  options.weave.max_rules = 1;  // the weave gives up after one rule (no rescue with a budget)
  std::size_t events = 0;
  options.weave.on_trace = [&events](const weave::TraceEvent&) { ++events; };
  std::vector<std::string> stages;
  options.on_stage = [&stages](const std::string& s) { stages.push_back(s); };
  const MeshResult r = mesh_file(file, options);
  EXPECT_TRUE(r.interior.used);
  EXPECT_NE(r.interior.reason.find("the weave failed"), std::string::npos) << r.interior.reason;
  EXPECT_EQ(events, 0u);  // the failed weave's trace is not the kept mesh's
  EXPECT_NE(std::find(stages.begin(), stages.end(), "woven interior: weave"), stages.end());
  EXPECT_NE(std::find(stages.begin(), stages.end(), "tet interior: weave"), stages.end());
  // With --interior weave the same budget is an error.
  options.interior.mode = InteriorMode::Weave;
  EXPECT_THROW((void)mesh_file(file, options), WeaveError);
}

TEST_F(TetInterior, AKeptWeaveKeepsItsTrace) {
  // The 2 x 2 x 2 box is the split octahedron: its weave (8 hexes of scaled Jacobian 1) wins.
  MeshOptions options;
  std::size_t events = 0;
  options.weave.on_trace = [&events](const weave::TraceEvent&) { ++events; };
  const MeshResult r = mesh_file(test::file_of(test::box_surface(2, 2, 2), "box2"), options);
  EXPECT_TRUE(r.interior.triangle_split);
  EXPECT_TRUE(r.interior.compared);
  EXPECT_FALSE(r.interior.used) << r.interior.reason;
  EXPECT_EQ(r.mesh.complex.hexes.size(), 8u);
  EXPECT_GT(events, 0u);
}

TEST_F(TetInterior, GrowthGivesFewerTetsInsideAndKeepsThemValid) {
  // A 4 x 4 x 4 box whose quads are split into triangles: room inside to grow.
  const SurfaceMesh surface = triangle_split_of(test::box_surface(4, 4, 4));
  const std::optional<stc::TriangleSplit> split = stc::recognise_triangle_split(surface.surface);
  ASSERT_TRUE(split.has_value());
  std::array<std::size_t, 2> tets{};
  for (std::size_t i = 0; i < 2; ++i) {
    TetInteriorOptions options;
    options.growth = i == 0 ? 1.0 : 2.0;
    Points positions;
    TetInteriorReport report;
    const weave::WeaveResult r = tet_interior(surface, *split, options, positions, &report);
    tets[i] = report.tets;
    const stc::ValidationReport v = stc::validate_hex_complex(r.complex, &surface.surface);
    EXPECT_TRUE(v.valid) << v.summary();
    EXPECT_EQ(summarize_quality(HexMesh{positions, r.complex}).inverted, 0u);
  }
  EXPECT_LT(tets[1], tets[0]);
}

TEST_F(TetInterior, FlipsRemoveTetsAndKeepTheComplexValid) {
  const SurfaceMesh surface = triangle_split_of(test::box_surface(4, 4, 4));
  const std::optional<stc::TriangleSplit> split = stc::recognise_triangle_split(surface.surface);
  ASSERT_TRUE(split.has_value());
  std::array<TetInteriorReport, 2> reports;
  std::array<std::size_t, 2> hexes{};
  for (std::size_t i = 0; i < 2; ++i) {
    TetInteriorOptions options;
    options.flips = i == 1;
    Points positions;
    const weave::WeaveResult r = tet_interior(surface, *split, options, positions, &reports[i]);
    hexes[i] = r.complex.hexes.size();
    const stc::ValidationReport v = stc::validate_hex_complex(r.complex, &surface.surface);
    EXPECT_TRUE(v.valid) << v.summary();
    EXPECT_EQ(summarize_quality(HexMesh{positions, r.complex}).inverted, 0u);
  }
  EXPECT_EQ(reports[0].flips, 0u);
  ASSERT_GT(reports[1].flips, 0u);
  EXPECT_EQ(reports[1].tets + reports[1].flips, reports[0].tets);
  EXPECT_EQ(hexes[1] + 4 * reports[1].flips, hexes[0]);
}

TEST_F(TetInterior, LeavesGmshAsItFoundItForTheCadFrontEnd) {
  // The growth is a size callback in Gmsh's one session, which Gmsh 4.8 keeps across
  // clear(): a CAD surface meshed after a tet interior must be the one meshed before it.
  const CadSurface before =
      mesh_cad_surface(test::repo_data("plate_slot.step"), test::cad_options(0.5));
  const SurfaceMesh surface = triangle_split_of(test::box_surface(4, 4, 4));
  Points positions;
  (void)tet_interior(surface, *stc::recognise_triangle_split(surface.surface), {}, positions);
  const CadSurface after =
      mesh_cad_surface(test::repo_data("plate_slot.step"), test::cad_options(0.5));
  EXPECT_EQ(after.file.quads, before.file.quads);
  EXPECT_TRUE(after.file.points.isApprox(before.file.points, 0.0));
}

TEST_F(TetInterior, TheSameInputGivesTheSameMesh) {
  const MeshFile file = test::file_of(split_lblock(), "split-lblock");
  MeshOptions options;
  options.interior.mode = InteriorMode::Tets;
  const MeshResult a = mesh_file(file, options);
  const MeshResult b = mesh_file(file, options);
  EXPECT_EQ(a.mesh.complex.hexes, b.mesh.complex.hexes);
  EXPECT_TRUE(a.mesh.points.isApprox(b.mesh.points, 0.0));
}

TEST_F(TetInterior, TetsAreRefusedForASurfaceThatIsNotTriangleSplit) {
  MeshOptions options;
  options.interior.mode = InteriorMode::Tets;
  try {
    (void)mesh_file(test::file_of(test::box_surface(3, 2, 2), "box"), options);
    FAIL() << "a box surface was accepted by --interior tets";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("triangle-split"), std::string::npos) << e.what();
  }
  // Auto weaves it without a second run.
  const MeshResult r = mesh_file(test::file_of(test::box_surface(3, 2, 2), "box"));
  EXPECT_FALSE(r.interior.triangle_split);
  EXPECT_EQ(r.seconds.other_interior, 0.0);
  EXPECT_EQ(r.mesh.complex.hexes.size(), 12u);
}

/// The pipeline with `--interior tets` on `surface`: valid against it, with no inverted hex.
void expect_valid_tets(const SurfaceMesh& surface, const std::string& name) {
  MeshOptions options;
  options.interior.mode = InteriorMode::Tets;
  const MeshResult r = mesh_file(test::file_of(surface, name), options);
  EXPECT_TRUE(r.interior.used);
  EXPECT_GT(r.interior.tets, 0u);
  const stc::ValidationReport v = stc::validate_hex_complex(r.mesh.complex, &r.surface.surface);
  EXPECT_TRUE(v.valid) << v.summary();
  EXPECT_TRUE(v.boundary_compared);
  EXPECT_EQ(r.quality.inverted, 0u);
}

TEST_F(TetInterior, TetsFillTwoDisjointSolids) {
  const SurfaceMesh one = split_lblock();
  expect_valid_tets(
      test::merged_surfaces({one, test::translated(one, Eigen::RowVector3d(10.0, 0.0, 0.0))}),
      "two");
}

/// A triangle-split 4 x 4 x 4 box with a 2 x 2 x 2 cavity at its centre, the cavity's quads
/// facing into it.
SurfaceMesh hollow_box() {
  const SurfaceMesh outer = triangle_split_of(test::box_surface(4, 4, 4));
  const SurfaceMesh inner = test::reversed_surface(
      test::translated(triangle_split_of(test::box_surface(2, 2, 2)), Eigen::RowVector3d(1, 1, 1)));
  return test::merged_surfaces({outer, inner});
}

TEST_F(TetInterior, TetsFillASolidWithACavity) {
  const SurfaceMesh hollow = hollow_box();
  expect_valid_tets(hollow, "hollow");
  // Auto takes the tets first on several shells and keeps them without weaving.
  const MeshResult r = mesh_file(test::file_of(hollow, "hollow"));
  EXPECT_TRUE(r.interior.used) << r.interior.reason;
  EXPECT_NE(r.interior.reason.find("2 shells: not woven"), std::string::npos) << r.interior.reason;
  EXPECT_EQ(r.seconds.other_interior, 0.0);
  EXPECT_EQ(r.quality.inverted, 0u);
}

/// The tet interior stage alone (no pipeline checks before it) refuses `surface` with an `E`
/// whose message holds `fragment`; `what` names the input in the failure message.
template <typename E>
void expect_stage_refuses(const SurfaceMesh& surface, const std::string& fragment,
                          const std::string& what) {
  const std::optional<stc::TriangleSplit> split = stc::recognise_triangle_split(surface.surface);
  ASSERT_TRUE(split.has_value());
  Points positions;
  try {
    (void)tet_interior(surface, *split, {}, positions);
    FAIL() << what << " was accepted";
  } catch (const E& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST_F(TetInterior, AnInwardShellInsideNoSolidIsRefused) {
  // Two disjoint L-blocks, the second facing inward: a "cavity" that no solid holds, which
  // only a caller skipping the pipeline's orientation can hand over.
  const SurfaceMesh one = split_lblock();
  const SurfaceMesh surface = test::merged_surfaces(
      {one, test::reversed_surface(test::translated(one, Eigen::RowVector3d(10.0, 0.0, 0.0)))});
  expect_stage_refuses<InvalidInput>(surface, "lies inside no solid",
                                     "an inward shell outside every solid");
}

TEST_F(TetInterior, ASolidInsideACavityIsMeshed) {
  // The hollow box with a small solid box floating in its cavity (nesting depth 2): the
  // floating box is a Gmsh volume of its own, the hollow box one with a hole.
  const SurfaceMesh core = test::translated(test::box_surface(1, 1, 1, 0.5, 0.5, 0.5),
                                            Eigen::RowVector3d(1.75, 1.75, 1.75));
  const SurfaceMesh nested = test::merged_surfaces({hollow_box(), triangle_split_of(core)});
  MeshOptions options;
  options.interior.mode = InteriorMode::Tets;
  const MeshResult r = mesh_file(test::file_of(nested, "nested"), options);
  EXPECT_TRUE(r.interior.used) << r.interior.reason;
  EXPECT_GT(r.interior.tets, 0u);
  const stc::ValidationReport v = stc::validate_hex_complex(r.mesh.complex, &r.surface.surface);
  EXPECT_TRUE(v.valid) << v.summary();
  EXPECT_TRUE(v.boundary_compared);
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_EQ(r.orientation.nesting_depth, (std::vector<int>{0, 1, 2}));
}

}  // namespace
}  // namespace stcweave::primal
