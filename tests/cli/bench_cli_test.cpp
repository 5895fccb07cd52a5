// `stcweave bench` as a user meets it: a manifest in a temporary folder, real child
// processes, every input a row whatever happens to it. No timing is asserted.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "support/cli_run.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using stcweave::test::CliRun;
using stcweave::test::slurp;

CliRun run(const std::string& args) {
  return stcweave::test::run_cli(args);
}

void write(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

class BenchCli : public stcweave::test::CliTest {
 protected:
  BenchCli() : CliTest("stcweave_bench_cli_") {}
  nlohmann::json results() const { return nlohmann::json::parse(slurp(dir_ / "out/results.json")); }
};

TEST_F(BenchCli, EveryInputIsARowFailuresIncluded) {
  write(dir_ / "broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7 9\nthis is not obj\n");
  write(dir_ / "m.manifest", "# two good inputs, a broken one and one that does not exist\n" +
                                 data("bar_1x1x3.obj") + "\n" + data("lblock.obj") +
                                 "   # the L-block\n\nbroken.obj\nno/such/file.obj\n");
  const CliRun r = run("bench " + (dir_ / "m.manifest").string() + " --out " +
                       (dir_ / "out").string() + " --jobs 2");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("bench [4/4]"));  // progress lines
  for (const char* f : {"results.json", "results.csv", "results.md"})
    EXPECT_TRUE(fs::exists(dir_ / "out" / f)) << f;

  const auto j = results();
  // Each run's threads: the hardware threads divided by --jobs, at least 1.
  const std::size_t hardware = std::max(1U, std::thread::hardware_concurrency());
  EXPECT_EQ(j.at("threads").get<std::size_t>(), std::max<std::size_t>(1, hardware / 2));
  const auto& rows = j.at("rows");
  ASSERT_EQ(rows.size(), 4U);
  // Manifest order, whatever finished first.
  EXPECT_THAT(rows[0]["input"].get<std::string>(), HasSubstr("bar_1x1x3.obj"));
  EXPECT_THAT(rows[1]["input"].get<std::string>(), HasSubstr("lblock.obj"));
  EXPECT_THAT(rows[2]["input"].get<std::string>(), HasSubstr("broken.obj"));
  EXPECT_THAT(rows[3]["input"].get<std::string>(), HasSubstr("file.obj"));

  EXPECT_EQ(rows[0]["status"], "ok");
  EXPECT_EQ(rows[0]["hexes"], 3);
  EXPECT_EQ(rows[0]["valid"], true);
  EXPECT_EQ(rows[0]["quads"], 14);
  EXPECT_EQ(rows[0]["genus"], 0);
  EXPECT_TRUE(rows[0]["loops"].is_number());
  EXPECT_TRUE(rows[0]["min_scaled_jacobian"].is_number());
  EXPECT_TRUE(rows[0]["seconds"].contains("weave"));
  EXPECT_GT(rows[0]["peak_memory_mb"].get<double>(), 0.0);
  EXPECT_EQ(rows[1]["status"], "ok");

  for (const std::size_t i : {2U, 3U}) {
    EXPECT_NE(rows[i]["status"], "ok") << rows[i].dump();
    ASSERT_TRUE(rows[i]["reason"].is_string()) << rows[i].dump();
    EXPECT_FALSE(rows[i]["reason"].get<std::string>().empty());
    EXPECT_TRUE(rows[i]["hexes"].is_null());
  }
  EXPECT_THAT(rows[3]["reason"].get<std::string>(), HasSubstr("file.obj"));

  const std::string csv = slurp(dir_ / "out/results.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
  const std::string md = slurp(dir_ / "out/results.md");
  EXPECT_THAT(md, HasSubstr("bar_1x1x3.obj | extended | 14 |"));
}

TEST_F(BenchCli, RuleSetsSideBySideAndGeneratedShapesWithTheirReference) {
  write(dir_ / "g.manifest", "generate:box:2x2x2\ngenerate:bar:straight\n");
  const CliRun r = run("bench " + (dir_ / "g.manifest").string() + " --out " +
                       (dir_ / "out").string() + " --rules reliable,extended -q");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = results();
  // One run at a time: each gets every hardware thread.
  EXPECT_EQ(j.at("threads").get<std::size_t>(),
            std::max<std::size_t>(1, std::thread::hardware_concurrency()));
  const auto& rows = j.at("rows");
  ASSERT_EQ(rows.size(), 4U);
  EXPECT_EQ(rows[0]["input"], "box:2x2x2");
  EXPECT_EQ(rows[0]["rules"], "reliable");
  EXPECT_EQ(rows[1]["input"], "box:2x2x2");
  EXPECT_EQ(rows[1]["rules"], "extended");
  EXPECT_EQ(rows[2]["input"], "bar:straight");
  EXPECT_EQ(rows[0]["quads"], 24);
  EXPECT_EQ(rows[0]["reference_hexes"], 8);
  EXPECT_NEAR(rows[0]["reference_min_scaled_jacobian"].get<double>(), 1.0, 1e-12);
  EXPECT_EQ(rows[3]["reference_hexes"], 3);
  EXPECT_EQ(rows[0]["status"], "ok");
  EXPECT_EQ(rows[0]["hexes"], 8);
  EXPECT_TRUE(j["scaling"].contains("reliable"));
  EXPECT_TRUE(j["scaling"].contains("extended"));
  EXPECT_THAT(slurp(dir_ / "out/results.md"), HasSubstr("## Side by side"));
}

TEST_F(BenchCli, ATinyTimeLimitGivesATimeoutRow) {
  write(dir_ / "t.manifest", "generate:box:24x24x24\n");
  const CliRun r = run("bench " + (dir_ / "t.manifest").string() + " --out " +
                       (dir_ / "out").string() + " --timeout 0.02");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto rows = results().at("rows");
  ASSERT_EQ(rows.size(), 1U);
  EXPECT_EQ(rows[0]["status"], "timeout");
  EXPECT_THAT(rows[0]["reason"].get<std::string>(), HasSubstr("--timeout"));
}

TEST_F(BenchCli, ASmallMemoryLimitGivesAnOutOfMemoryRow) {
  // The 24^3 box needs about twice this address space.
  write(dir_ / "m.manifest", "generate:box:24x24x24\n");
  const CliRun r = run("bench " + (dir_ / "m.manifest").string() + " --out " +
                       (dir_ / "out").string() + " --memory 12");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto rows = results().at("rows");
  ASSERT_EQ(rows.size(), 1U);
  EXPECT_EQ(rows[0]["status"], "out of memory");
  EXPECT_THAT(rows[0]["reason"].get<std::string>(), HasSubstr("--memory"));
}

TEST_F(BenchCli, BadManifestOrOptionsFailBeforeAnythingRuns) {
  const CliRun missing =
      run("bench " + (dir_ / "absent.manifest").string() + " --out " + (dir_ / "out").string());
  EXPECT_EQ(missing.code, 2);
  EXPECT_THAT(missing.out, HasSubstr("absent.manifest"));
  EXPECT_FALSE(fs::exists(dir_ / "out"));

  write(dir_ / "bad.manifest", "a.obj\nb.obj c.msh d.msh\n");
  const CliRun bad_line =
      run("bench " + (dir_ / "bad.manifest").string() + " --out " + (dir_ / "out").string());
  EXPECT_EQ(bad_line.code, 2);
  EXPECT_THAT(bad_line.out, HasSubstr("bad.manifest:2"));

  write(dir_ / "ok.manifest", data("bar_1x1x3.obj") + "\n");
  const std::string ok =
      "bench " + (dir_ / "ok.manifest").string() + " --out " + (dir_ / "out").string();
  const CliRun rules = run(ok + " --rules reliable,magic");
  EXPECT_EQ(rules.code, 2);
  EXPECT_THAT(rules.out, HasSubstr("magic"));
  EXPECT_EQ(run(ok + " --jobs 0").code, 1);
  EXPECT_EQ(run(ok + " --threads -1").code, 1);
  EXPECT_EQ(run(ok + " --threads 257").code, 1);
  EXPECT_EQ(run(ok + " --timeout -3").code, 1);
  EXPECT_EQ(run(ok + " --frobnicate").code, 1);
  EXPECT_FALSE(fs::exists(dir_ / "out" / "results.json"));
}

}  // namespace
