// `stcweave mesh` on CAD input (issue 15): the recipe line, the report's "cad" record,
// --surface-out, IGES input, splitting into blocks, exit code 2 for what is not a closed
// solid, the build without Gmsh.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "stcweave/primal/cad.hpp"
#include "stcweave/primal/io.hpp"
#include "support/cad.hpp"
#include "support/cli_run.hpp"
#include "support/iges.hpp"

namespace {

namespace fs = std::filesystem;
using stcweave::test::run_cli;
using stcweave::test::slurp;
using ::testing::HasSubstr;

class CadCli : public stcweave::test::CliTest {
 protected:
  CadCli() : CliTest("stcweave_cad_cli_") {}
  [[nodiscard]] std::string at(const std::string& name) const { return (dir_ / name).string(); }

  /// What `mesh` gave: its exit code and output, and its report (null when none was written).
  struct Meshed {
    stcweave::test::CliRun run;
    nlohmann::json report;
  };
  /// `stcweave mesh INPUT -o NAME.vtk ARGS --report NAME.json`, the one set-up of these tests.
  [[nodiscard]] Meshed mesh(const std::string& input, const std::string& name,
                            const std::string& args = "") const {
    Meshed m{run_cli("mesh " + input + " -o " + at(name + ".vtk") + " " + args + " --report " +
                     at(name + ".json")),
             nullptr};
    if (fs::exists(at(name + ".json"))) m.report = nlohmann::json::parse(slurp(at(name + ".json")));
    return m;
  }

  /// data/FILE at size 0.25, whose mixed surface `auto` drops for `dropped_because`: the tet
  /// interior, kept without a weave (`not_woven_because` in its reason), no inverted hex, and
  /// `check` certifies the mesh against the surface written.
  void expect_tets_without_a_weave(const std::string& file, const std::string& dropped_because,
                                   const std::string& not_woven_because) const {
    const auto [r, report] = mesh(data(file), "tw", "--size 0.25 --surface-out " + at("tw.obj"));
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_THAT(r.out, HasSubstr("mixed surface dropped: " + dropped_because));
    EXPECT_EQ(report["interior"]["used"], "tets");
    EXPECT_EQ(report["interior"]["compared"], false);
    EXPECT_THAT(report["interior"]["reason"].get<std::string>(),
                HasSubstr(not_woven_because + ": not woven"));
    EXPECT_EQ(report["seconds"]["other_interior"].get<double>(), 0.0);
    EXPECT_EQ(report["quality"]["inverted"], 0);
    EXPECT_GT(report["quality"]["min_scaled_jacobian"].get<double>(), 0.1);
    const auto check = run_cli("check " + at("tw.vtk") + " --boundary " + at("tw.obj"));
    EXPECT_EQ(check.code, 0) << check.out;
  }
};

TEST_F(CadCli, PlateWithASlotIsMeshedAndItsSurfaceWritten) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const auto [r, report] = mesh(data("plate_slot.step"), "plate",
                                "--size 0.5 --no-untangle --surface-out " + at("plate.obj"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("mixed surface"));
  EXPECT_THAT(r.out, HasSubstr("valid      yes"));
  EXPECT_THAT(r.out, ::testing::Not(HasSubstr("Info")));  // Gmsh stays quiet
  EXPECT_EQ(report["cad"]["recipe"], "mixed");
  EXPECT_GT(report["cad"]["structured_faces"].get<int>(), 0);
  EXPECT_EQ(report["cad"]["quads"], report["quads"]);
  EXPECT_LT(report["cad"]["max_cad_distance"].get<double>(), 1e-7);
  EXPECT_EQ(report["cad"]["split"], "");  // curved faces: not a solid the split recognises
  // At this size the top face folds at the slot's rounded end (docs/topology.md, "A surface
  // that passes through itself", measured 2026-12-08): the warning says so and points to
  // --size. When the CAD front end stops making that fold, this line goes.
  EXPECT_THAT(r.out, HasSubstr("the surface passes through itself: 4 pair(s) of quads cross"));
  EXPECT_THAT(r.out, HasSubstr("another --size may avoid the fold"));
  // The surface written is the one woven: meshing it again gives the same number of hexes.
  const auto [again, report2] = mesh(at("plate.obj"), "again", "--no-untangle");
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_EQ(report2["quads"], report["quads"]);
  EXPECT_EQ(report2["hexes"], report["hexes"]);
  EXPECT_EQ(report2["cad"], nullptr);
}

TEST_F(CadCli, AnAssemblyOfThreeBlocksIsMergedAndStructured) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const auto [r, report] = mesh(data("lblock_blocks.step"), "l", "--size 0.25");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("transfinite surface"));
  EXPECT_EQ(report["cad"]["volumes"], 3);
  // The faces the STEP file holds twice (one copy per block) are merged and left out.
  EXPECT_EQ(report["cad"]["faces"], 14);
  EXPECT_EQ(report["quads"], 224);
  EXPECT_EQ(report["hexes"], 192);
  EXPECT_EQ(report["valid"], true);
  EXPECT_EQ(report["quality"]["inverted"], 0);
  const auto check = run_cli("check " + at("l.vtk"));
  EXPECT_EQ(check.code, 0) << check.out;
}

