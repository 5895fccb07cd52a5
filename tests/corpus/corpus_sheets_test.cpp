/// \file
/// The STC and the validator on every third-party hex mesh of the shared corpus (entries
/// of `expected.json` with `reference_hexes`): the STC has one boundary point per boundary
/// quad (`quads`); its figures are the same across two runs and after writing the mesh in
/// another format and reading it back; the validator's verdict (with the boundary compared
/// to `NAME.boundary.obj` or the Gmsh surface it was made from, matched by
/// coordinates) is the one recorded below, each invalid
/// mesh with the reason found.

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "stcweave/primal/io.hpp"
#include "stcweave/stc/hex_stc.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/corpus.hpp"

namespace {

namespace fs = std::filesystem;
using namespace stcweave;

const fs::path& kData = test::shared_data();
using test::expected_figures;

/// The hex meshes listed in expected.json; one empty name when the data folder is missing,
/// so that the test shows a visible skip rather than nothing.
std::vector<std::string> hex_meshes() {
  std::vector<std::string> files = test::expected_files([](const nlohmann::json& figures) {
    return figures.contains("reference_hexes") && figures["reference_hexes"].is_number();
  });
  return files.empty() ? std::vector<std::string>{""} : files;
}

/// The figures compared across runs and formats.
struct Figures {
  std::size_t hexes = 0;
  std::size_t sheets = 0;
  std::size_t chords = 0;
  std::size_t blind_chords = 0;
  std::size_t blind_sheets = 0;
  std::size_t self_intersecting_sheets = 0;
  std::size_t boundary_points = 0;
  std::multiset<std::pair<std::size_t, std::size_t>> sheet_hexes_and_loops;
  std::multiset<std::size_t> chord_lengths;
  friend bool operator==(const Figures&, const Figures&) = default;
};

Figures figures_of(const stc::HexStc& stc) {
  Figures f;
  f.hexes = stc.num_hexes();
  f.sheets = stc.sheets.size();
  f.chords = stc.chords.size();
  f.blind_chords = stc::num_blind_chords(stc);
  f.blind_sheets = stc::num_blind_sheets(stc);
  f.self_intersecting_sheets = stc::num_self_intersecting_sheets(stc);
  f.boundary_points = stc.boundary_points.size();
  for (const stc::Sheet& s : stc.sheets)
    f.sheet_hexes_and_loops.emplace(s.hexes.size(), s.boundary_loops.size());
  for (const stc::Chord& c : stc.chords) f.chord_lengths.insert(c.hexes.size());
  return f;
}

stc::HexComplex complex_of(const primal::MeshFile& file) {
  stc::HexComplex c;
  c.hexes = file.hexes;
  c.num_nodes = static_cast<std::size_t>(file.points.rows());
  return c;
}

/// The quads of the boundary surface over the hex mesh's node ids, matching nodes by
/// coordinates; nullopt when some boundary node has no (or no unique) match.
std::optional<stc::QuadSurface> expected_boundary(const fs::path& mesh_path,
                                                  const primal::MeshFile& mesh, std::string* why) {
  // NAME.boundary.obj next to a third-party mesh; the surface NAME.obj it was made from
  // for the Gmsh reference meshes (NAME.reference_hex.msh).
  fs::path obj = mesh_path;
  obj.replace_extension(".boundary.obj");
  if (!fs::exists(obj)) {
    fs::path stem = mesh_path.stem();  // NAME.reference_hex
    obj = mesh_path.parent_path() / stem.replace_extension(".obj");
  }
  if (!fs::exists(obj)) {
    *why = "no boundary surface for " + mesh_path.filename().string();
    return std::nullopt;
  }
  const primal::MeshFile surface = primal::read_mesh(obj);
  // Match by position up to 1e-7 of the bounding box (files print different digits):
  // hash the points on a grid of that step and look in the 27 neighbouring cells.
  const double extent =
      (mesh.points.colwise().maxCoeff() - mesh.points.colwise().minCoeff()).norm();
  const double tolerance = 1e-7 * std::max(extent, 1e-300);
  using Cell = std::array<long long, 3>;
  const auto cell_of = [&](double x, double y, double z) {
    return Cell{std::llround(x / tolerance), std::llround(y / tolerance),
                std::llround(z / tolerance)};
  };
  std::map<Cell, std::vector<Eigen::Index>> grid;
  for (Eigen::Index i = 0; i < mesh.points.rows(); ++i)
    grid[cell_of(mesh.points(i, 0), mesh.points(i, 1), mesh.points(i, 2))].push_back(i);
  std::vector<NodeId> node_of(static_cast<std::size_t>(surface.points.rows()), NodeId::invalid());
  std::size_t unmatched = 0;
  for (Eigen::Index i = 0; i < surface.points.rows(); ++i) {
    const Eigen::RowVector3d p = surface.points.row(i);
    const Cell c = cell_of(p(0), p(1), p(2));
    std::vector<Eigen::Index> candidates;
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (Eigen::Index j : it->second)
            if ((mesh.points.row(j) - p).norm() <= tolerance) candidates.push_back(j);
        }
    if (candidates.size() == 1)
      node_of[static_cast<std::size_t>(i)] = NodeId(static_cast<std::size_t>(candidates[0]));
    else
      ++unmatched;
  }
  stc::QuadSurface out;
  out.num_nodes = static_cast<std::size_t>(mesh.points.rows());
  for (stc::Quad q : surface.quads) {
    for (NodeId& v : q) {
      if (!node_of[v.index()].is_valid()) {
        *why = std::to_string(unmatched) + " boundary nodes of " + obj.filename().string() +
               " match no single node of the mesh";
        return std::nullopt;
      }
      v = node_of[v.index()];
    }
    out.quads.push_back(q);
  }
  return out;
}

