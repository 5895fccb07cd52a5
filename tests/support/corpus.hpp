#pragma once
/// \file
/// The shared third-party meshes (`../shared/data`, STCWEAVE_SHARED_DATA) and the figures
/// of their independent oracle, `expected.json`, for the tests labelled `corpus`. Only for
/// targets that define STCWEAVE_SHARED_DATA.

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