TEST_F(CadCli, ATorusOfBlocksFromDataIsMeshedThroughItsHandle) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const auto [r, report] = mesh(data("torus_blocks.step"), "t", "--size 0.5");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("transfinite surface"));
  EXPECT_EQ(report["cad"]["volumes"], 20);
  EXPECT_EQ(report["cad"]["faces"], 16);
  EXPECT_EQ(report["valid"], true);
  EXPECT_EQ(report["quality"]["inverted"], 0);
  const auto check = run_cli("check " + at("t.vtk"));
  EXPECT_EQ(check.code, 0) << check.out;
}

TEST_F(CadCli, OneSolidTorusAndPlateWithAHoleAreSplitIntoBlocksAndMeshed) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  // One solid each (a toroidal face; planar faces and a cylindrical hole), not blocks.
  for (const char* name : {"torus_tilted.step", "plate_hole_tilted.step"}) {
    const auto [r, report] = mesh(data(name), name, "--size 0.25");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_THAT(r.out, HasSubstr("transfinite surface")) << name;
    EXPECT_EQ(report["cad"]["volumes"], 1) << name;
    EXPECT_EQ(report["cad"]["structured_faces"], report["cad"]["faces"]) << name;
    EXPECT_THAT(report["cad"]["split"].get<std::string>(),
                HasSubstr(std::string(name) == "torus_tilted.step" ? "a torus" : "half-planes"));
    EXPECT_EQ(report["valid"], true) << name;
    EXPECT_EQ(report["quality"]["inverted"], 0) << name;
    const auto check = run_cli("check " + at(std::string(name) + ".vtk"));
    EXPECT_EQ(check.code, 0) << check.out;
  }
}

TEST_F(CadCli, RecipeAndTriangleAlgorithmCanBeChosen) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const auto [r, report] =
      mesh(data("plate_hole_blocks.step"), "p",
           "--size 0.5 --cad-recipe triangle-split --cad-triangles 6 --no-untangle");
  // A triangle-split surface of a solid with a handle: no disc cut of it is loop-clean, so
  // it is refused (exit 2) with the reason, or woven; either way the recipe was the one asked.
  EXPECT_TRUE(r.code == 0 || r.code == 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("triangle-split surface"));
  EXPECT_THAT(r.out, HasSubstr("asked for"));
  const auto bad = run_cli("mesh " + data("plate_hole_blocks.step") + " -o " + at("q.vtk") +
                           " --cad-triangles 8");
  EXPECT_EQ(bad.code, 1) << bad.out;
  EXPECT_THAT(bad.out, HasSubstr("must be 1 (MeshAdapt), 5 (Delaunay) or 6 (Frontal-Delaunay)"));
}

TEST_F(CadCli, AnIgesBoxIsSewnIntoASolidAndMeshedStructured) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  // Both IGES extensions; the file holds six faces and no solid, as IGES files usually do.
  for (const char* name : {"box.igs", "box.iges"}) {
    stcweave::test::write_iges(at(name), stcweave::test::iges_box_faces(1, 2, 1));
    const auto [r, report] = mesh(at(name), name, "--size 0.25");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_THAT(r.out, HasSubstr("transfinite surface"));
    EXPECT_EQ(report["cad"]["format"], "iges");
    EXPECT_EQ(report["cad"]["faces"], 6);
    EXPECT_THAT(report["cad"]["warnings"].dump(), HasSubstr("sewn into 1 solid"));
    EXPECT_LT(report["cad"]["max_cad_distance"].get<double>(), 1e-7);
    EXPECT_EQ(report["hexes"], 4 * 8 * 4);  // the structured 4 x 8 x 4 box
    EXPECT_EQ(report["valid"], true);
    EXPECT_DOUBLE_EQ(report["quality"]["min_scaled_jacobian"].get<double>(), 1.0);
    const auto check = run_cli("check " + at(std::string(name) + ".vtk"));
    EXPECT_EQ(check.code, 0) << check.out;
  }
}

