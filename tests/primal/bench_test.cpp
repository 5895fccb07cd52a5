// The pure half of the corpus runner: manifests, rows, their CSV / Markdown / JSON forms and
// the fitted scaling exponent. No process is started here (tests/cli/bench_cli_test.cpp
// runs the real thing).
#include "stcweave/primal/bench.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "stcweave/primal/generate.hpp"
#include "stcweave/stc/errors.hpp"

namespace {

using namespace stcweave;
using primal::BenchRow;
using primal::RunStatus;
using ::testing::HasSubstr;
using ::testing::Not;
namespace fs = std::filesystem;

primal::Manifest parse(const std::string& text, const fs::path& path = "/corpus/bench/m.txt") {
  std::istringstream in(text);
  return primal::parse_manifest(in, path);
}

std::string error_of(const std::string& text) {
  try {
    (void)parse(text);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "no error";
}

// ---- manifests ----

TEST(Manifest, CommentsBlankLinesAndReferencesAreRead) {
  const auto m = parse(
      "# the corpus\n"
      "\n"
      "  ../data/a.obj   # trailing comment\n"
      "../data/sub/b.mesh\t../data/sub/b.mesh\n"
      "   # only a comment\n"
      "/abs/c.off ref/c.vtk\r\n");
  ASSERT_EQ(m.entries.size(), 3U);
  EXPECT_EQ(m.entries[0].input, fs::path("/corpus/data/a.obj"));
  EXPECT_FALSE(m.entries[0].reference);
  EXPECT_EQ(m.entries[0].line, 3U);
  EXPECT_EQ(m.entries[1].input, fs::path("/corpus/data/sub/b.mesh"));
  ASSERT_TRUE(m.entries[1].reference);
  EXPECT_EQ(*m.entries[1].reference, fs::path("/corpus/data/sub/b.mesh"));
  EXPECT_EQ(m.entries[2].input, fs::path("/abs/c.off"));
  EXPECT_EQ(*m.entries[2].reference, fs::path("/corpus/bench/ref/c.vtk"));
  EXPECT_EQ(m.entries[2].line, 6U);
}

TEST(Manifest, NamesDropTheFoldersEveryInputShares) {
  const auto m = parse(
      "../../shared/data/gmsh/cube.obj\n"
      "../../shared/data/real/mfem/fichera.mesh\n");
  ASSERT_EQ(m.entries.size(), 2U);
  EXPECT_EQ(m.entries[0].name, "gmsh/cube.obj");
  EXPECT_EQ(m.entries[1].name, "real/mfem/fichera.mesh");
  EXPECT_EQ(m.entries[1].file_stem, "real_mfem_fichera.mesh");
  // A single input keeps its file name.
  EXPECT_EQ(parse("x/y/z.obj\n").entries[0].name, "z.obj");
}

TEST(Manifest, FileStemsStayUniqueWhenNamesCollideAfterSanitising) {
  const auto m = parse("a/b.obj\na_b.obj\n");
  ASSERT_EQ(m.entries.size(), 2U);
  EXPECT_EQ(m.entries[0].name, "a/b.obj");
  EXPECT_EQ(m.entries[1].name, "a_b.obj");
  EXPECT_EQ(m.entries[0].file_stem, "a_b.obj");
  EXPECT_EQ(m.entries[1].file_stem, "a_b.obj-line2");
}

TEST(Manifest, GeneratedInputsAreNamedByTheirSpec) {
  const auto m = parse(
      "generate:box:4x5x6\n"
      "generate:bar:l  ../data/l.vtk\n"
      "files/one.obj\n");
  ASSERT_EQ(m.entries.size(), 3U);
  ASSERT_TRUE(m.entries[0].generated);
  EXPECT_EQ(m.entries[0].generated->a, 4);
  EXPECT_EQ(m.entries[0].generated->c, 6);
  EXPECT_TRUE(m.entries[0].input.empty());
  EXPECT_EQ(m.entries[0].name, "box:4x5x6");
  EXPECT_EQ(m.entries[0].file_stem, "box_4x5x6");
  EXPECT_EQ(m.entries[1].name, "bar:l");
  EXPECT_EQ(*m.entries[1].reference, fs::path("/corpus/data/l.vtk"));
  EXPECT_EQ(m.entries[2].name, "one.obj");
  EXPECT_FALSE(m.entries[2].generated);
}

TEST(Manifest, ErrorsNameTheLineAndSayWhatToDo) {
  EXPECT_THAT(error_of("a.obj\nb.obj c.vtk d.vtk\n"), HasSubstr("m.txt:2"));
  EXPECT_THAT(error_of("a.obj\nb.obj c.vtk d.vtk\n"), HasSubstr("3 fields"));
  EXPECT_THAT(error_of("a.obj\n./a.obj\n"), HasSubstr("already listed on line 1"));
  EXPECT_THAT(error_of("# nothing\n\n"), HasSubstr("lists no input"));
  EXPECT_THAT(error_of(""), HasSubstr("lists no input"));
  EXPECT_THAT(error_of("generate:box:4x4\n"), HasSubstr("m.txt:1"));
  EXPECT_THAT(error_of("generate:box:0x4x4\n"), HasSubstr("between 1 and"));
  EXPECT_THAT(error_of("generate:cone:3\n"), HasSubstr("box:AxBxC"));
  EXPECT_THAT(error_of("generate:bar:zigzag\n"), HasSubstr("straight"));
  EXPECT_THAT(error_of("generate:box:2x2x2\ngenerate:box:2x2x2\n"), HasSubstr("already listed"));
  EXPECT_THAT(error_of("a.obj generate:box:2x2x2\n"), HasSubstr("reference"));
}

TEST(Manifest, MissingFileIsAnIoErrorNamingIt) {
  try {
    (void)primal::read_manifest("/nonexistent/stcweave/manifest.txt");
    FAIL() << "no exception";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent/stcweave/manifest.txt"));
  }
}

TEST(Manifest, ReadFromAFileAnchorsRelativePathsAtItsFolder) {
  const fs::path dir = fs::temp_directory_path() / "stcweave_bench_manifest_test";
  fs::create_directories(dir / "sub");
  {
    std::ofstream out(dir / "sub" / "list.manifest");
    out << "../in.obj ref.vtk\n";
  }
  const auto m = primal::read_manifest(dir / "sub" / "list.manifest");
  fs::remove_all(dir);
  ASSERT_EQ(m.entries.size(), 1U);
  EXPECT_EQ(m.entries[0].input, (dir / "in.obj").lexically_normal());
  EXPECT_EQ(*m.entries[0].reference, (dir / "sub" / "ref.vtk").lexically_normal());
}

TEST(RulesList, SplitsTrimsAndRefusesEmptyOrRepeatedNames) {
  EXPECT_EQ(primal::parse_rules_list("reliable"), std::vector<std::string>{"reliable"});
  EXPECT_EQ(primal::parse_rules_list(" reliable , extended"),
            (std::vector<std::string>{"reliable", "extended"}));
  EXPECT_THROW((void)primal::parse_rules_list(""), InvalidInput);
  EXPECT_THROW((void)primal::parse_rules_list("reliable,"), InvalidInput);
  EXPECT_THROW((void)primal::parse_rules_list("reliable,reliable"), InvalidInput);
}

// ---- generated shapes ----

TEST(ShapeSpec, ParsesPrintsAndBuilds) {
  const auto box = primal::parse_shape_spec("box:2x3x4");
  EXPECT_EQ(primal::to_string(box), "box:2x3x4");
  EXPECT_EQ(primal::shape_hexes(box).complex.hexes.size(), 24U);
  const auto bar = primal::parse_shape_spec("bar:u");
  EXPECT_EQ(primal::to_string(bar), "bar:u");
  EXPECT_EQ(primal::shape_hexes(bar).complex.hexes.size(), 3U);
  for (const char* bad : {"box:", "box:1x1", "box:1x1x1x1", "box:axbxc", "box:-1x2x2",
                          "bar:", "sphere:3", "box:1x1x99999"})
    EXPECT_THROW((void)primal::parse_shape_spec(bad), InvalidInput) << bad;
}

// ---- rows ----

BenchRow ok_row(const std::string& input, const std::string& rules, std::size_t hexes,
                double weave_seconds) {
  BenchRow r;
  r.input = input;
  r.rules = rules;
  r.status = RunStatus::Ok;
  r.quads = 6;
  r.genus = 0;
  r.loops = 3;
  r.hexes = hexes;
  r.valid = true;
  r.inverted = 0;
  r.min_scaled_jacobian = 0.5;
  r.mean_scaled_jacobian = 0.75;
  r.seconds = {{"weave", weave_seconds}, {"total", 2 * weave_seconds}};
  r.wall_seconds = 3 * weave_seconds;
  r.peak_memory_mb = 12.0;
  return r;
}

TEST(Report, KeysAreReadInStageOrderAndUnknownKeysIgnored) {
  const auto report = nlohmann::json::parse(R"({
    "hexes": 27, "valid": true, "future_key": {"x": 1},
    "quality": {"inverted": 2, "min_scaled_jacobian": -0.25, "mean_scaled_jacobian": 0.5},
    "seconds": {"total": 1.5, "write": 0.1, "weave": 0.7, "diagnose": 0.01, "zeta": 0.2,
                "position": 0.3}
  })");
  BenchRow row;
  primal::apply_report(report, row);
  EXPECT_EQ(row.hexes, 27U);
  EXPECT_EQ(row.valid, true);
  EXPECT_EQ(row.inverted, 2U);
  EXPECT_DOUBLE_EQ(*row.min_scaled_jacobian, -0.25);
  EXPECT_DOUBLE_EQ(*row.mean_scaled_jacobian, 0.5);
  std::vector<std::string> stages;
  for (const auto& [s, v] : row.seconds) stages.push_back(s);
  EXPECT_EQ(stages,
            (std::vector<std::string>{"diagnose", "weave", "position", "write", "zeta", "total"}));
  EXPECT_DOUBLE_EQ(*row.stage_seconds("weave"), 0.7);
  EXPECT_FALSE(row.stage_seconds("recover"));
}

TEST(Report, ReasonsLoseTheCategoryPrefixAndNameTheInputByItsName) {
  EXPECT_EQ(primal::tidy_reason("invalid input: component 0 of ../d/torus.obj has genus 1",
                                "../d/torus.obj", "gmsh/torus.obj"),
            "component 0 of gmsh/torus.obj has genus 1");
  EXPECT_EQ(primal::tidy_reason("failure: weave blocked", "x", "x"), "weave blocked");
  EXPECT_EQ(primal::tidy_reason("internal error: std::bad_alloc", "a", "b"),
            "internal error: std::bad_alloc");
  EXPECT_EQ(primal::tidy_reason("a.obj vs a.obj", "a.obj", "sub/a.obj"), "sub/a.obj vs sub/a.obj");
}

TEST(Report, MissingOrMistypedKeysLeaveFieldsNull) {
  BenchRow row;
  primal::apply_report(nlohmann::json::parse(R"({"hexes": "many", "quality": 3})"), row);
  primal::apply_report(nlohmann::json::parse("[1, 2]"), row);
  EXPECT_FALSE(row.hexes);
  EXPECT_FALSE(row.valid);
  EXPECT_FALSE(row.inverted);
  EXPECT_TRUE(row.seconds.empty());
}

TEST(Probe, RoundTripsThroughJson) {
  BenchRow a;
  a.quads = 150;
  a.genus = 1;
  a.loops = 15;
  a.self_intersecting_loops = 0;
  a.reference_hexes = 125;
  a.reference_min_scaled_jacobian = 0.25;
  a.reference_mean_scaled_jacobian = 0.875;
  BenchRow b;
  primal::apply_probe(nlohmann::json::parse(primal::probe_to_json(a).dump()), b);
  EXPECT_EQ(b.quads, 150U);
  EXPECT_EQ(b.genus, 1);
  EXPECT_EQ(b.loops, 15U);
  EXPECT_EQ(b.self_intersecting_loops, 0U);
  EXPECT_EQ(b.reference_hexes, 125U);
  EXPECT_DOUBLE_EQ(*b.reference_min_scaled_jacobian, 0.25);
  EXPECT_DOUBLE_EQ(*b.reference_mean_scaled_jacobian, 0.875);
  EXPECT_TRUE(b.reference_error.empty());

  BenchRow c;  // nothing known, and a reference that could not be read
  c.reference_error = "ref.vtk has no hexahedra";
  BenchRow d;
  primal::apply_probe(primal::probe_to_json(c), d);
  EXPECT_FALSE(d.quads);
  EXPECT_FALSE(d.genus);
  EXPECT_FALSE(d.reference_hexes);
  EXPECT_EQ(d.reference_error, "ref.vtk has no hexahedra");
}

// ---- CSV ----

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

TEST(Csv, HeaderHasEveryStageAndCellsAreQuoted) {
  BenchRow ok = ok_row("gmsh/cube.obj", "reliable", 125, 0.5);
  BenchRow bad;
  bad.input = "broken, \"quoted\".obj";
  bad.rules = "extended";
  bad.status = RunStatus::Rejected;
  bad.reason = "line 3: bad vertex, see \"v\"";
  bad.seconds = {{"position", 0.25}};
  const auto lines = lines_of(primal::format_csv({ok, bad}));
  ASSERT_EQ(lines.size(), 3U);
  EXPECT_EQ(lines[0],
            "input,rules,status,reason,quads,genus,loops,self_intersecting_loops,hexes,valid,"
            "inverted,min_scaled_jacobian,mean_scaled_jacobian,seconds_weave,seconds_position,"
            "seconds_total,wall_seconds,peak_memory_mb,reference_hexes,"
            "reference_min_scaled_jacobian,reference_mean_scaled_jacobian,reference_error");
  EXPECT_EQ(lines[1], "gmsh/cube.obj,reliable,ok,,6,0,3,,125,true,0,0.5,0.75,0.5,,1,1.5,12,,,,");
  EXPECT_EQ(lines[2],
            "\"broken, \"\"quoted\"\".obj\",extended,rejected,\"line 3: bad vertex, see "
            "\"\"v\"\"\",,,,,,,,,,,0.25,,0,,,,,");
}

// ---- Markdown ----

TEST(Markdown, TableHasOneLinePerRowAndEscapesPipes) {
  BenchRow bad;
  bad.input = "a|b.obj";
  bad.rules = "reliable";
  bad.status = RunStatus::Timeout;
  bad.reason = std::string(200, 'x');
  const auto lines =
      lines_of(primal::format_markdown_table({ok_row("c.obj", "reliable", 8, 1), bad}));
  ASSERT_EQ(lines.size(), 4U);
  EXPECT_THAT(lines[0], HasSubstr("| input | rules | quads |"));
  EXPECT_THAT(lines[2], HasSubstr("| c.obj | reliable | 6 | 0 | 3 | ok | 8 | 0 | 0.500 | 0.750 |"));
  EXPECT_THAT(lines[3], HasSubstr("a\\|b.obj"));
  EXPECT_THAT(lines[3], HasSubstr("timeout: xxx"));
  EXPECT_THAT(lines[3], HasSubstr("..."));
  EXPECT_EQ(lines[3].find(std::string(primal::kMarkdownReasonLength, 'x')), std::string::npos);
  // Every line has the same number of cells as the header.
  const auto cells = [](const std::string& l) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < l.size(); ++i) n += l[i] == '|' && (i == 0 || l[i - 1] != '\\');
    return n;
  };
  for (const auto& l : lines) EXPECT_EQ(cells(l), cells(lines[0])) << l;
}

