/// \file
/// Reads every file listed in the shared `expected.json` and checks what the readers find
/// against the independent figures: the file loads; a hex mesh has `reference_hexes`
/// hexahedra; an OBJ surface has `quads` quads. (For a hex mesh, `quads` counts its
/// boundary quads, not the quads stored in the file, so it is not compared there.)

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "stcweave/primal/io.hpp"
#include "support/corpus.hpp"

namespace {

namespace fs = std::filesystem;
using stcweave::primal::MeshFile;
using stcweave::primal::read_mesh;

const fs::path& kData = stcweave::test::shared_data();

using stcweave::test::expected_figures;

/// The files listed in expected.json; one empty name when the data folder is missing, so
/// that the test shows a visible skip rather than nothing.
std::vector<std::string> listed_files() {
  std::vector<std::string> files = stcweave::test::expected_files();
  return files.empty() ? std::vector<std::string>{""} : files;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

class CorpusRead : public ::testing::TestWithParam<std::string> {};

TEST_P(CorpusRead, LoadsWithTheExpectedCounts) {
  const std::string& name = GetParam();
  if (name.empty())
    GTEST_SKIP() << "shared data missing: " << (kData / "expected.json")
                 << " not found or unreadable (set STCWEAVE_SHARED_DATA)";
  const nlohmann::json& figures = expected_figures().at(name);
  MeshFile file;
  ASSERT_NO_THROW(file = read_mesh(kData / name)) << name;
  EXPECT_GT(file.points.rows(), 0) << name;
  EXPECT_EQ(file.quad_lines.size(), file.quads.size()) << name;
  if (figures.contains("reference_hexes") && figures["reference_hexes"].is_number()) {
    EXPECT_EQ(file.hexes.size(), figures["reference_hexes"].get<std::size_t>()) << name;
    EXPECT_EQ(file.triangles, 0u) << name;
  } else if (figures.contains("quads")) {
    // A surface file: every face in it is a quad of the surface.
    EXPECT_TRUE(file.hexes.empty()) << name;
    if (ends_with(name, ".obj"))
      EXPECT_EQ(file.quads.size(), figures["quads"].get<std::size_t>()) << name;
  }
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  if (info.param.empty()) return "shared_data_missing";
  std::string out;
  for (const char c : info.param) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

INSTANTIATE_TEST_SUITE_P(SharedData, CorpusRead, ::testing::ValuesIn(listed_files()), test_name);

}  // namespace