TEST_F(CadCli, AnIgesShellWithAFaceMissingOrGarbageExitsTwo) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  std::vector<stcweave::test::IgesFace> five = stcweave::test::iges_box_faces(1, 1, 1);
  five.pop_back();
  stcweave::test::write_iges(at("open.igs"), five);
  const auto [open, none] = mesh(at("open.igs"), "open");
  EXPECT_EQ(open.code, 2) << open.out;
  EXPECT_THAT(open.out, HasSubstr("not a closed solid: it holds 5 faces"));
  EXPECT_FALSE(fs::exists(at("open.vtk")));
  {
    std::ofstream out(at("junk.iges"));
    out << "this is not IGES\n";
  }
  const auto [junk, nothing] = mesh(at("junk.iges"), "junk");
  EXPECT_EQ(junk.code, 2) << junk.out;
  // OpenCASCADE's IGES reader reads nothing from it without an error: refused as empty.
  EXPECT_THAT(junk.out, HasSubstr("junk.iges: holds no shape at all"));
  EXPECT_FALSE(fs::exists(at("junk.vtk")));
}

TEST_F(CadCli, ACylinderIsSplitIntoAnOGridUnlessToldNot) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  // The cylinder's axis runs from (0.2, 0.1, 0) along (1, 2, 2) / 3: the blocks must follow it.
  const auto [r, report] =
      mesh(data("cylinder_tilted.step"), "c", "--size 0.25 --surface-out " + at("c.obj"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("transfinite surface"));
  EXPECT_THAT(r.out, HasSubstr("O-grid of 5 blocks"));
  EXPECT_THAT(report["cad"]["split"].get<std::string>(), HasSubstr("O-grid"));
  EXPECT_EQ(report["cad"]["faces"], 14);
  EXPECT_EQ(report["valid"], true);
  EXPECT_EQ(report["quality"]["inverted"], 0);
  // Every node of the surface woven lies on the file's cylinder.
  const stcweave::primal::MeshFile surface = stcweave::primal::read_mesh(at("c.obj"));
  const Eigen::Vector3d origin(0.2, 0.1, 0.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 2) / 3.0;
  double worst = 0.0;
  for (Eigen::Index i = 0; i < surface.points.rows(); ++i) {
    const Eigen::Vector3d d = surface.points.row(i).transpose() - origin;
    const double t = d.dot(axis);
    const Eigen::Vector3d local((d - t * axis).norm(), 0.0, t);
    worst = std::max(worst, stcweave::test::cylinder_distance(local, 0.5, 1.0));
  }
  EXPECT_GT(surface.points.rows(), 0);
  EXPECT_LT(worst, 1e-9);
  const auto [off, report_off] =
      mesh(data("cylinder_tilted.step"), "off", "--size 0.25 --no-cad-split --no-untangle");
  ASSERT_EQ(off.code, 0) << off.out;
  EXPECT_THAT(off.out, HasSubstr("triangle-split surface"));
  EXPECT_EQ(report_off["cad"]["split"], "");
  const auto bad = run_cli("mesh " + data("lblock.obj") + " -o " + at("x.vtk") + " --no-cad-split");
  EXPECT_EQ(bad.code, 1) << bad.out;
}

TEST_F(CadCli, SameCadInputGivesTheSameBytes) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  for (const char* name : {"a.vtk", "b.vtk"}) {
    const auto r = run_cli("mesh " + data("plate_slot.step") + " -o " + at(name) +
                           " --size 0.6 --no-untangle -q");
    ASSERT_EQ(r.code, 0) << r.out;
  }
  EXPECT_EQ(slurp(at("a.vtk")), slurp(at("b.vtk")));
}

TEST_F(CadCli, AnOpenShellExitsTwoWithTheReason) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const auto r = run_cli("mesh " + data("open_shell.step") + " -o " + at("x.vtk"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("not a closed solid"));
  EXPECT_FALSE(fs::exists(at("x.vtk")));
}

TEST_F(CadCli, GarbageStepExitsTwoWithGmshsReasonAndPrintsNothingElse) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  {
    std::ofstream out(at("junk.step"));
    out << "ISO-10303-21;\nnot really\n";
  }
  const auto r = run_cli("mesh " + at("junk.step") + " -o " + at("x.vtk"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("Gmsh cannot read it as step"));
  EXPECT_THAT(r.out, HasSubstr("OpenCASCADE"));
  // One line: OpenCASCADE's own printout went into the message, not to the terminal.
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

TEST_F(CadCli, TransfiniteRecipeOnACylindricalPartExitsTwo) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const auto r = run_cli("mesh " + data("plate_slot.step") + " -o " + at("x.vtk") +
                         " --cad-recipe transfinite");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("4 corners"));
}

TEST_F(CadCli, SizeOnAQuadSurfaceIsAUsageError) {
  const auto r = run_cli("mesh " + data("lblock.obj") + " -o " + at("x.vtk") + " --size 0.5");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_THAT(r.out, HasSubstr("CAD inputs only"));
}

