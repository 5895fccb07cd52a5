/// \file
/// Tests of the mesh readers and writers (`stcweave/primal/io.hpp`): every reader on small
/// in-memory files, every malformed case (an `InvalidInput` naming the line), round trips
/// through every writer.

#include "stcweave/primal/io.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace {

namespace fs = std::filesystem;
using stcweave::InvalidInput;
using stcweave::IoError;
using stcweave::NodeId;
using stcweave::primal::Format;
using stcweave::primal::MeshFile;
using stcweave::primal::read_mesh;
using ::testing::HasSubstr;

MeshFile read_text(const std::string& text, Format format, const std::string& name = "t") {
  std::istringstream in(text);
  return read_mesh(in, format, name);
}

/// The message of the InvalidInput that reading `text` throws ("" if none is thrown).
std::string invalid_message(const std::string& text, Format format,
                            const std::string& name = "bad") {
  try {
    (void)read_text(text, format, name);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

stcweave::stc::Quad quad(int a, int b, int c, int d) {
  return {NodeId(a), NodeId(b), NodeId(c), NodeId(d)};
}

stcweave::stc::Hex hex(std::array<int, 8> v) {
  stcweave::stc::Hex h;
  for (std::size_t i = 0; i < 8; ++i) h[i] = NodeId(v[i]);
  return h;
}

/// A folder of its own for each test, removed afterwards.
class IoFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device random;
    dir_ = fs::temp_directory_path() / ("stcweave_io_test_" + std::to_string(random()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  fs::path dir_;
};

// ---------------------------------------------------------------------------------------
// Format names

TEST(FormatFromName, KnowsEveryName) {
  using stcweave::primal::format_from_name;
  EXPECT_EQ(format_from_name("obj"), Format::Obj);
  EXPECT_EQ(format_from_name("OFF"), Format::Off);
  EXPECT_EQ(format_from_name("vtk"), Format::Vtk);
  EXPECT_EQ(format_from_name("vtu"), Format::Vtu);
  EXPECT_EQ(format_from_name("msh"), Format::Msh);
  EXPECT_EQ(format_from_name("msh2"), Format::Msh2);
  EXPECT_EQ(format_from_name("mesh"), Format::Medit);
  EXPECT_EQ(format_from_name("medit"), Format::Medit);
  EXPECT_EQ(format_from_name("mfem"), Format::Mfem);
  EXPECT_EQ(format_from_name("inp"), Format::Inp);
}

TEST(FormatFromName, UnknownNameListsTheValidOnes) {
  try {
    (void)stcweave::primal::format_from_name("stl");
    FAIL() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("'stl'"));
    EXPECT_THAT(e.what(), HasSubstr("obj, off, vtk, vtu, msh, msh2"));
  }
}

TEST(FormatFromPath, UsesTheExtensionCaseInsensitively) {
  using stcweave::primal::format_from_path;
  EXPECT_EQ(format_from_path("a/b.OBJ"), Format::Obj);
  EXPECT_EQ(format_from_path("b.off"), Format::Off);
  EXPECT_EQ(format_from_path("b.vtk"), Format::Vtk);
  EXPECT_EQ(format_from_path("b.vtu"), Format::Vtu);
  EXPECT_EQ(format_from_path("b.msh"), Format::Msh);
  EXPECT_EQ(format_from_path("b.mesh"), Format::Medit);
  EXPECT_EQ(format_from_path("b.inp"), Format::Inp);
}

TEST(FormatFromPath, UnknownExtensionThrows) {
  EXPECT_THROW((void)stcweave::primal::format_from_path("b.stl"), InvalidInput);
  EXPECT_THROW((void)stcweave::primal::format_from_path("noextension"), InvalidInput);
}

// ---------------------------------------------------------------------------------------
// OBJ

TEST(ReadObj, ReadsQuadsWithSlashesAndNegativeIndices) {
  const MeshFile f = read_text(
      "# comment\nmtllib a.mtl\no thing\ng group\ns 1\nusemtl red\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
      "f 1/1/1 2/1/1 3//1 4\nf -4 -1 -2 -3\nl 1 2\n",
      Format::Obj);
  EXPECT_EQ(f.format, "obj");
  ASSERT_EQ(f.points.rows(), 4);
  EXPECT_EQ(f.points(2, 0), 1.0);
  EXPECT_EQ(f.points(2, 1), 1.0);
  ASSERT_EQ(f.quads.size(), 2u);
  EXPECT_EQ(f.quads[0], quad(0, 1, 2, 3));
  EXPECT_EQ(f.quads[1], quad(0, 3, 2, 1));
  EXPECT_EQ(f.quad_lines, (std::vector<std::size_t>{13, 14}));
  EXPECT_EQ(f.triangles, 0u);
  EXPECT_TRUE(f.notes.empty());
}

TEST(ReadObj, CountsTrianglesAndPolygons) {
  const MeshFile f =
      read_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 0\nf 1 2 3\nf 1 2 3 4 5\nf 1 2 3 4\n",
                Format::Obj);
  EXPECT_EQ(f.triangles, 1u);
  EXPECT_EQ(f.other_cells, 1u);
  EXPECT_EQ(f.quads.size(), 1u);
  EXPECT_EQ(f.quad_lines.at(0), 8u);
}

TEST(ReadObj, KeepsNonFiniteCoordinates) {
  const MeshFile f = read_text("v nan 0 inf\nv -inf 1e400 +2\n", Format::Obj);
  ASSERT_EQ(f.points.rows(), 2);
  EXPECT_TRUE(std::isnan(f.points(0, 0)));
  EXPECT_TRUE(std::isinf(f.points(0, 2)));
  EXPECT_LT(f.points(1, 0), 0.0);
  EXPECT_TRUE(std::isinf(f.points(1, 1)));
  EXPECT_EQ(f.points(1, 2), 2.0);
}

TEST(ReadObj, IndexOutOfRangeNamesLineAndFace) {
  const std::string m =
      invalid_message("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3 9\n", Format::Obj, "s.obj");
  EXPECT_THAT(m, HasSubstr("s.obj:4:"));
  EXPECT_THAT(m, HasSubstr("face 1"));
  EXPECT_THAT(m, HasSubstr("node 9"));
}

TEST(ReadObj, IndexZeroIsRejected) {
  EXPECT_THAT(invalid_message("v 0 0 0\n\nf 0 1 1 1\n", Format::Obj, "s.obj"),
              HasSubstr("s.obj:3:"));
}

TEST(ReadObj, RelativeIndexBeforeTheFirstVertexIsRejected) {
  EXPECT_THAT(invalid_message("v 0 0 0\nf -2 1 1 1\n", Format::Obj, "s.obj"),
              HasSubstr("s.obj:2:"));
}

TEST(ReadObj, BadCoordinateNamesTheLine) {
  EXPECT_THAT(invalid_message("v 0 0 0\nv 1 x 0\n", Format::Obj, "s.obj"),
              HasSubstr("s.obj:2: expected a number"));
}

TEST(ReadObj, VertexWithTwoCoordinatesIsRejected) {
  EXPECT_THAT(invalid_message("v 0 0\n", Format::Obj, "s.obj"), HasSubstr("s.obj:1:"));
}

TEST(ReadObj, FaceWithTwoVerticesIsRejected) {
  EXPECT_THAT(invalid_message("v 0 0 0\nv 1 1 1\nf 1 2\n", Format::Obj, "s.obj"),
              HasSubstr("s.obj:3:"));
}

// ---------------------------------------------------------------------------------------
// OFF

TEST(ReadOff, ReadsCommentsBlankLinesAndColours) {
  const MeshFile f = read_text(
      "OFF\n# a comment\n\n4 2 0\n0 0 0\n1 0 0\n1 1 0 # trailing\n0 1 0\n"
      "4 0 1 2 3 255 0 0\n3 0 1 2\n",
      Format::Off);
  EXPECT_EQ(f.format, "off");
  EXPECT_EQ(f.points.rows(), 4);
  ASSERT_EQ(f.quads.size(), 1u);
  EXPECT_EQ(f.quads[0], quad(0, 1, 2, 3));
  EXPECT_EQ(f.quad_lines[0], 9u);
  EXPECT_EQ(f.triangles, 1u);
}

TEST(ReadOff, AcceptsCountsOnTheHeaderLineWithoutEdgeCount) {
  const MeshFile f = read_text("OFF 4 1\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 3 2 1 0\n", Format::Off);
  ASSERT_EQ(f.quads.size(), 1u);
  EXPECT_EQ(f.quads[0], quad(3, 2, 1, 0));
}

TEST(ReadOff, TruncatedFileIsReported) {
  EXPECT_THAT(
      invalid_message("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1\n", Format::Off, "s.off"),
      HasSubstr("unexpected end of file"));
}

TEST(ReadOff, HugeCountDoesNotAllocate) {
  EXPECT_THAT(invalid_message("OFF\n99999999 1 0\n0 0 0\n", Format::Off, "s.off"),
              HasSubstr("s.off:2:"));
}

TEST(ReadOff, FaceIndexOutOfRangeNamesTheLine) {
  EXPECT_THAT(invalid_message("OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1 7\n", Format::Off, "s.off"),
              HasSubstr("s.off:6:"));
}

TEST(ReadOff, WrongHeaderIsRejected) {
  EXPECT_THAT(invalid_message("PLY\n", Format::Off, "s.off"), HasSubstr("s.off:1:"));
}

// ---------------------------------------------------------------------------------------
// Legacy VTK

const std::string kVtkCubePoints =
    "POINTS 8 float\n0 0 0 1 0 0 1 1 0 0 1 0\n0 0 1 1 0 1 1 1 1 0 1 1\n";

std::string vtk_header(const std::string& dataset = "UNSTRUCTURED_GRID") {
  return "# vtk DataFile Version 3.0\ntitle\nASCII\nDATASET " + dataset + "\n";
}

TEST(ReadVtk, ReadsClassicCellsAndStopsAtCellData) {
  const MeshFile f = read_text(vtk_header() + kVtkCubePoints +
                                   "CELLS 2 14\n8 0 1 2 3 4 5 6 7\n4 0 1 2 3\n"
                                   "CELL_TYPES 2\n12\n9\nCELL_DATA 2\nSCALARS a float 1\n"
                                   "LOOKUP_TABLE default\n1 2\n",
                               Format::Vtk);
  EXPECT_EQ(f.format, "vtk");
  ASSERT_EQ(f.hexes.size(), 1u);
  EXPECT_EQ(f.hexes[0], hex({0, 1, 2, 3, 4, 5, 6, 7}));
  ASSERT_EQ(f.quads.size(), 1u);
  EXPECT_EQ(f.quad_lines[0], 10u);
}

TEST(ReadVtk, ReadsVtk51OffsetsConnectivityLayout) {
  const MeshFile f = read_text(
      "# vtk DataFile Version 5.1\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\n" + kVtkCubePoints +
          "CELLS 3 12\nOFFSETS vtktypeint64\n0 8 12\nCONNECTIVITY vtktypeint64\n"
          "0 1 2 3 4 5 6 7\n4 5 6 7\nCELL_TYPES 2\n12\n9\n",
      Format::Vtk);
  ASSERT_EQ(f.hexes.size(), 1u);
  EXPECT_EQ(f.hexes[0], hex({0, 1, 2, 3, 4, 5, 6, 7}));
  ASSERT_EQ(f.quads.size(), 1u);
  EXPECT_EQ(f.quads[0], quad(4, 5, 6, 7));
  EXPECT_EQ(f.quad_lines[0], 13u);
}

TEST(ReadVtk, ReadsPolydataPolygons) {
  const MeshFile f = read_text(
      vtk_header("POLYDATA") + kVtkCubePoints + "POLYGONS 3 14\n4 0 3 2 1\n4 4 5 6 7\n3 0 1 5\n",
      Format::Vtk);
  ASSERT_EQ(f.quads.size(), 2u);
  EXPECT_EQ(f.quads[0], quad(0, 3, 2, 1));
  EXPECT_EQ(f.triangles, 1u);
  EXPECT_TRUE(f.hexes.empty());
}

TEST(ReadVtk, EightNodeCellLabelledTetIsAHexWithANote) {
  const MeshFile f =
      read_text(vtk_header() + kVtkCubePoints + "CELLS 1 9\n8 0 1 2 3 4 5 6 7\nCELL_TYPES 1\n10\n",
                Format::Vtk);
  ASSERT_EQ(f.hexes.size(), 1u);
  EXPECT_EQ(f.tetrahedra, 0u);
  ASSERT_EQ(f.notes.size(), 1u);
  EXPECT_THAT(f.notes[0], HasSubstr("VTK_TETRA (10)"));
  EXPECT_THAT(f.notes[0], HasSubstr("line 9"));
}

TEST(ReadVtk, FourNodeTetStaysATet) {
  const MeshFile f = read_text(
      vtk_header() + kVtkCubePoints + "CELLS 1 5\n4 0 1 2 4\nCELL_TYPES 1\n10\n", Format::Vtk);
  EXPECT_EQ(f.tetrahedra, 1u);
  EXPECT_TRUE(f.hexes.empty());
}

TEST(ReadVtk, VoxelIsReorderedToHexOrder) {
  // Voxel order is lexicographic: x + 2y + 4z.
  const MeshFile f =
      read_text(vtk_header() + kVtkCubePoints + "CELLS 1 9\n8 0 1 3 2 4 5 7 6\nCELL_TYPES 1\n11\n",
                Format::Vtk);
  ASSERT_EQ(f.hexes.size(), 1u);
  EXPECT_EQ(f.hexes[0], hex({0, 1, 2, 3, 4, 5, 6, 7}));
}

TEST(ReadVtk, TriquadraticHexKeepsItsCorners) {
  std::string conn = "27";
  for (int i = 0; i < 27; ++i) conn += " " + std::to_string(i < 8 ? 7 - i : i % 8);
  const MeshFile f = read_text(
      vtk_header() + kVtkCubePoints + "CELLS 1 28\n" + conn + "\nCELL_TYPES 1\n29\n", Format::Vtk);
  ASSERT_EQ(f.hexes.size(), 1u);
  EXPECT_EQ(f.hexes[0], hex({7, 6, 5, 4, 3, 2, 1, 0}));
}

TEST(ReadVtk, BinaryIsRejectedClearly) {
  const std::string m = invalid_message(
      "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\n", Format::Vtk, "b.vtk");
  EXPECT_THAT(m, HasSubstr("b.vtk:3:"));
  EXPECT_THAT(m, HasSubstr("binary"));
  EXPECT_THAT(m, HasSubstr("ASCII"));
}

TEST(ReadVtk, PointIndexOutOfRangeNamesLineAndCell) {
  const std::string m = invalid_message(vtk_header() + kVtkCubePoints +
                                            "CELLS 2 14\n4 0 1 2 3\n8 0 1 2 3 4 5 6 8\n"
                                            "CELL_TYPES 2\n9\n12\n",
                                        Format::Vtk, "b.vtk");
  EXPECT_THAT(m, HasSubstr("b.vtk:10:"));
  EXPECT_THAT(m, HasSubstr("cell 1"));
  EXPECT_THAT(m, HasSubstr("point 8"));
}

TEST(ReadVtk, TruncatedPointsAreReported) {
  const std::string m =
      invalid_message(vtk_header() + "POINTS 8 float\n0 0 0 1 0 0\n", Format::Vtk, "b.vtk");
  EXPECT_THAT(m, HasSubstr("b.vtk:5:"));
  EXPECT_THAT(m, HasSubstr("truncated"));
}

TEST(ReadVtk, CellTypeCountMismatchIsReported) {
  EXPECT_THAT(invalid_message(vtk_header() + kVtkCubePoints +
                                  "CELLS 1 9\n8 0 1 2 3 4 5 6 7\nCELL_TYPES 2\n12 12\n",
                              Format::Vtk, "b.vtk"),
              HasSubstr("b.vtk:10: CELL_TYPES lists 2 types but CELLS has 1"));
}

TEST(ReadVtk, HexWithTooFewPointsIsReported) {
  EXPECT_THAT(
      invalid_message(vtk_header() + kVtkCubePoints + "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n12\n",
                      Format::Vtk, "b.vtk"),
      HasSubstr("b.vtk:9: cell 0 of type 12 has 4 points"));
}

TEST(ReadVtk, NotAVtkFileIsRejected) {
  EXPECT_THAT(invalid_message("hello\n", Format::Vtk, "b.vtk"), HasSubstr("b.vtk:1:"));
}

// ---------------------------------------------------------------------------------------
// VTU

TEST(ReadVtu, ReadsAsciiUnstructuredGrid) {
  const MeshFile f = read_text(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n"
      "<Piece NumberOfPoints=\"8\" NumberOfCells=\"1\">\n<Points>\n"
      "<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">\n"
      "0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1</DataArray>\n</Points>\n<Cells>\n"
      "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 4 5 6 7"
      "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">8</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">12</DataArray>\n</Cells>\n"
      "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n",
      Format::Vtu);
  EXPECT_EQ(f.format, "vtu");
  ASSERT_EQ(f.hexes.size(), 1u);
  EXPECT_EQ(f.points(6, 0), 1.0);
}

TEST(ReadVtu, BinaryDataIsRejectedClearly) {
  const std::string m = invalid_message(
      "<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n"
      "<Piece NumberOfPoints=\"1\" NumberOfCells=\"0\">\n<Points>\n"
      "<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"binary\">AAAA"
      "</DataArray>\n</Points>\n<Cells></Cells></Piece></UnstructuredGrid></VTKFile>\n",
      Format::Vtu, "b.vtu");
  EXPECT_THAT(m, HasSubstr("b.vtu:5:"));
  EXPECT_THAT(m, HasSubstr("ASCII"));
}

// ---------------------------------------------------------------------------------------
// Gmsh MSH

TEST(ReadMsh, Reads22WithSparseTagsAndSkipsPointsAndLines) {
  const MeshFile f = read_text(
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"s\"\n$EndPhysicalNames\n"
      "$Nodes\n4\n10 0 0 0\n20 1 0 0\n30 1 1 0\n40 0 1 0\n$EndNodes\n"
      "$Elements\n3\n1 15 2 0 1 10\n2 1 2 0 1 10 20\n7 3 2 1 1 10 20 30 40\n$EndElements\n",
      Format::Msh);
  EXPECT_EQ(f.format, "msh2");
  ASSERT_EQ(f.quads.size(), 1u);
  EXPECT_EQ(f.quads[0], quad(0, 1, 2, 3));
  EXPECT_EQ(f.quad_lines[0], 19u);
  EXPECT_EQ(f.other_cells, 0u);
}

TEST(ReadMsh, SecondOrderHexKeepsItsCorners) {
  std::string nodes;
  for (int i = 1; i <= 27; ++i) nodes += std::to_string(i) + " " + std::to_string(i) + " 0 0\n";
  std::string hex27 = "1 12 2 0 1";
  for (int i = 1; i <= 27; ++i) hex27 += " " + std::to_string(i);
  const MeshFile f = read_text("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n27\n" + nodes +
                                   "$EndNodes\n$Elements\n1\n" + hex27 + "\n$EndElements\n",
                               Format::Msh2);
  ASSERT_EQ(f.hexes.size(), 1u);
  EXPECT_EQ(f.hexes[0], hex({0, 1, 2, 3, 4, 5, 6, 7}));
}

TEST(ReadMsh, Reads41WithParametricNodes) {
  const MeshFile f = read_text(
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
      "$Entities\n0 0 1 0\n1 0 0 0 1 1 0 0 0\n$EndEntities\n"
      "$Nodes\n2 4 1 4\n0 1 0 1\n1\n0 0 0\n2 1 1 3\n2\n3\n4\n1 0 0 0.5 0.5\n1 1 0 0.5 0.6\n"
      "0 1 0 0.1 0.2\n$EndNodes\n"
      "$Elements\n2 2 1 2\n0 1 15 1\n1 1\n2 1 3 1\n2 1 2 3 4\n$EndElements\n",
      Format::Msh);
  EXPECT_EQ(f.format, "msh4");
  ASSERT_EQ(f.points.rows(), 4);
  EXPECT_EQ(f.points(2, 1), 1.0);
  EXPECT_EQ(f.points(3, 0), 0.0);
  ASSERT_EQ(f.quads.size(), 1u);
  EXPECT_EQ(f.quads[0], quad(0, 1, 2, 3));
  EXPECT_EQ(f.quad_lines[0], 26u);
}

TEST(ReadMsh, HugeSparseNodeTagsAreMapped) {
  const MeshFile f = read_text(
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n900000000000 1 0 0\n"
      "7 1 1 0\n3000000 0 1 0\n$EndNodes\n$Elements\n1\n1 3 2 0 1 1 900000000000 7 3000000\n"
      "$EndElements\n",
      Format::Msh);
  ASSERT_EQ(f.quads.size(), 1u);
  EXPECT_EQ(f.quads[0], quad(0, 1, 2, 3));
}

TEST(ReadMsh, BinaryIsRejectedClearly) {
  const std::string m =
      invalid_message("$MeshFormat\n4.1 1 8\n$EndMeshFormat\n", Format::Msh, "b.msh");
  EXPECT_THAT(m, HasSubstr("b.msh:2:"));
  EXPECT_THAT(m, HasSubstr("ASCII"));
}

TEST(ReadMsh, UnknownNodeTagNamesLineAndElement) {
  const std::string m = invalid_message(
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 1 1 0\n$EndNodes\n"
      "$Elements\n1\n42 3 2 0 1 1 2 3 4\n$EndElements\n",
      Format::Msh, "b.msh");
  EXPECT_THAT(m, HasSubstr("b.msh:12:"));
  EXPECT_THAT(m, HasSubstr("element tag 42"));
  EXPECT_THAT(m, HasSubstr("node 4"));
}

TEST(ReadMsh, CountMismatchIsReported) {
  EXPECT_THAT(invalid_message("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n2 1 0 "
                              "0\n$EndNodes\n",
                              Format::Msh, "b.msh"),
              HasSubstr("b.msh:7: expected $EndNodes"));
}

TEST(ReadMsh, DuplicateNodeTagIsReported) {
  EXPECT_THAT(invalid_message("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n1 1 0 "
                              "0\n$EndNodes\n",
                              Format::Msh, "b.msh"),
              HasSubstr("b.msh:7: node tag 1 is defined twice"));
}

// ---------------------------------------------------------------------------------------
// MEDIT

const std::string kMeditCube =
    "MeshVersionFormatted 2\n# comment\nDimension\n3\nVertices\n8\n0 0 0 0\n1 0 0 0\n1 1 0 0\n"
    "0 1 0 0\n0 0 1 0\n1 0 1 0\n1 1 1 0\n0 1 1 0\n";

TEST(ReadMedit, ReadsVerticesQuadrilateralsHexahedraAndSkipsOthers) {
  const MeshFile f = read_text(kMeditCube +
                                   "Corners\n1\n1\nEdges\n1\n1 2 0\nQuadrilaterals\n1\n1 4 3 2 "
                                   "7\nHexahedra\n1\n1 2 3 4 5 6 7 8 0\nTriangles\n1\n1 2 3 0\n"
                                   "End\n",
                               Format::Medit);
  EXPECT_EQ(f.format, "medit");
  ASSERT_EQ(f.quads.size(), 1u);
  EXPECT_EQ(f.quads[0], quad(0, 3, 2, 1));
  EXPECT_EQ(f.quad_lines[0], 23u);
  ASSERT_EQ(f.hexes.size(), 1u);
  EXPECT_EQ(f.hexes[0], hex({0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(f.triangles, 1u);
  EXPECT_TRUE(f.notes.empty());
}

TEST(ReadMedit, ReadsNonStandardQuadsKeywordWithANote) {
  const MeshFile f = read_text(kMeditCube + "Quads\n1\n1 2 3 4 0\nEnd\n", Format::Medit);
  ASSERT_EQ(f.quads.size(), 1u);
  ASSERT_EQ(f.notes.size(), 1u);
  EXPECT_THAT(f.notes[0], HasSubstr("Quads"));
}

TEST(ReadMedit, UnknownKeywordNamesTheLine) {
  EXPECT_THAT(invalid_message(kMeditCube + "Blocks\n1\n", Format::Medit, "b.mesh"),
              HasSubstr("b.mesh:15: unknown MEDIT keyword 'Blocks'"));
}

TEST(ReadMedit, VertexOutOfRangeNamesLineAndElement) {
  const std::string m = invalid_message(kMeditCube + "Hexahedra\n1\n1 2 3 4 5 6 7 9 0\nEnd\n",
                                        Format::Medit, "b.mesh");
  EXPECT_THAT(m, HasSubstr("b.mesh:17:"));
  EXPECT_THAT(m, HasSubstr("hexahedron (element 1)"));
  EXPECT_THAT(m, HasSubstr("node 9"));
}

TEST(ReadMedit, TruncatedElementsAreReported) {
  EXPECT_THAT(invalid_message(kMeditCube + "Hexahedra\n2\n1 2 3 4 5 6 7 8 0\n1 2 3\n",
                              Format::Medit, "b.mesh"),
              HasSubstr("truncated"));
}

// ---------------------------------------------------------------------------------------
// MFEM

const std::string kMfemHex =
    "MFEM mesh v1.0\n\n# comment\ndimension\n3\n\nelements\n1\n1 5 0 1 2 3 4 5 6 7\n\n"
    "boundary\n1\n1 3 0 3 2 1\n\nvertices\n8\n3\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
    "0 0 1\n1 0 1\n1 1 1\n0 1 1\n";

TEST(ReadMfem, ReadsHexesAndSkipsTheBoundary) {
  const MeshFile f = read_text(kMfemHex, Format::Mfem);
  EXPECT_EQ(f.format, "mfem");
  ASSERT_EQ(f.hexes.size(), 1u);
  EXPECT_EQ(f.hexes[0], hex({0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_TRUE(f.quads.empty());
  EXPECT_EQ(f.points(6, 2), 1.0);
}

TEST(ReadMfem, DetectedByContentWhateverTheFormatAsked) {
  const MeshFile f = read_text(kMfemHex, Format::Medit);
  EXPECT_EQ(f.format, "mfem");
  EXPECT_EQ(f.hexes.size(), 1u);
}

const std::string kMfemCurvedQuads =
    "MFEM mesh v1.0\ndimension\n2\nelements\n1\n1 3 0 1 2 3\nboundary\n0\nvertices\n4\n\n"
    "nodes\nFiniteElementSpace\nFiniteElementCollection: H1_2D_P2\nVDim: 3\n";

TEST(ReadMfem, CurvedNodesByVdimGiveTheVertices) {
  // 9 dofs of a P2 quad, byVDIM: the 4 vertices first.
  const MeshFile f = read_text(kMfemCurvedQuads +
                                   "Ordering: 1\n\n0 0 0\n1 0 0\n1 1 0\n0 1 5\n"
                                   "9 9 9\n9 9 9\n9 9 9\n9 9 9\n9 9 9\n",
                               Format::Mfem);
  ASSERT_EQ(f.quads.size(), 1u);
  ASSERT_EQ(f.points.rows(), 4);
  EXPECT_EQ(f.points(3, 2), 5.0);
  EXPECT_EQ(f.points(2, 0), 1.0);
}

TEST(ReadMfem, CurvedNodesByNodesGiveTheVertices) {
  const MeshFile f = read_text(kMfemCurvedQuads +
                                   "Ordering: 0\n\n0 1 1 0 9 9 9 9 9\n0 0 1 1 9 9 9 9 9\n"
                                   "0 0 0 5 9 9 9 9 9\n",
                               Format::Mfem);
  ASSERT_EQ(f.points.rows(), 4);
  EXPECT_EQ(f.points(1, 0), 1.0);
  EXPECT_EQ(f.points(2, 1), 1.0);
  EXPECT_EQ(f.points(3, 2), 5.0);
}

TEST(ReadMfem, DiscontinuousNodesAreRejectedClearly) {
  const std::string m = invalid_message(
      "MFEM mesh v1.0\ndimension\n2\nelements\n1\n1 3 0 1 2 3\nboundary\n0\nvertices\n4\n\n"
      "nodes\nFiniteElementSpace\nFiniteElementCollection: L2_T1_2D_P1\nVDim: 3\nOrdering: 1\n"
      "0 0 0\n",
      Format::Mfem, "b.mesh");
  EXPECT_THAT(m, HasSubstr("b.mesh:14:"));
  EXPECT_THAT(m, HasSubstr("H1"));
}

TEST(ReadMfem, VertexOutOfRangeNamesLineAndElement) {
  std::string text = kMfemHex;
  text.replace(text.find("1 5 0 1 2 3 4 5 6 7"), 19, "1 5 0 1 2 3 4 5 6 8");
  const std::string m = invalid_message(text, Format::Mfem, "b.mesh");
  EXPECT_THAT(m, HasSubstr("b.mesh:9:"));
  EXPECT_THAT(m, HasSubstr("node 8"));
}

TEST(ReadMfem, UnknownGeometryIsRejected) {
  std::string text = kMfemHex;
  text.replace(text.find("1 5 0 1 2"), 3, "1 9");
  EXPECT_THAT(invalid_message(text, Format::Mfem, "b.mesh"), HasSubstr("b.mesh:9:"));
}

// ---------------------------------------------------------------------------------------
// Abaqus INP

TEST(ReadInp, ReadsNodesAndContinuedElementLines) {
  const MeshFile f = read_text(
      "*Heading\n t\n** comment\n*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n"
      "5, 0, 0, 1\n6, 1, 0, 1\n7, 1, 1, 1\n8, 0, 1, 1\n*ELEMENT, TYPE=C3D8R, ELSET=V\n"
      "1, 1, 2, 3, 4,\n5, 6, 7, 8\n*ELEMENT, type=S4R\n2, 1, 4, 3, 2\n",
      Format::Inp);
  EXPECT_EQ(f.format, "inp");
  ASSERT_EQ(f.hexes.size(), 1u);
  EXPECT_EQ(f.hexes[0], hex({0, 1, 2, 3, 4, 5, 6, 7}));
  ASSERT_EQ(f.quads.size(), 1u);
  EXPECT_EQ(f.quads[0], quad(0, 3, 2, 1));
  EXPECT_EQ(f.quad_lines[0], 17u);
}

TEST(ReadInp, UnknownNodeNamesTheLine) {
  EXPECT_THAT(invalid_message("*NODE\n1, 0, 0, 0\n*ELEMENT, TYPE=S4\n1, 1, 1, 1, 2\n", Format::Inp,
                              "b.inp"),
              HasSubstr("b.inp:4:"));
}

// ---------------------------------------------------------------------------------------
// Files

TEST(ReadStream, AutoRecognisesTheContent) {
  EXPECT_EQ(read_text(vtk_header() + kVtkCubePoints, Format::Auto).format, "vtk");
  EXPECT_EQ(read_text("OFF\n0 0 0\n", Format::Auto).format, "off");
  EXPECT_THROW((void)read_text("v 0 0 0\n", Format::Auto), InvalidInput);
}

TEST_F(IoFiles, ReadMissingFileIsAnIoError) {
  EXPECT_THROW((void)read_mesh(dir_ / "missing.obj"), IoError);
}

TEST_F(IoFiles, EmptyFileIsInvalidInput) {
  std::ofstream(dir_ / "empty.obj").close();
  EXPECT_THROW((void)read_mesh(dir_ / "empty.obj"), InvalidInput);
}

TEST_F(IoFiles, MfemContentWinsOverTheExtension) {
  std::ofstream(dir_ / "cube.vtk") << kMfemHex;
  const MeshFile f = read_mesh(dir_ / "cube.vtk");
  EXPECT_EQ(f.format, "mfem");
  EXPECT_EQ(f.hexes.size(), 1u);
  EXPECT_EQ(f.path, (dir_ / "cube.vtk").string());
}

TEST_F(IoFiles, UnknownExtensionIsRecognisedByContent) {
  std::ofstream(dir_ / "cube.txt")
      << vtk_header() << kVtkCubePoints << "CELLS 1 9\n8 0 1 2 3 4 5 6 7\nCELL_TYPES 1\n12\n";
  EXPECT_EQ(read_mesh(dir_ / "cube.txt").hexes.size(), 1u);
}

// ---------------------------------------------------------------------------------------
// Writers

/// Every hex format, round-tripped through a file.
class HexRoundTrip : public IoFiles, public ::testing::WithParamInterface<Format> {};

TEST_P(HexRoundTrip, WriteThenReadGivesTheSameMesh) {
  const auto mesh = stcweave::test::box_hexes(2, 3, 4, 0.1, 1.0 / 3.0, 2.5);
  const std::string name = "box." + std::string(stcweave::primal::format_name(GetParam()));
  const fs::path path = dir_ / name;
  stcweave::primal::write_hex_mesh(mesh, path, GetParam());
  const MeshFile f = read_mesh(path, GetParam() == Format::Msh2 ? Format::Msh : GetParam());
  ASSERT_EQ(f.points.rows(), mesh.points.rows());
  EXPECT_TRUE(f.points == mesh.points) << "coordinates must round-trip exactly";
  EXPECT_EQ(f.hexes, mesh.complex.hexes);
  EXPECT_TRUE(f.quads.empty());
  EXPECT_TRUE(f.notes.empty());
}

TEST_P(HexRoundTrip, OutputIsDeterministic) {
  const auto mesh = stcweave::test::box_hexes(2, 1, 1, 0.1, 0.2, 0.3);
  stcweave::primal::write_hex_mesh(mesh, dir_ / "a.out", GetParam());
  stcweave::primal::write_hex_mesh(mesh, dir_ / "b.out", GetParam());
  EXPECT_EQ(slurp(dir_ / "a.out"), slurp(dir_ / "b.out"));
  EXPECT_FALSE(slurp(dir_ / "a.out").empty());
}

INSTANTIATE_TEST_SUITE_P(AllHexFormats, HexRoundTrip,
                         ::testing::Values(Format::Vtk, Format::Vtu, Format::Msh, Format::Msh2,
                                           Format::Medit, Format::Inp),
                         [](const auto& info) {
                           return std::string(stcweave::primal::format_name(info.param));
                         });

TEST_F(IoFiles, MshExtensionWritesMsh41AndMsh2Writes22) {
  const auto mesh = stcweave::test::box_hexes(1, 1, 1);
  stcweave::primal::write_hex_mesh(mesh, dir_ / "a.msh");
  stcweave::primal::write_hex_mesh(mesh, dir_ / "b.msh", Format::Msh2);
  EXPECT_EQ(read_mesh(dir_ / "a.msh").format, "msh4");
  EXPECT_EQ(read_mesh(dir_ / "b.msh").format, "msh2");
}

/// Every surface format, round-tripped through a file.
class SurfaceRoundTrip : public IoFiles, public ::testing::WithParamInterface<Format> {};

TEST_P(SurfaceRoundTrip, WriteThenReadGivesTheSameSurface) {
  const auto mesh = stcweave::test::box_surface(2, 2, 3, 0.7, 1.1, 1e-3);
  const fs::path path = dir_ / ("box." + std::string(stcweave::primal::format_name(GetParam())));
  stcweave::primal::write_surface(mesh, path);
  const MeshFile f = read_mesh(path);
  EXPECT_TRUE(f.points == mesh.points);
  EXPECT_EQ(f.quads, mesh.surface.quads);
  EXPECT_EQ(f.quad_lines.size(), f.quads.size());
  EXPECT_GT(f.quad_lines.at(0), 0u);
  EXPECT_TRUE(f.hexes.empty());
}

INSTANTIATE_TEST_SUITE_P(AllSurfaceFormats, SurfaceRoundTrip,
                         ::testing::Values(Format::Obj, Format::Off, Format::Vtk),
                         [](const auto& info) {
                           return std::string(stcweave::primal::format_name(info.param));
                         });

TEST_F(IoFiles, WriteLeavesNoTemporaryFile) {
  stcweave::primal::write_hex_mesh(stcweave::test::box_hexes(1, 1, 1), dir_ / "a.vtk");
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir_)) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "a.vtk");
  }
  EXPECT_EQ(files, 1u);
}

TEST_F(IoFiles, WriteIntoMissingFolderIsAnIoError) {
  EXPECT_THROW(stcweave::primal::write_hex_mesh(stcweave::test::box_hexes(1, 1, 1),
                                                dir_ / "no" / "such" / "a.vtk"),
               IoError);
}

TEST_F(IoFiles, FailedWriteKeepsThePreviousFile) {
  const fs::path path = dir_ / "a.vtk";
  stcweave::primal::write_hex_mesh(stcweave::test::box_hexes(1, 1, 1), path);
  const std::string before = slurp(path);
  auto bad = stcweave::test::box_hexes(2, 1, 1);
  bad.complex.hexes[1][7] = NodeId(999);
  EXPECT_THROW(stcweave::primal::write_hex_mesh(bad, path), InvalidInput);
  EXPECT_EQ(slurp(path), before);
}

TEST_F(IoFiles, HexMeshCannotBeWrittenAsObj) {
  EXPECT_THROW(stcweave::primal::write_hex_mesh(stcweave::test::box_hexes(1, 1, 1), dir_ / "a.obj"),
               InvalidInput);
}

TEST_F(IoFiles, SurfaceCannotBeWrittenAsVtu) {
  EXPECT_THROW(
      stcweave::primal::write_surface(stcweave::test::box_surface(1, 1, 1), dir_ / "a.vtu"),
      InvalidInput);
}

TEST_F(IoFiles, WrittenVtkUsesHexCellType12) {
  stcweave::primal::write_hex_mesh(stcweave::test::box_hexes(1, 1, 1), dir_ / "a.vtk");
  const std::string text = slurp(dir_ / "a.vtk");
  EXPECT_THAT(text, HasSubstr("CELLS 1 9\n8 0 1 3 2 4 5 7 6\nCELL_TYPES 1\n12\n"));
}

TEST_F(IoFiles, WrittenInpIsOneBasedC3D8) {
  stcweave::primal::write_hex_mesh(stcweave::test::box_hexes(1, 1, 1), dir_ / "a.inp");
  EXPECT_THAT(slurp(dir_ / "a.inp"),
              HasSubstr("*ELEMENT, TYPE=C3D8, ELSET=Volume1\n1, 1, 2, 4, 3, 5, 6, 8, 7\n"));
}

}  // namespace