TEST(Markdown, PageHasSummarySideBySideStagesAndScaling) {
  primal::BenchResults results;
  results.manifest = "bench/generated.manifest";
  results.rules = {"reliable", "extended"};
  results.jobs = 2;
  for (const std::size_t k : {10, 20, 40}) {
    const std::string name = "box:" + std::to_string(k);
    const double hexes = static_cast<double>(k * k * k);
    results.rows.push_back(ok_row(name, "reliable", k * k * k, 1e-4 * hexes));
    BenchRow e = ok_row(name, "extended", k * k * k, 1e-4 * hexes * hexes);
    if (k == 40) {
      e.status = RunStatus::Crashed;
      e.reason = "killed by signal 11 (Segmentation fault)";
    }
    results.rows.push_back(e);
  }
  primal::fit_scaling(results);
  const std::string md = primal::format_markdown(results);
  EXPECT_THAT(md, HasSubstr("# stcweave bench: bench/generated.manifest"));
  EXPECT_THAT(md, HasSubstr(" runs (2 jobs at a time, "));
  EXPECT_THAT(md, Not(HasSubstr("each,")));  // threads per run not said
  results.threads = 1;
  EXPECT_THAT(primal::format_markdown(results), HasSubstr("(2 jobs at a time, 1 thread each, "));
  EXPECT_THAT(md, HasSubstr("| reliable | 3 | 3 | 3 | 3 | 0 | 0 | 0 | 0 | 0 | 0 |"));
  EXPECT_THAT(md, HasSubstr("| extended | 3 | 2 | 2 | 2 | 0 | 0 | 0 | 1 | 0 | 0 |"));
  EXPECT_THAT(md, HasSubstr("## Side by side"));
  EXPECT_THAT(md, HasSubstr("| box:40 | 6 | 0 | 3 | ok | 64000 |"));
  EXPECT_THAT(md, HasSubstr("crashed: killed by signal 11"));
  EXPECT_THAT(md, HasSubstr("## Seconds per stage"));
  EXPECT_THAT(md, HasSubstr("reliable, weave seconds: ~ 0.0001 x hexes^1.00 (3 runs"));
  EXPECT_THAT(md, HasSubstr("extended, weave seconds: no exponent"));
  // One rule set: no side-by-side table.
  results.rules = {"reliable"};
  EXPECT_EQ(primal::format_markdown(results).find("Side by side"), std::string::npos);
}

