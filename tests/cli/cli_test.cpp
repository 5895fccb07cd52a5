// The command-line program as a user meets it: exit codes, messages, outputs, determinism.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "support/cli_run.hpp"

namespace {

namespace fs = std::filesystem;

using stcweave::test::CliRun;
using stcweave::test::slurp;

CliRun run(const std::string& args) {
  return stcweave::test::run_cli(args);
}

class Cli : public stcweave::test::CliTest {
 protected:
  Cli() : CliTest("stcweave_cli_") {}
};

TEST_F(Cli, HelpExitsZeroAndNamesTheSubcommands) {
  const CliRun r = run("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* sub : {"mesh", "check", "loops", "sheets"})
    EXPECT_NE(r.out.find(sub), std::string::npos) << sub;
  EXPECT_EQ(run("mesh --help").code, 0);
}

TEST_F(Cli, UsageErrorsExitOne) {
  EXPECT_EQ(run("").code, 1);
  EXPECT_EQ(run("mesh").code, 1);
  EXPECT_EQ(run("frobnicate").code, 1);
}

TEST_F(Cli, MeshWritesAValidMeshAndAReport) {
  const fs::path out = dir_ / "bar.vtk", report = dir_ / "bar.json";
  const CliRun r =
      run("mesh " + data("bar_1x1x3.obj") + " -o " + out.string() + " --report " + report.string());
  ASSERT_EQ(r.code, 0) << r.out;
  ASSERT_TRUE(fs::exists(out));
  const auto j = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(j.at("hexes"), 3);
  EXPECT_EQ(j.at("valid"), true);
  for (const char* key : {"nodes", "interior_nodes", "sheets", "chords", "seconds"})
    EXPECT_TRUE(j.contains(key)) << key;
  const CliRun c = run("check " + out.string() + " --boundary " + data("bar_1x1x3.obj"));
  EXPECT_EQ(c.code, 0) << c.out;
}

TEST_F(Cli, MeshIsDeterministicByteForByte) {
  const fs::path a = dir_ / "a.vtk", b = dir_ / "b.vtk";
  ASSERT_EQ(run("mesh " + data("lblock.obj") + " -o " + a.string() + " -q").code, 0);
  ASSERT_EQ(run("mesh " + data("lblock.obj") + " -o " + b.string() + " -q").code, 0);
  EXPECT_EQ(slurp(a), slurp(b));
}

// `--threads` changes the work's threads, never the mesh; out of its range it is a usage error.
TEST_F(Cli, MeshDoesNotDependOnTheThreadCount) {
  const fs::path one = dir_ / "one.vtk", all = dir_ / "all.vtk";
  const std::string args = "mesh " + data("lblock.obj") + " --pillow always -q -o ";
  ASSERT_EQ(run(args + one.string() + " --threads 1").code, 0);
  ASSERT_EQ(run(args + all.string() + " --threads 0").code, 0);
  const std::string a = slurp(one);
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, slurp(all));
  EXPECT_EQ(run(args + (dir_ / "x.vtk").string() + " --threads -1").code, 1);
  EXPECT_EQ(run(args + (dir_ / "x.vtk").string() + " --threads 257").code, 1);
}

// The program tunes glibc's malloc unless GLIBC_TUNABLES names a malloc tunable
// (cli/allocator.cpp): the mesh must not depend on which allocator settings ran it.
TEST_F(Cli, MeshDoesNotDependOnTheAllocatorSettings) {
  const fs::path tuned = dir_ / "tuned.vtk", plain = dir_ / "plain.vtk";
  const std::string args = "mesh " + data("lblock.obj") + " --pillow always -q -o ";
  ASSERT_EQ(run(args + tuned.string()).code, 0);
  ASSERT_EQ(setenv("GLIBC_TUNABLES", "glibc.malloc.check=0", 1), 0);
  const CliRun r = run(args + plain.string());
  unsetenv("GLIBC_TUNABLES");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string a = slurp(tuned);
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, slurp(plain));
}

