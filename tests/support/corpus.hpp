#pragma once
/// \file
/// The shared third-party meshes (`../shared/data`, STCWEAVE_SHARED_DATA) and the figures
/// of their independent oracle, `expected.json`, for the tests labelled `corpus`. Only for
/// targets that define STCWEAVE_SHARED_DATA.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace stcweave::test {

/// The shared data folder.
inline const std::filesystem::path& shared_data() {
  static const std::filesystem::path path = STCWEAVE_SHARED_DATA;
  return path;
}

/// True when the environment variable STCWEAVE_REQUIRE_SHARED_DATA is set to 1 (CI sets it
/// in .ci/run): a corpus test must then fail, not skip, when the shared data is missing. A
/// user's clone without the data leaves it unset and the corpus tests skip.
inline bool shared_data_required() {
  const char* v = std::getenv("STCWEAVE_REQUIRE_SHARED_DATA");
  return v != nullptr && std::string(v) == "1";
}

/// True when the shared data folder exists (a test that then finds no expected.json or an
/// empty file list must fail, not skip).
inline bool has_shared_data() {
  return std::filesystem::is_directory(shared_data());
}

/// expected.json, parsed once; not an object (null or discarded) when the file is missing
/// or unreadable.
inline const nlohmann::json& expected_figures() {
  static const nlohmann::json figures = [] {
    std::ifstream in(shared_data() / "expected.json");
    if (!in) return nlohmann::json();
    return nlohmann::json::parse(in, nullptr, false);
  }();
  return figures;
}

/// The names listed in expected.json whose figures pass `keep` (all when `keep` is empty),
/// in the file's order; empty when the file is missing or unreadable.
inline std::vector<std::string> expected_files(
    const std::function<bool(const nlohmann::json&)>& keep = {}) {
  std::vector<std::string> files;
  const nlohmann::json& expected = expected_figures();
  if (!expected.is_object()) return files;
  for (const auto& [name, figures] : expected.items())
    if (!keep || keep(figures)) files.push_back(name);
  return files;
}

}  // namespace stcweave::test

/// In a test body: skips the test when the shared data is missing, or fails it when
/// `shared_data_required()` (CI).
#define STCWEAVE_SKIP_WITHOUT_SHARED_DATA()                                       \
  do {                                                                            \
    if (!::stcweave::test::has_shared_data()) {                                   \
      if (::stcweave::test::shared_data_required())                               \
        FAIL() << "shared data not found at " << STCWEAVE_SHARED_DATA             \
               << " and STCWEAVE_REQUIRE_SHARED_DATA=1: CI needs ../shared/data"; \
      GTEST_SKIP() << "shared data not found at " << STCWEAVE_SHARED_DATA;        \
    }                                                                             \
  } while (false)
