// `stcweave mesh` on CAD input (issue 15): the recipe line, the report's "cad" record,
// --surface-out, exit code 2 for what is not a closed solid, the build without Gmsh.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "stcweave/primal/cad.hpp"
#include "support/cli_run.hpp"

namespace {

namespace fs = std::filesystem;
using stcweave::test::run_cli;
using stcweave::test::slurp;
using ::testing::HasSubstr;

class CadCli : public stcweave::test::CliTest {
 protected:
  CadCli() : CliTest("stcweave_cad_cli_") {}
  [[nodiscard]] std::string at(const std::string& name) const { return (dir_ / name).string(); }
};

#define SKIP_WITHOUT_GMSH()                 \
  if (!stcweave::primal::has_cad_support()) \
  GTEST_SKIP() << "built without Gmsh (STCWEAVE_WITH_GMSH=OFF)"

TEST_F(CadCli, PlateWithASlotIsMeshedAndItsSurfaceWritten) {
  SKIP_WITHOUT_GMSH();
  const auto r = run_cli("mesh " + data("plate_slot.step") + " -o " + at("plate.vtk") +
                         " --size 0.5 --no-untangle --surface-out " + at("plate.obj") +
                         " --report " + at("plate.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("triangle-split surface"));
  EXPECT_THAT(r.out, HasSubstr("valid      yes"));
  EXPECT_THAT(r.out, ::testing::Not(HasSubstr("Info")));  // Gmsh stays quiet
  const nlohmann::json report = nlohmann::json::parse(slurp(at("plate.json")));
  EXPECT_EQ(report["cad"]["recipe"], "triangle-split");
  EXPECT_EQ(report["cad"]["quads"], report["quads"]);
  EXPECT_LT(report["cad"]["max_cad_distance"].get<double>(), 1e-7);
  // The surface written is the one woven: meshing it again gives the same number of hexes.
  const auto again = run_cli("mesh " + at("plate.obj") + " -o " + at("again.vtk") +
                             " --no-untangle --report " + at("again.json"));
  ASSERT_EQ(again.code, 0) << again.out;
  const nlohmann::json report2 = nlohmann::json::parse(slurp(at("again.json")));
  EXPECT_EQ(report2["quads"], report["quads"]);
  EXPECT_EQ(report2["hexes"], report["hexes"]);
  EXPECT_EQ(report2["cad"], nullptr);
}

TEST_F(CadCli, AnAssemblyOfThreeBlocksIsMergedAndStructured) {
  SKIP_WITHOUT_GMSH();
  const auto r = run_cli("mesh " + data("lblock_blocks.step") + " -o " + at("l.vtk") +
                         " --size 0.25 --report " + at("l.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("transfinite surface"));
  const nlohmann::json report = nlohmann::json::parse(slurp(at("l.json")));
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

TEST_F(CadCli, SameCadInputGivesTheSameBytes) {
  SKIP_WITHOUT_GMSH();
  for (const char* name : {"a.vtk", "b.vtk"}) {
    const auto r = run_cli("mesh " + data("plate_slot.step") + " -o " + at(name) +
                           " --size 0.6 --no-untangle -q");
    ASSERT_EQ(r.code, 0) << r.out;
  }
  EXPECT_EQ(slurp(at("a.vtk")), slurp(at("b.vtk")));
}

TEST_F(CadCli, AnOpenShellExitsTwoWithTheReason) {
  SKIP_WITHOUT_GMSH();
  const auto r = run_cli("mesh " + data("open_shell.step") + " -o " + at("x.vtk"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("not a closed solid"));
  EXPECT_FALSE(fs::exists(at("x.vtk")));
}

TEST_F(CadCli, GarbageStepExitsTwoWithGmshsReasonAndPrintsNothingElse) {
  SKIP_WITHOUT_GMSH();
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
  SKIP_WITHOUT_GMSH();
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