// ---- scaling ----

TEST(Scaling, FitRecoversAnExactPowerLaw) {
  const std::vector<double> x = {10, 100, 1000, 10000};
  std::vector<double> y;
  for (double v : x) y.push_back(3.0 * std::pow(v, 1.5));
  const auto fit = primal::fit_power_law(x, y);
  EXPECT_NEAR(fit.exponent, 1.5, 1e-12);
  EXPECT_NEAR(fit.coefficient, 3.0, 1e-9);
  EXPECT_NEAR(fit.r_squared, 1.0, 1e-12);
  EXPECT_EQ(fit.points, 4U);
}

TEST(Scaling, NoisyDataGivesAnExponentNearTheTruthAndRSquaredBelowOne) {
  const std::vector<double> x = {64, 512, 4096, 32768};
  const std::vector<double> noise = {1.1, 0.9, 1.05, 0.95};
  std::vector<double> y;
  for (std::size_t i = 0; i < x.size(); ++i) y.push_back(2e-6 * x[i] * x[i] * noise[i]);
  const auto fit = primal::fit_power_law(x, y);
  EXPECT_NEAR(fit.exponent, 2.0, 0.05);
  EXPECT_LT(fit.r_squared, 1.0);
  EXPECT_GT(fit.r_squared, 0.99);
}

