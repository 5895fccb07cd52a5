// The command line of issue 16: `mesh` writes cell data unless --no-cell-data, `mesh --html`
// and `view` write the page, and `view` refuses what it cannot show with exit code 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "stcweave/primal/mesh_data.hpp"
#include "stcweave/viewer/page.hpp"
#include "support/cli_run.hpp"

namespace stcweave {
namespace {

namespace fs = std::filesystem;

fs::path dir() {
  fs::path d = fs::temp_directory_path() / "stcweave_view_cli";
  fs::create_directories(d);
  return d;
}

const std::string kLBlock = std::string(STCWEAVE_SOURCE_DIR) + "/data/lblock.obj";

TEST(ViewCli, MeshWritesCellDataUnlessTold) {
  for (const char* ext : {".vtk", ".vtu", ".msh"}) {
    const fs::path with = dir() / ("with" + std::string(ext));
    const fs::path without = dir() / ("without" + std::string(ext));
    ASSERT_EQ(test::run_cli("mesh " + kLBlock + " -o " + with.string() + " -q").code, 0);
    ASSERT_EQ(
        test::run_cli("mesh " + kLBlock + " -o " + without.string() + " --no-cell-data -q").code,
        0);
    const primal::MeshData d = primal::read_mesh_data(with);
    for (const char* name :
         {"scaled_jacobian", "sheet_0", "sheet_1", "sheet_2", "chord_0", "chord_1", "chord_2",
          "layer", "creation_step", "shrink", "rule", "depth"}) {
      ASSERT_NE(d.cell(name), nullptr) << ext << " " << name;
      EXPECT_EQ(d.cell(name)->values.size(), 10U) << ext << " " << name;
    }
    ASSERT_NE(d.point("boundary"), nullptr);
    ASSERT_NE(d.point("valence"), nullptr);
    EXPECT_TRUE(primal::read_mesh_data(without).empty()) << ext;
  }
}

TEST(ViewCli, ViewRefusesWhatItCannotShow) {
  auto r = test::run_cli("view " + kLBlock + " -o " + (dir() / "x.html").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("no hexahedra"), std::string::npos) << r.out;
  r = test::run_cli("view " + (dir() / "missing.vtk").string() + " -o " +
                    (dir() / "x.html").string());
  EXPECT_EQ(r.code, 2) << r.out;
  const fs::path vtk = dir() / "lb.vtk";
  ASSERT_EQ(test::run_cli("mesh " + kLBlock + " -o " + vtk.string() + " -q").code, 0);
  const fs::path bad_trace = dir() / "bad.jsonl";
  {
    std::ofstream out(bad_trace);
    out << "not json\n";
  }
  r = test::run_cli("view " + vtk.string() + " -o " + (dir() / "x.html").string() + " --trace " +
                    bad_trace.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("bad.jsonl:1"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir() / "x.html"));
}

TEST(ViewCli, MeshHtmlAndViewGiveTheSameData) {
  if (!viewer::has_three_js()) GTEST_SKIP() << "built without three.js (libjs-three)";
  for (const char* ext : {".vtk", ".vtu", ".msh"}) {
    const fs::path mesh = dir() / ("same" + std::string(ext));
    const fs::path trace = dir() / "same.jsonl";
    const fs::path a = dir() / "a.html";
    const fs::path b = dir() / "b.html";
    ASSERT_EQ(test::run_cli("mesh " + kLBlock + " -o " + mesh.string() + " --trace " +
                            trace.string() + " --html " + a.string() + " -q")
                  .code,
              0);
    const auto r = test::run_cli("view " + mesh.string() + " -o " + b.string() + " --trace " +
                                 trace.string() + " --title lblock.obj");
    ASSERT_EQ(r.code, 0) << r.out;
    // Same mesh (the files hold the doubles exactly), same cell data read back, same trace:
    // the same page, byte for byte.
    EXPECT_EQ(test::slurp(a), test::slurp(b)) << ext;
  }
}

}  // namespace
}  // namespace stcweave
