/// Corpus test of primal/diagnose.hpp: every file listed in ../shared/data/expected.json is
/// read and diagnosed, and every figure of expected.json is compared (null where null).

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>

#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/io.hpp"
#include "support/corpus.hpp"

namespace stcweave::primal {
namespace {

const std::filesystem::path& kData = test::shared_data();

TEST(CorpusDiagnose, EveryFigureOfExpectedJsonAgrees) {
  if (!std::filesystem::exists(kData / "expected.json"))
    GTEST_SKIP() << "shared test data not found at " << kData
                 << " (set STCWEAVE_SHARED_DATA): corpus diagnosis not checked";
  const nlohmann::json& expected = test::expected_figures();
  ASSERT_TRUE(expected.is_object()) << "expected.json is not readable JSON";
  ASSERT_FALSE(expected.empty());
  std::size_t files = 0, figures = 0;
  std::string largest;
  std::size_t largest_quads = 0, largest_hexes = 0;
  for (const auto& [name, figures_expected] : expected.items()) {
    SCOPED_TRACE(name);
    MeshFile file;
    try {
      file = read_mesh(kData / name);
    } catch (const std::exception& e) {
      ADD_FAILURE() << name << ": cannot be read: " << e.what();
      continue;
    }
    const SurfaceDiagnosis d = diagnose(file);
    const nlohmann::json got = to_json(d);
    for (const auto& [key, want] : figures_expected.items()) {
      if (key == "reference_hexes") {
        EXPECT_EQ(d.hexes, want.get<std::size_t>()) << name << ": hexes";
      } else {
        ASSERT_TRUE(got.contains(key)) << name << ": no figure " << key;
        EXPECT_EQ(got[key], want) << name << ": " << key;
      }
      ++figures;
    }
    if (std::tie(d.quads, d.hexes) > std::tie(largest_quads, largest_hexes)) {
      largest_quads = d.quads;
      largest_hexes = d.hexes;
      largest = name;
    }
    ++files;
  }
  EXPECT_EQ(files, expected.size());
  std::cout << "[ corpus   ] " << files << " files, " << figures << " figures compared\n";

  // A timing, reported, not asserted: the largest input (most quads, then most hexes), read
  // once, diagnosed three times.
  const auto read_start = std::chrono::steady_clock::now();
  const MeshFile big = read_mesh(kData / largest);
  const std::chrono::duration<double, std::milli> read_ms =
      std::chrono::steady_clock::now() - read_start;
  double best = 1e300;
  for (int run = 0; run < 3; ++run) {
    const auto start = std::chrono::steady_clock::now();
    const SurfaceDiagnosis d = diagnose(big);
    const std::chrono::duration<double, std::milli> ms = std::chrono::steady_clock::now() - start;
    best = std::min(best, ms.count());
    EXPECT_EQ(d.quads, largest_quads);
  }
  std::cout << "[ timing   ] diagnose(" << largest << "): " << largest_quads << " quads, "
            << big.hexes.size() << " hexes, best of 3: " << best
            << " ms (reading: " << read_ms.count() << " ms)\n";
}

TEST(CorpusDiagnose, FandiskHasOneSelfIntersectingLoopAndIsRejected) {
  const auto path = kData / "real/pmp/fandisk_quads.off";
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << "shared test data not found at " << kData << ": fandisk not checked";
  const SurfaceDiagnosis d = diagnose(read_mesh(path));
  ASSERT_EQ(d.sites.self_intersecting_loops.size(), 1u);
  try {
    require_weavable(d);
    FAIL() << "fandisk_quads.off has a self-intersecting loop";
  } catch (const TopologyError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("fandisk_quads.off: loop " + d.sites.self_intersecting_loops[0].loop.str()),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("crosses itself in q"), std::string::npos) << msg;
  }
}

TEST(CorpusDiagnose, KleinBottleIsRejectedAsNonOrientable) {
  const auto path = kData / "real/mfem/klein-bottle.mesh";
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << "shared test data not found at " << kData << ": klein bottle not checked";
  try {
    require_weavable(diagnose(read_mesh(path)));
    FAIL() << "klein-bottle.mesh is not orientable";
  } catch (const TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("not orientable"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stcweave::primal