TEST(Scaling, BadInputsThrow) {
  EXPECT_THROW((void)primal::fit_power_law({1, 2}, {1}), InvalidInput);
  EXPECT_THROW((void)primal::fit_power_law({1}, {1}), InvalidInput);
  EXPECT_THROW((void)primal::fit_power_law({1, 0}, {1, 1}), InvalidInput);
  EXPECT_THROW((void)primal::fit_power_law({1, 2}, {1, -1}), InvalidInput);
  EXPECT_THROW((void)primal::fit_power_law({1, 2}, {1, NAN}), InvalidInput);
  EXPECT_THROW((void)primal::fit_power_law({5, 5, 5}, {1, 2, 3}), InvalidInput);
}

TEST(Scaling, OnlySuccessfulRowsOfTheRuleSetCount) {
  std::vector<BenchRow> rows = {ok_row("a", "reliable", 1000, 1.0),
                                ok_row("b", "reliable", 10000, 10.0),
                                ok_row("c", "extended", 100000, 5.0),
                                ok_row("tiny", "reliable", 10, 1e3)};  // below kMinScalingHexes
  EXPECT_FALSE(primal::fit_stage_scaling(rows, "reliable", "weave"));  // two points only
  BenchRow failed = ok_row("d", "reliable", 100000, 1e6);
  failed.status = RunStatus::Failed;
  rows.push_back(failed);
  EXPECT_FALSE(primal::fit_stage_scaling(rows, "reliable", "weave"));
  rows.push_back(ok_row("e", "reliable", 100000, 100.0));
  const auto fit = primal::fit_stage_scaling(rows, "reliable", "weave");
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->exponent, 1.0, 1e-12);
  EXPECT_EQ(fit->points, 3U);
  const auto total = primal::fit_stage_scaling(rows, "reliable", "total");
  ASSERT_TRUE(total);
  EXPECT_NEAR(total->coefficient, 0.002, 1e-12);
  EXPECT_FALSE(primal::fit_stage_scaling(rows, "reliable", "position"));
}

