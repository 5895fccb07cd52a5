// Cell and point data (mesh_data.hpp): what hex_mesh_data computes on meshes whose answer is
// known, the weave history of a real weave, and every writer that stores data read back by
// read_mesh_data (values exact, the mesh itself still readable by read_mesh).
#include "stcweave/primal/mesh_data.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <system_error>

#include <unistd.h>

#include "stcweave/primal/pipeline.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// A folder of its own for the running test, removed with everything in it when the test
/// ends (named by the test and the process, so that parallel ctest runs do not share it).
class TempDir {
 public:
  TempDir() {
    std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::replace(name.begin(), name.end(), '/', '_');
    path_ = fs::temp_directory_path() /
            ("stcweave_mesh_data_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  TempDir(TempDir&&) = delete;
  TempDir& operator=(TempDir&&) = delete;
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

using test::file_of;

const DataArray& cell(const MeshData& d, const std::string& name) {
  const DataArray* a = d.cell(name);
  if (a == nullptr) throw std::runtime_error("no cell array " + name);
  return *a;
}

TEST(MeshData, BoxSheetsChordsLayersBoundaryAndValence) {
  // A 3 x 4 x 5 box: 12 sheets (one per slab), 47 chords, layers 0..1, every node a corner
  // of 1, 2, 4 or 8 hexes.
  HexMesh box = test::box_hexes(3, 4, 5);
  box.points.col(0) *= 2.0;  // a skewed box still has scaled Jacobian 1 (an affine map of a cube)
  const stc::HexStc stc = stc::build_hex_stc(box.complex);
  const MeshData d = hex_mesh_data(box, stc);
  ASSERT_EQ(cell(d, "scaled_jacobian").values.size(), 60U);
  for (const double v : cell(d, "scaled_jacobian").values) EXPECT_NEAR(v, 1.0, 1e-12);
  std::set<double> sheets;
  for (const char* name : {"sheet_0", "sheet_1", "sheet_2"})
    for (const double v : cell(d, name).values) sheets.insert(v);
  EXPECT_EQ(sheets.size(), 3U + 4U + 5U);
  std::set<double> chords;
  for (const char* name : {"chord_0", "chord_1", "chord_2"})
    for (const double v : cell(d, name).values) chords.insert(v);
  EXPECT_EQ(chords.size(), 4U * 5U + 3U * 5U + 3U * 4U);
  // Interior hexes of a 3 x 4 x 5 box: 1 x 2 x 3 = 6 at layer 1, the others at layer 0.
  std::size_t deep = 0;
  for (const double v : cell(d, "layer").values) {
    EXPECT_TRUE(v == 0.0 || v == 1.0) << v;
    deep += v == 1.0 ? 1 : 0;
  }
  EXPECT_EQ(deep, 6U);
  EXPECT_EQ(d.cell("creation_step"), nullptr);  // no weave: no weave arrays
  const DataArray* boundary = d.point("boundary");
  const DataArray* valence = d.point("valence");
  ASSERT_NE(boundary, nullptr);
  ASSERT_NE(valence, nullptr);
  std::map<double, std::size_t> by_valence;
  std::size_t on_boundary = 0;
  for (std::size_t v = 0; v < valence->values.size(); ++v) {
    ++by_valence[valence->values[v]];
    on_boundary += boundary->values[v] == 1.0 ? 1 : 0;
    EXPECT_EQ(boundary->values[v] == 1.0, valence->values[v] < 8.0) << "node " << v;
  }
  EXPECT_EQ(by_valence[1.0], 8U);            // corners
  EXPECT_EQ(by_valence[8.0], 2U * 3U * 4U);  // interior nodes
  EXPECT_EQ(on_boundary, 4U * 5U * 6U - 2U * 3U * 4U);
}

TEST(MeshData, FaceNeighboursAreSymmetric) {
  const HexMesh mesh = test::voxel_hexes(test::lblock_cells());
  const auto nb = hex_face_neighbours(mesh.complex);
  std::size_t boundary = 0;
  for (std::size_t h = 0; h < nb.size(); ++h) {
    for (const std::int32_t o : nb[h]) {
      if (o < 0) {
        EXPECT_EQ(o, -1);
        ++boundary;
        continue;
      }
      const auto& back = nb[static_cast<std::size_t>(o)];
      EXPECT_NE(std::find(back.begin(), back.end(), static_cast<std::int32_t>(h)), back.end());
    }
  }
  EXPECT_EQ(boundary, stc::boundary_surface(mesh.complex).quads.size());
}

TEST(MeshData, WeaveHistoryOfARealWeave) {
  // Without a trace: the history the weave records itself.
  MeshOptions options;
  const MeshResult r = mesh_file(file_of(test::box_surface(3, 3, 4), "box"), options);
  const WeaveHistory h = weave_history(r.woven);
  const std::size_t m = r.mesh.complex.hexes.size();
  ASSERT_EQ(m, 36U);
  ASSERT_FALSE(h.shrinks.empty());
  const stc::HexStc stc = stc::build_hex_stc(r.mesh.complex);
  const MeshData d = hex_mesh_data(r.mesh, stc, &h);
  for (std::size_t i = 0; i < m; ++i) {
    EXPECT_EQ(cell(d, "creation_step").values[i], static_cast<double>(i));
    EXPECT_EQ(cell(d, "shrink").values[i], r.woven.hex_shrink[i]);
    EXPECT_EQ(cell(d, "rule").values[i], rule_code(r.woven.hex_rule[i]));
    const ShrinkRecord* s = h.shrink(r.woven.hex_shrink[i]);
    ASSERT_NE(s, nullptr) << "hex " << i << " of shrink " << r.woven.hex_shrink[i];
    EXPECT_EQ(cell(d, "depth").values[i], s->depth);
    EXPECT_TRUE(h.hex_node[i].is_valid());
  }
  // The same history from a full trace of the same weave (what `stcweave view` reads).
  options.weave.trace = true;
  const MeshResult r2 = mesh_file(file_of(test::box_surface(3, 3, 4), "box"), options);
  TraceDigest digest;
  for (const weave::TraceEvent& e : r2.woven.trace) digest.add(e);
  ASSERT_EQ(digest.shrinks().size(), h.shrinks.size());
  for (std::size_t i = 0; i < h.shrinks.size(); ++i) {
    EXPECT_EQ(digest.shrinks()[i].shrink, h.shrinks[i].shrink);
    EXPECT_EQ(digest.shrinks()[i].loop, h.shrinks[i].loop);
    EXPECT_EQ(digest.shrinks()[i].side, h.shrinks[i].side);
    EXPECT_EQ(digest.shrinks()[i].length, h.shrinks[i].length);
    EXPECT_EQ(digest.shrinks()[i].depth, h.shrinks[i].depth);
    EXPECT_EQ(digest.shrinks()[i].decided_by, h.shrinks[i].decided_by);
    EXPECT_EQ(digest.shrinks()[i].failed, h.shrinks[i].failed);
  }
  EXPECT_EQ(digest.hex_nodes(), h.hex_node);
  EXPECT_EQ(weave_history(r2.woven).hex_node, h.hex_node);
}

TEST(MeshData, WeaveHistoryOfABacktrackedWeaveKeepsOnlyWhatStayed) {
  // Shrinks undone by backtracking give their index and hex ids to the next ones: the
  // history recorded by the weave must agree with the digest of its trace, which replays
  // every event in order (undone ones included).
  MeshOptions options;
  options.weave.rules = weave::RuleSet::Extended;
  options.weave.trace = true;
  options.interior.mode = InteriorMode::Weave;
  // The extended weave of the triangle-split L-block undoes shrinks (2, measured).
  const MeshResult r = mesh_file(
      file_of(test::triangle_split_of(test::voxel_surface(test::lblock_cells())), "split L"),
      options);
  ASSERT_GT(r.woven.stats.rolled_back_shrinks, 0U) << "no shrink was undone: pick another shape";
  TraceDigest digest;
  for (const weave::TraceEvent& e : r.woven.trace) digest.add(e);
  const WeaveHistory h = weave_history(r.woven);
  ASSERT_EQ(h.hex_node.size(), r.woven.complex.hexes.size());
  ASSERT_EQ(digest.shrinks().size(), h.shrinks.size());
  for (std::size_t i = 0; i < h.shrinks.size(); ++i) {
    EXPECT_EQ(digest.shrinks()[i].shrink, h.shrinks[i].shrink);
    EXPECT_EQ(digest.shrinks()[i].loop, h.shrinks[i].loop);
    EXPECT_EQ(digest.shrinks()[i].failed, h.shrinks[i].failed);
  }
  std::vector<NodeId> traced = digest.hex_nodes();
  traced.resize(h.hex_node.size(), NodeId::invalid());
  EXPECT_EQ(traced, h.hex_node);
}

TEST(MeshData, WeaveHistoryRefusesAResultWithTooFewNodes) {
  MeshOptions options;
  MeshResult r = mesh_file(file_of(test::box_surface(2, 2, 2), "box"), options);
  ASSERT_EQ(weave_history(r.woven).hex_node.size(), 8U);
  r.woven.hex_node.pop_back();
  EXPECT_THROW((void)weave_history(r.woven), InvalidInput);
}

TEST(MeshData, RuleCodes) {
  for (const char* name : {"cross", "cross-relaxed", "blind-chord", "parallel-merge", "pillow"})
    EXPECT_EQ(rule_name(rule_code(name)), name);
  EXPECT_EQ(rule_code("some-new-rule"), kRuleOther);
  EXPECT_EQ(rule_name(42), "other");
}

TEST(MeshData, AppendedHexesExtendTheHistoryAndFewerAreRefused) {
  WeaveHistory h;
  h.hex_shrink = {0, 1};
  h.hex_rule = {"cross", "blind-chord"};
  h.hex_node = {NodeId(3), NodeId(4)};
  append_hexes(h, 5, "pillow");
  ASSERT_EQ(h.hex_shrink.size(), 5u);
  EXPECT_EQ(h.hex_shrink[1], 1);
  EXPECT_EQ(h.hex_shrink[4], -1);
  EXPECT_EQ(h.hex_rule[4], "pillow");
  EXPECT_EQ(h.hex_node[0], NodeId(3));
  EXPECT_FALSE(h.hex_node[4].is_valid());
  EXPECT_THROW(append_hexes(h, 3, "pillow"), InvalidInput);
}

/// A mesh with data of both types, values that need all 17 digits, negative integers.
std::pair<HexMesh, MeshData> sample() {
  HexMesh mesh = test::box_hexes(2, 1, 2);
  mesh.points(3, 1) += 0.1234567890123;
  const stc::HexStc stc = stc::build_hex_stc(mesh.complex);
  MeshData d = hex_mesh_data(mesh, stc);
  DataArray extra;
  extra.name = "signed";
  extra.type = DataType::Int32;
  extra.values = {-3, 7, -1, 2147483647};
  d.cells.push_back(extra);
  return {mesh, d};
}

class WriterData : public ::testing::TestWithParam<std::string> {};

TEST_P(WriterData, ReadsBackEveryArray) {
  const auto [mesh, data] = sample();
  const TempDir tmp;
  const fs::path& dir = tmp.path();
  const std::string ext = GetParam() == "msh2" ? ".msh" : "." + GetParam();
  const fs::path path = dir / ("data_" + GetParam() + ext);
  write_hex_mesh(mesh, data, path, format_from_name(GetParam()));
  const MeshData back = read_mesh_data(path);
  ASSERT_EQ(back.cells.size(), data.cells.size());
  ASSERT_EQ(back.points.size(), data.points.size());
  for (std::size_t i = 0; i < data.cells.size(); ++i) {
    EXPECT_EQ(back.cells[i].name, data.cells[i].name);
    EXPECT_EQ(back.cells[i].values, data.cells[i].values) << data.cells[i].name;
    if (GetParam() != "msh" && GetParam() != "msh2")  // Gmsh data has no type: reals
      EXPECT_EQ(back.cells[i].type, data.cells[i].type) << data.cells[i].name;
  }
  for (std::size_t i = 0; i < data.points.size(); ++i) {
    EXPECT_EQ(back.points[i].name, data.points[i].name);
    EXPECT_EQ(back.points[i].values, data.points[i].values) << data.points[i].name;
  }
  // The mesh reader still reads the mesh in spite of the data sections.
  const MeshFile f = read_mesh(path);
  EXPECT_EQ(f.hexes.size(), mesh.complex.hexes.size());
  EXPECT_EQ(f.points.rows(), mesh.points.rows());
  // No data: the bytes of the plain writer.
  const fs::path plain = dir / ("plain_" + GetParam() + ext);
  const fs::path empty = dir / ("empty_" + GetParam() + ext);
  write_hex_mesh(mesh, plain, format_from_name(GetParam()));
  write_hex_mesh(mesh, MeshData{}, empty, format_from_name(GetParam()));
  EXPECT_EQ(slurp(plain), slurp(empty));
  EXPECT_TRUE(read_mesh_data(plain).empty());
}

INSTANTIATE_TEST_SUITE_P(Formats, WriterData, ::testing::Values("vtk", "vtu", "msh", "msh2"));

TEST(MeshData, FormatsWithoutDataGetTheMeshAlone) {
  const auto [mesh, data] = sample();
  const TempDir tmp;
  const fs::path& dir = tmp.path();
  for (const char* ext : {".mesh", ".inp"}) {
    write_hex_mesh(mesh, data, dir / ("with" + std::string(ext)));
    write_hex_mesh(mesh, dir / ("without" + std::string(ext)));
    EXPECT_EQ(slurp(dir / ("with" + std::string(ext))),
              slurp(dir / ("without" + std::string(ext))));
  }
}

TEST(MeshData, WritersRefuseBadArrays) {
  auto [mesh, data] = sample();
  const TempDir tmp;
  const fs::path path = tmp.path() / "bad.vtk";
  MeshData short_array = data;
  short_array.cells[0].values.pop_back();
  EXPECT_THROW(write_hex_mesh(mesh, short_array, path), InvalidInput);
  MeshData bad_name = data;
  bad_name.points[0].name = "has space";
  EXPECT_THROW(write_hex_mesh(mesh, bad_name, path), InvalidInput);
  EXPECT_FALSE(fs::exists(path));
}

TEST(MeshData, ReaderReportsMalformedSections) {
  const std::string head =
      "# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 0 double\n"
      "CELLS 0 0\nCELL_TYPES 0\n";
  try {
    (void)read_mesh_data(head + "CELL_DATA 2\nSCALARS a int 1\nLOOKUP_TABLE default\n1\n",
                         Format::Vtk, "t.vtk");
    FAIL() << "a short array was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("t.vtk:"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)read_mesh_data(head + "CELL_DATA 1\nBOGUS x\n", Format::Vtk, "t.vtk"),
               InvalidInput);
  EXPECT_THROW((void)read_mesh_data(head + "CELL_DATA 99999999999\n", Format::Vtk, "t.vtk"),
               InvalidInput);
  EXPECT_THROW((void)read_mesh_data("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$ElementData\n1\n"
                                    "\"a\"\n1\n0\n3\n0\n1\n2\n1 5\n",
                                    Format::Msh, "t.msh"),
               InvalidInput);
  // FIELD arrays, as ParaView writes them, are read too.
  const MeshData f = read_mesh_data(
      head + "CELL_DATA 2\nFIELD FieldData 1\nq 1 2 double\n0.5 0.25\n", Format::Vtk, "t.vtk");
  ASSERT_NE(f.cell("q"), nullptr);
  EXPECT_EQ(f.cell("q")->values, (std::vector<double>{0.5, 0.25}));
}

}  // namespace
}  // namespace stcweave::primal