TEST_F(Cli, TraceHasSelectionAndRuleLines) {
  const fs::path out = dir_ / "l.vtk", trace = dir_ / "t.jsonl";
  ASSERT_EQ(
      run("mesh " + data("lblock.obj") + " -o " + out.string() + " -q --trace " + trace.string())
          .code,
      0);
  std::ifstream in(trace);
  std::string line;
  int selections = 0, rules = 0;
  while (std::getline(in, line)) {
    const auto j = nlohmann::json::parse(line);
    if (j.at("event") == "selection") {
      ++selections;
      EXPECT_TRUE(j.contains("candidates"));
      EXPECT_TRUE(j.at("chosen").contains("weight"));
    }
    if (j.at("event") == "rule") ++rules;
  }
  EXPECT_GT(selections, 0);
  EXPECT_GE(rules, 10);
}

TEST_F(Cli, MissingInputExitsTwoWithTheName) {
  const CliRun r = run("mesh " + (dir_ / "nope.obj").string() + " -o " + (dir_ / "x.vtk").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("nope.obj"), std::string::npos) << r.out;
}

TEST_F(Cli, OpenSurfaceExitsTwoAndWritesNothing) {
  const fs::path in = dir_ / "open.obj", out = dir_ / "open.vtk";
  std::ofstream(in) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  const CliRun r = run("mesh " + in.string() + " -o " + out.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("open"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(Cli, UnknownOutputExtensionExitsTwoBeforeWeaving) {
  const CliRun r = run("mesh " + data("bar_1x1x3.obj") + " -o " + (dir_ / "x.xyz").string());
  EXPECT_EQ(r.code, 2) << r.out;
}

TEST_F(Cli, AFileWithoutQuadsExitsTwo) {
  // Binary garbage named .obj and an OBJ with only `v` lines hold no quad: nothing to mesh.
  const fs::path garbage = dir_ / "garbage.obj", points = dir_ / "points.obj";
  {
    std::ofstream g(garbage, std::ios::binary);
    for (int i = 0; i < 4096; ++i) g.put(static_cast<char>((i * 7919 + 13) % 256));
  }
  std::ofstream(points) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 1\n";
  for (const fs::path& in : {garbage, points}) {
    SCOPED_TRACE(in.filename().string());
    const fs::path out = dir_ / "out.vtk";
    const CliRun r = run("mesh " + in.string() + " -o " + out.string());
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_THAT(r.out, ::testing::HasSubstr("no quads"));
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST_F(Cli, PillowModesAreAppliedAndReported) {
  const fs::path surface = dir_ / "box.obj", out = dir_ / "out.vtk", report = dir_ / "r.json";
  ASSERT_EQ(run("generate box 2 2 2 -q -o " + surface.string()).code, 0);
  const std::string mesh =
      "mesh " + surface.string() + " -o " + out.string() + " -q --report " + report.string();
  ASSERT_EQ(run(mesh).code, 0);
  nlohmann::json j = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(j.at("pillow").at("mode"), "auto");
  EXPECT_FALSE(j.at("pillow").at("applied").get<bool>()) << j.at("pillow");
  EXPECT_EQ(j.at("hexes"), 8);
  EXPECT_DOUBLE_EQ(j.at("quality").at("min_scaled_jacobian").get<double>(), 1.0);

  ASSERT_EQ(run(mesh + " --pillow always").code, 0);
  j = nlohmann::json::parse(slurp(report));
  EXPECT_TRUE(j.at("pillow").at("applied").get<bool>());
  EXPECT_EQ(j.at("pillow").at("hexes_added"), 24);
  EXPECT_EQ(j.at("hexes"), 32);
  EXPECT_TRUE(j.at("valid").get<bool>());
  EXPECT_EQ(j.at("quality").at("inverted"), 0);
  EXPECT_THAT(j.at("pillow").at("reason").get<std::string>(), ::testing::HasSubstr("always"));
  // The sheets the report counts are those of the final mesh: one more (the pillow).
  EXPECT_EQ(j.at("sheets"), 7);

  EXPECT_EQ(run(mesh + " --pillow sometimes").code, 1);
}

TEST_F(Cli, UnknownRuleSetExitsTwo) {
  const CliRun r =
      run("mesh " + data("bar_1x1x3.obj") + " -o " + (dir_ / "x.vtk").string() + " --rules magic");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("reliable"), std::string::npos) << r.out;
}

}  // namespace

namespace {

TEST_F(Cli, GenerateThenQualityOfAStructuredBox) {
  const fs::path hexes = dir_ / "box.vtk";
  ASSERT_EQ(run("generate box 2 3 4 --hexes -q -o " + hexes.string()).code, 0);
  const CliRun q = run("quality " + hexes.string() + " --json");
  ASSERT_EQ(q.code, 0) << q.out;
  const auto j = nlohmann::json::parse(q.out);
  EXPECT_EQ(j.at("hexes").get<int>(), 24) << q.out;
  EXPECT_NEAR(j.at("scaled_jacobian").at("min").get<double>(), 1.0, 1e-12) << q.out;
  EXPECT_EQ(run("quality " + (dir_ / "missing.vtk").string()).code, 2);
  EXPECT_EQ(run("quality").code, 1);
}

TEST_F(Cli, GeneratedSurfaceMeshesToItsBox) {
  const fs::path surface = dir_ / "box.obj", out = dir_ / "out.vtk", report = dir_ / "r.json";
  ASSERT_EQ(run("generate box 3 2 2 -q -o " + surface.string()).code, 0);
  const CliRun r =
      run("mesh " + surface.string() + " -o " + out.string() + " -q --report " + report.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(j.at("hexes").get<int>(), 12);
  EXPECT_EQ(j.at("rules").get<std::string>(), "extended");
  EXPECT_EQ(j.at("quality").at("inverted").get<int>(), 0);
}

/// Grades the spacing of an OBJ surface along x (x -> x^2 / 4, for x in [0, 4]): the
/// harmonic start of its interior is then no longer optimal, so untangling rounds run.
void grade_along_x(const fs::path& surface) {
  std::istringstream in(slurp(surface));
  std::ostringstream graded;
  for (std::string line; std::getline(in, line);) {
    double x = 0.0, y = 0.0, z = 0.0;
    if (std::sscanf(line.c_str(), "v %lf %lf %lf", &x, &y, &z) == 3)
      graded << "v " << x * x / 4.0 << ' ' << y << ' ' << z << '\n';
    else
      graded << line << '\n';
  }
  std::ofstream(surface) << graded.str();
}

TEST_F(Cli, NewtonStepsAreOptInAndReported) {
  const fs::path surface = dir_ / "box.obj", out = dir_ / "out.vtk", report = dir_ / "r.json";
  ASSERT_EQ(run("generate box 4 4 4 -q -o " + surface.string()).code, 0);
  grade_along_x(surface);
  const std::string mesh =
      "mesh " + surface.string() + " -o " + out.string() + " -q --report " + report.string();
  ASSERT_EQ(run(mesh).code, 0);
  EXPECT_EQ(nlohmann::json::parse(slurp(report)).at("position").at("newton_steps").get<int>(), 0);
  // --good-start 2: the graded box's harmonic start is valid and good, which would skip the
  // rounds (and their Newton steps) altogether.
  const CliRun r =
      run(mesh + " --position-newton-after 1 --position-newton-steps 2 --good-start 2");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(slurp(report));
  EXPECT_GT(j.at("position").at("newton_steps").get<int>(), 0);
  EXPECT_EQ(j.at("quality").at("inverted").get<int>(), 0);
  EXPECT_EQ(run(mesh + " --position-newton-steps 0").code, 1);  // out of range: usage error
}

TEST_F(Cli, ProgressNamesEachUntanglingRound) {
  // The graded box of NewtonStepsAreOptInAndReported: with --good-start 2 the untangling
  // rounds run, and --progress prints one line per round (as many as the report counts).
  const fs::path surface = dir_ / "box.obj", out = dir_ / "out.vtk", report = dir_ / "r.json";
  ASSERT_EQ(run("generate box 4 4 4 -q -o " + surface.string()).code, 0);
  grade_along_x(surface);
  const CliRun r = run("mesh " + surface.string() + " -o " + out.string() + " --report " +
                       report.string() + " --good-start 2 --progress");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto rounds = nlohmann::json::parse(slurp(report)).at("position").at("rounds").get<int>();
  ASSERT_GT(rounds, 0);
  int lines = 0;
  for (std::size_t at = r.out.find("stcweave: positioning: untangle round ");
       at != std::string::npos; at = r.out.find("stcweave: positioning: untangle round ", at + 1))
    ++lines;
  EXPECT_EQ(lines, rounds) << r.out;
  EXPECT_NE(r.out.find("round 1 of at most 100: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" L-BFGS iterations, eps "), std::string::npos) << r.out;
  // Without --progress (and not on a terminal) nothing of it is printed.
  const CliRun q = run("mesh " + surface.string() + " -o " + out.string() + " --good-start 2");
  ASSERT_EQ(q.code, 0) << q.out;
  EXPECT_EQ(q.out.find("positioning:"), std::string::npos) << q.out;
}

TEST_F(Cli, FailOnInvertedExitsFourAndWritesNoMesh) {
  // The 2x2x2 box with the centre of its top face pushed through the bottom: the interior
  // node cannot be above the bottom centre and below the top one, so hexes stay inverted.
  const fs::path surface = dir_ / "fold.obj", out = dir_ / "out.vtk", report = dir_ / "r.json";
  ASSERT_EQ(run("generate box 2 2 2 -q -o " + surface.string()).code, 0);
  {
    std::string text = slurp(surface);
    const std::string top_centre = "\nv 1 1 2\n";
    const std::size_t at = text.find(top_centre);
    ASSERT_NE(at, std::string::npos);
    text.replace(at, top_centre.size(), "\nv 1 1 -0.5\n");
    std::ofstream(surface) << text;
  }
  const std::string mesh = "mesh " + surface.string() + " -o " + out.string() +
                           " --rules reliable -q --report " + report.string();
  const CliRun plain = run(mesh);
  ASSERT_EQ(plain.code, 0) << plain.out;  // without the flag: written, exit 0, ...
  // ... but never silently: stderr says how many hexes are inverted.
  EXPECT_THAT(plain.out, ::testing::HasSubstr("warning:"));
  EXPECT_THAT(plain.out, ::testing::HasSubstr("still inverted after untangling"));
  EXPECT_TRUE(fs::exists(out));
  EXPECT_GT(nlohmann::json::parse(slurp(report)).at("quality").at("inverted").get<int>(), 0);
  fs::remove(out);

  const CliRun r = run(mesh + " --fail-on-inverted");
  EXPECT_EQ(r.code, 4) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("still inverted after untangling"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("--keep-invalid"));
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(nlohmann::json::parse(slurp(report)).at("output").is_null());

  const CliRun kept = run(mesh + " --fail-on-inverted --keep-invalid");
  EXPECT_EQ(kept.code, 4) << kept.out;
  EXPECT_TRUE(fs::exists(out));

  // A mesh with no inverted hex passes the flag.
  ASSERT_EQ(run("generate box 2 2 2 -q -o " + surface.string()).code, 0);
  EXPECT_EQ(run(mesh + " --fail-on-inverted").code, 0);
}

TEST_F(Cli, WeavingOptionsAreCheckedAndRecorded) {
  const fs::path out = dir_ / "l.vtk", report = dir_ / "r.json";
  const CliRun bad =
      run("mesh " + data("lblock.obj") + " -o " + out.string() + " --sharp 200 --little-sharp 170");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("out of order"), std::string::npos) << bad.out;
  EXPECT_FALSE(fs::exists(out));
  const CliRun start = run("mesh " + data("lblock.obj") + " -o " + out.string() + " --start x");
  EXPECT_EQ(start.code, 2) << start.out;
  EXPECT_NE(start.out.find("--start must be layers or harmonic"), std::string::npos) << start.out;
  EXPECT_FALSE(fs::exists(out));
  const CliRun ok = run("mesh " + data("lblock.obj") + " -o " + out.string() +
                        " -q --no-depth-filter --flat 185 --report " + report.string());
  ASSERT_EQ(ok.code, 0) << ok.out;
  const auto j = nlohmann::json::parse(slurp(report));
  EXPECT_FALSE(j.at("weave_options").at("depth_filter").get<bool>());
  EXPECT_EQ(j.at("weave_options").at("flat").get<double>(), 185.0);
  EXPECT_EQ(j.at("hexes").get<int>(), 10);
  // The depth filter after a block (the default) is recorded, and so is its retry (none here).
  EXPECT_TRUE(j.at("weave_options").at("depth_filter_after_block").get<bool>());
  EXPECT_TRUE(j.at("depth_filter_retry").is_null());
  // The report of lblock meshed with `flags`.
  const auto report_with = [&](const std::string& flags) {
    const CliRun r = run("mesh " + data("lblock.obj") + " -o " + out.string() + " -q " + flags +
                         " --report " + report.string());
    EXPECT_EQ(r.code, 0) << flags << ": " << r.out;
    return nlohmann::json::parse(slurp(report));
  };
  EXPECT_FALSE(report_with("--depth-filter-always")
                   .at("weave_options")
                   .at("depth_filter_after_block")
                   .get<bool>());
  // The retry undoing the shrinks that leave a seam blocked: on by default (not needed here:
  // no retry counted), off with --keep-seam-blocking-shrinks.
  EXPECT_TRUE(j.at("weave_options").at("undo_seam_blocking_on_block").get<bool>());
  EXPECT_FALSE(j.at("weave_options").at("undo_seam_blocking_shrinks").get<bool>());
  EXPECT_EQ(j.at("weave").at("seam_undo_retries").get<int>(), 0);
  // The last ways after it (the fill, the reliable rules from the start): on, not needed here.
  EXPECT_EQ(j.at("weave_options").at("fill_up_to").get<int>(), 200);
  EXPECT_TRUE(j.at("weave_options").at("reliable_from_start").get<bool>());
  EXPECT_EQ(j.at("weave").at("fill_hexes").get<int>(), 0);
  EXPECT_EQ(j.at("weave").at("reliable_from_start").get<int>(), 0);
  const auto k = report_with("--keep-seam-blocking-shrinks");
  EXPECT_FALSE(k.at("weave_options").at("undo_seam_blocking_on_block").get<bool>());
  EXPECT_EQ(k.at("hexes").get<int>(), 10);
  // --block-recovery off asks for the first block alone: no retry either.
  EXPECT_FALSE(report_with("--block-recovery off")
                   .at("weave_options")
                   .at("undo_seam_blocking_on_block")
                   .get<bool>());
}

TEST_F(Cli, TraceNamesTheDecidingFilterAndSurvivesAFailedWeave) {
  const fs::path out = dir_ / "l.vtk", trace = dir_ / "t.jsonl";
  ASSERT_EQ(
      run("mesh " + data("lblock.obj") + " -o " + out.string() + " -q --trace " + trace.string())
          .code,
      0);
  std::istringstream lines(slurp(trace));
  std::string line;
  std::size_t selections = 0;
  while (std::getline(lines, line)) {
    const auto e = nlohmann::json::parse(line);
    if (e.at("event") != "selection") continue;
    ++selections;
    EXPECT_FALSE(e.at("decided_by").get<std::string>().empty()) << line;
    EXPECT_FALSE(e.at("filters").empty()) << line;
  }
  EXPECT_GT(selections, 0u);
  // A rule budget too small to finish: exit 3, no mesh, but the trace of what was done.
  fs::remove(out);
  const CliRun r = run("mesh " + data("lblock.obj") + " -o " + out.string() +
                       " --max-rules 3 --trace " + trace.string());
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_NE(slurp(trace).find("\"event\":\"rule\""), std::string::npos);
}

}  // namespace