// ---- JSON ----

TEST(Json, RowsKeepTheirOrderAndNullsAndScalingIsPerRuleSetAndStage) {
  primal::BenchResults results;
  results.manifest = "m";
  results.rules = {"reliable"};
  results.rows = {ok_row("a", "reliable", 1000, 0.1), ok_row("b", "reliable", 8000, 0.8),
                  ok_row("c", "reliable", 64000, 6.4)};
  BenchRow missing;
  missing.input = "gone.obj";
  missing.rules = "reliable";
  missing.status = RunStatus::Rejected;
  missing.reason = "cannot open gone.obj";
  results.rows.push_back(missing);
  primal::fit_scaling(results);
  const auto j = primal::to_json(results);
  ASSERT_EQ(j.at("rows").size(), 4U);
  EXPECT_EQ(j["rows"][0]["input"], "a");
  EXPECT_EQ(j["rows"][3]["input"], "gone.obj");
  EXPECT_EQ(j["rows"][3]["status"], "rejected");
  EXPECT_EQ(j["rows"][3]["reason"], "cannot open gone.obj");
  EXPECT_TRUE(j["rows"][3]["hexes"].is_null());
  EXPECT_TRUE(j["rows"][0]["reason"].is_null());
  EXPECT_EQ(j["rows"][1]["seconds"]["weave"], 0.8);
  EXPECT_NEAR(j["scaling"]["reliable"]["weave"]["exponent"].get<double>(), 1.0, 1e-12);
  EXPECT_EQ(j["scaling"]["reliable"]["weave"]["points"], 3);
  EXPECT_FALSE(j["scaling"]["reliable"]["total"].is_null());
}

}  // namespace