/// Meshes the validator finds invalid, with the reason found by hand (see the test's
/// output and the project notes). Empty when every shared hex mesh is valid.
const std::map<std::string, std::string>& known_invalid() {
  static const std::map<std::string, std::string> invalid = {};
  return invalid;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

class CorpusSheets : public ::testing::TestWithParam<std::string> {};

TEST_P(CorpusSheets, StcIsStableAndValidationAsRecorded) {
  const std::string& name = GetParam();
  if (name.empty())
    GTEST_SKIP() << "shared data missing: " << (kData / "expected.json")
                 << " not found or unreadable (set STCWEAVE_SHARED_DATA)";
  const nlohmann::json& expected = expected_figures().at(name);
  const primal::MeshFile file = primal::read_mesh(kData / name);
  const stc::HexComplex complex = complex_of(file);
  ASSERT_EQ(complex.hexes.size(), expected.at("reference_hexes").get<std::size_t>());

  // The validator, with the boundary compared to NAME.boundary.obj when it matches.
  std::string why_not_compared;
  const std::optional<stc::QuadSurface> boundary =
      expected_boundary(kData / name, file, &why_not_compared);
  auto start = std::chrono::steady_clock::now();
  const stc::ValidationReport report =
      stc::validate_hex_complex(complex, boundary ? &*boundary : nullptr);
  const double validate_seconds = seconds_since(start);

  start = std::chrono::steady_clock::now();
  const stc::HexStc stc = stc::build_hex_stc(complex);
  const double stc_seconds = seconds_since(start);
  const Figures figures = figures_of(stc);

  std::cout << "[corpus sheets] " << name << ": hexes " << figures.hexes << ", sheets "
            << figures.sheets << " (" << figures.self_intersecting_sheets << " self-intersecting, "
            << figures.blind_sheets << " blind), chords " << figures.chords << " ("
            << figures.blind_chords << " blind), boundary points " << figures.boundary_points
            << "; build_hex_stc " << stc_seconds * 1e3 << " ms, validate " << validate_seconds * 1e3
            << " ms; "
            << (boundary ? "boundary compared" : "boundary not compared: " + why_not_compared)
            << "; " << report.summary() << "\n";
  RecordProperty("valid", report.valid ? "true" : "false");
  RecordProperty("sheets", std::to_string(figures.sheets));
  RecordProperty("chords", std::to_string(figures.chords));

  EXPECT_EQ(figures.boundary_points, expected.at("quads").get<std::size_t>()) << name;
  EXPECT_EQ(report.boundary_faces, expected.at("quads").get<std::size_t>()) << name;
  const auto known = known_invalid().find(name);
  if (known == known_invalid().end())
    EXPECT_TRUE(report.valid) << name << ": " << report.summary();
  else
    EXPECT_FALSE(report.valid) << name << " was invalid (" << known->second << ")";

  // Stable across runs.
  EXPECT_EQ(figures_of(stc::build_hex_stc(complex)), figures) << name;

  // Stable across formats: write in another format, read back.
  const bool is_vtk = file.format == "vtk";
  const fs::path copy =
      fs::temp_directory_path() /
      ("stcweave_corpus_sheets_" + std::to_string(::getpid()) + (is_vtk ? ".mesh" : ".vtk"));
  primal::HexMesh mesh{file.points, complex};
  primal::write_hex_mesh(mesh, copy, is_vtk ? primal::Format::Medit : primal::Format::Vtk);
  const primal::MeshFile again = primal::read_mesh(copy);
  fs::remove(copy);
  EXPECT_EQ(figures_of(stc::build_hex_stc(complex_of(again))), figures) << name;
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  if (info.param.empty()) return "shared_data_missing";
  std::string out;
  for (const char c : info.param) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

INSTANTIATE_TEST_SUITE_P(SharedData, CorpusSheets, ::testing::ValuesIn(hex_meshes()), test_name);

}  // namespace