TEST_F(CadCli, WithoutGmshCadInputExitsTwoWithTheMessage) {
  if (stcweave::primal::has_cad_support()) GTEST_SKIP() << "built with Gmsh";
  const auto r = run_cli("mesh " + data("plate_slot.step") + " -o " + at("x.vtk"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("built without"));
  EXPECT_THAT(r.out, HasSubstr("libgmsh-dev"));
}

}  // namespace

// A plate with two through-holes (genus 2, one solid, not split into blocks): its mixed
// surface has handles no disc cut weaves, so `auto` makes it triangle-split, and the tet
// interior meshes it without a cut and without weaving it at all.
TEST_F(CadCli, TwoHolePlateIsTriangleSplitAndGetsTheTetInteriorWithoutAWeave) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  expect_tets_without_a_weave("plate_two_holes.step", "genus 2", "genus 2");
}

// A box with a spherical cavity (one solid, two shells): its mixed surface would need an
// annulus cut, so `auto` makes it triangle-split, and the tet interior fills the space
// between the shells (Gmsh's volume with the cavity as a hole) without weaving.
TEST_F(CadCli, BoxWithACavityGetsTheTetInteriorBetweenItsShells) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  expect_tets_without_a_weave("box_cavity.step", "2 shells for 1 solid(s): a cavity", "2 shells");
}

// The blind hole (genus 0, triangle-split): the woven star cannot see past the hole's rim and
// kept inverted hexes (54 at 0.125); `--interior auto` keeps the split tetrahedral mesh
// (docs/tet-interior.md), a valid mesh with no inverted hex, certified by `check` against the
// surface it was made from.
TEST_F(CadCli, BlindHoleGetsTheTetInteriorWithNoInvertedHex) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const auto [r, report] =
      mesh(data("plate_blind_hole.step"), "bh", "--size 0.25 --surface-out " + at("bh.obj"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("triangle-split surface"));
  EXPECT_THAT(r.out, HasSubstr("interior   auto: tets kept"));
  EXPECT_EQ(report["interior"]["used"], "tets");
  EXPECT_EQ(report["interior"]["compared"], true);
  EXPECT_EQ(report["interior"]["triangles"].get<int>() * 3, report["quads"].get<int>());
  EXPECT_EQ(report["quality"]["inverted"], 0);
  EXPECT_GT(report["quality"]["min_scaled_jacobian"].get<double>(), 0.1);
  EXPECT_GT(report["seconds"]["other_interior"].get<double>(), 0.0);
  const auto check = run_cli("check " + at("bh.vtk") + " --boundary " + at("bh.obj"));
  EXPECT_EQ(check.code, 0) << check.out;
  // Asked for, the weave alone and the tets alone; tets on a surface that is not split
  // triangles is refused with exit code 2 and a reason.
  const auto [woven, woven_report] = mesh(at("bh.obj"), "bh_weave", "--interior weave");
  ASSERT_EQ(woven.code, 0) << woven.out;
  EXPECT_EQ(woven_report["interior"]["used"], "woven");
  const auto [tets, tets_report] = mesh(at("bh.obj"), "bh_tets", "--interior tets");
  ASSERT_EQ(tets.code, 0) << tets.out;
  EXPECT_EQ(tets_report["interior"]["used"], "tets");
  EXPECT_EQ(tets_report["hexes"], report["hexes"]);
  // The 3-2 flips (on by default) save four hexes each; off, the split of Gmsh's own tets.
  const int flips = tets_report["interior"]["flips"].get<int>();
  EXPECT_GT(flips, 0);
  EXPECT_THAT(tets.out, HasSubstr(std::to_string(flips) + " removed by 3-2 flips"));
  const auto [plain, plain_report] =
      mesh(at("bh.obj"), "bh_plain", "--interior tets --tet-flips off");
  ASSERT_EQ(plain.code, 0) << plain.out;
  EXPECT_EQ(plain_report["interior"]["flips"], 0);
  EXPECT_EQ(plain_report["hexes"].get<int>(), tets_report["hexes"].get<int>() + 4 * flips);
  const auto bad_floor = run_cli("mesh " + at("bh.obj") + " -o " + at("x.vtk") + " --tet-flips 2");
  EXPECT_EQ(bad_floor.code, 1) << bad_floor.out;
  EXPECT_THAT(bad_floor.out, HasSubstr("--tet-flips: must be off or a quality floor"));
  const auto refused =
      run_cli("mesh " + data("lblock.obj") + " -o " + at("l.vtk") + " --interior tets");
  EXPECT_EQ(refused.code, 2) << refused.out;
  EXPECT_THAT(refused.out, HasSubstr("triangle-split"));
  EXPECT_FALSE(fs::exists(at("l.vtk")));
  const auto unknown =
      run_cli("mesh " + data("lblock.obj") + " -o " + at("l.vtk") + " --interior tet");
  EXPECT_EQ(unknown.code, 1) << unknown.out;
}
