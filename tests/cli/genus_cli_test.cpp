// Solids with handles through the command line: the odd-handle refusal (exit code 2, the
// cycle named), the handle report of `loops`, a ring meshed by cutting and gluing, a hollow
// cube meshed by an annulus cut, and a shell inside a cavity meshed as a solid of its own.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "stcweave/primal/io.hpp"
#include "support/cli_run.hpp"
#include "support/shapes.hpp"

namespace {

namespace fs = std::filesystem;

class GenusCli : public stcweave::test::CliTest {
 protected:
  GenusCli() : CliTest("stcweave_genus_cli_") {}
};

TEST_F(GenusCli, TriangularTorusIsRefusedWithExitCodeTwoNamingTheCycle) {
  const fs::path in = dir_ / "tri-torus.obj";
  stcweave::primal::write_surface(stcweave::test::torus_surface(3, 8, 3.0, 1.0), in);
  const auto r =
      stcweave::test::run_cli("mesh " + in.string() + " -o " + (dir_ / "o.vtk").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("no hex mesh with this boundary exists: the cycle n"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("has 3 edges"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir_ / "o.vtk"));

  const auto loops = stcweave::test::run_cli("loops " + in.string());
  EXPECT_EQ(loops.code, 0) << loops.out;
  EXPECT_NE(loops.out.find("handles: 1"), std::string::npos) << loops.out;
  EXPECT_NE(loops.out.find("3 edges (odd)"), std::string::npos) << loops.out;

  const auto json = stcweave::test::run_cli("loops --json " + in.string());
  ASSERT_EQ(json.code, 0) << json.out;
  const auto j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["handles"]["all_even"], false);
  ASSERT_EQ(j["handles"]["cycles"].size(), 1u);
  EXPECT_EQ(j["handles"]["cycles"][0]["length"], 3);
}

TEST_F(GenusCli, RingIsMeshedIntoEightHexes) {
  const fs::path in = dir_ / "ring.obj";
  stcweave::primal::write_surface(stcweave::test::voxel_surface(stcweave::test::ring_cells()), in);
  const fs::path out = dir_ / "ring.vtk";
  const fs::path report = dir_ / "ring.json";
  // (--no-untangle: the complex is what counts here; its thin shell keeps inverted hexes.)
  const auto r = stcweave::test::run_cli("mesh " + in.string() + " -o " + out.string() +
                                         " --no-untangle --report " + report.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(stcweave::test::slurp(report));
  EXPECT_EQ(j["hexes"], 8);
  EXPECT_EQ(j["valid"], true);
  const auto check =
      stcweave::test::run_cli("check " + out.string() + " --boundary " + in.string());
  EXPECT_EQ(check.code, 0) << check.out;
}

TEST_F(GenusCli, HollowCubeIsCutAlongAnAnnulusAndMeshed) {
  // 3 x 3 x 3 voxels minus the centre one: an outer and an inner shell (a cavity).
  std::vector<std::array<int, 3>> cells;
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        if (!(i == 1 && j == 1 && k == 1)) {
          cells.push_back({i, j, k});
        }
      }
    }
  }
  const fs::path in = dir_ / "hollow.obj";
  stcweave::primal::write_surface(stcweave::test::voxel_surface(cells), in);
  const fs::path out = dir_ / "hollow.vtk";
  const fs::path report = dir_ / "hollow.json";
  const auto r = stcweave::test::run_cli("mesh " + in.string() + " -o " + out.string() +
                                         " --report " + report.string() + " --fail-on-inverted");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(stcweave::test::slurp(report));
  EXPECT_EQ(j["valid"], true);
  EXPECT_EQ(j["solids"]["solids"], 1);
  EXPECT_EQ(j["solids"]["cuts"].size(), 1u);
  const auto check =
      stcweave::test::run_cli("check " + out.string() + " --boundary " + in.string());
  EXPECT_EQ(check.code, 0) << check.out;
}

TEST_F(GenusCli, ShellInsideACavityIsMeshed) {
  // A cube in the cavity of a hollow cube: nesting depth 2. The floating cube is a solid of
  // its own (one hex); the hollow cube's cavity is joined to its outer shell by a column.
  std::vector<std::array<int, 3>> cells;
  for (int k = 0; k < 5; ++k) {
    for (int j = 0; j < 5; ++j) {
      for (int i = 0; i < 5; ++i) {
        if (i == 0 || i == 4 || j == 0 || j == 4 || k == 0 || k == 4 ||
            (i == 2 && j == 2 && k == 2)) {
          cells.push_back({i, j, k});
        }
      }
    }
  }
  const fs::path in = dir_ / "nested.obj";
  const fs::path out = dir_ / "o.vtk";
  const fs::path report = dir_ / "r.json";
  stcweave::primal::write_surface(stcweave::test::voxel_surface(cells), in);
  // (--no-untangle: the complex is what counts here; its thin shell keeps inverted hexes.)
  const auto r = stcweave::test::run_cli("mesh " + in.string() + " -o " + out.string() +
                                         " --no-untangle --report " + report.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(stcweave::test::slurp(report));
  EXPECT_EQ(j["solids"]["solids"], 2);
  const auto check =
      stcweave::test::run_cli("check " + out.string() + " --boundary " + in.string());
  EXPECT_EQ(check.code, 0) << check.out;
}

}  // namespace
