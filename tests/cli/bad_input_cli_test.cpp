// Inputs a fuzzing pass found mishandled: coordinates beyond the arithmetic's range (a crash
// in Gmsh's Delaunay at 1e64), NaN hex nodes reported as valid, duplicated hexes, a UTF-8
// byte-order mark, NaN option values, cells of other kinds named without a line. Each must end with
// exit code 1 or 2 and a message saying what and where, or, for the byte-order mark, be read as if
// it were not there. A second pass (2026-12-07, about 5,400 runs over 12 formats and 38 options)
// found NaN interior nodes written with exit code 0, negative and overflowing values taken by
// unsigned options, and (writers_test, diagnose_test) outputs replacing links, FIFOs and devices
// and a closed surface of two quads that kept the weave busy for minutes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/cli_run.hpp"

namespace {

namespace fs = std::filesystem;

using stcweave::test::CliRun;
using stcweave::test::slurp;
using ::testing::ContainsRegex;
using ::testing::HasSubstr;
using ::testing::Not;

CliRun run(const std::string& args) {
  return stcweave::test::run_cli(args);
}

class BadInputCli : public stcweave::test::CliTest {
 protected:
  BadInputCli() : CliTest("stcweave_bad_input_") {}

  /// The generated 2 x 2 x 2 box surface with every coordinate multiplied by `factor`.
  fs::path scaled_box(double factor, const std::string& name) {
    const fs::path box = dir_ / "box.obj";
    if (!fs::exists(box)) EXPECT_EQ(run("generate box 2 2 2 -q -o " + box.string()).code, 0);
    std::istringstream in(slurp(box));
    std::ofstream out(dir_ / name);
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("v ", 0) == 0) {
        double x = 0, y = 0, z = 0;
        std::istringstream(line.substr(2)) >> x >> y >> z;
        std::array<char, 128> buf{};
        std::snprintf(buf.data(), buf.size(), "v %.17g %.17g %.17g", x * factor, y * factor,
                      z * factor);
        out << buf.data() << "\n";
      } else {
        out << line << "\n";
      }
    }
    return dir_ / name;
  }

  /// The generated 2 x 2 x 2 box surface with its node line `from` (e.g. "v 1 2 2") replaced
  /// by `to`; the line must be there once.
  fs::path box_with_node_moved(const std::string& from, const std::string& to,
                               const std::string& name) {
    std::istringstream in(slurp(scaled_box(1.0, "box1.obj")));
    std::ofstream out(dir_ / name);
    std::string line;
    int moved = 0;
    while (std::getline(in, line)) {
      if (line == from) {
        line = to;
        ++moved;
      }
      out << line << "\n";
    }
    EXPECT_EQ(moved, 1) << from;
    return dir_ / name;
  }

  /// One unit hex (VTK legacy), node 0 at `first`, `copies` times the same cell.
  fs::path hex_file(const std::string& first, int copies, const std::string& name) {
    std::ofstream out(dir_ / name);
    out << "# vtk DataFile Version 3.0\nhex\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 double\n"
        << first << "\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
        << "CELLS " << copies << " " << 9 * copies << "\n";
    for (int i = 0; i < copies; ++i) out << "8 0 1 3 2 4 5 7 6\n";
    out << "CELL_TYPES " << copies << "\n";
    for (int i = 0; i < copies; ++i) out << "12\n";
    return dir_ / name;
  }
};

TEST_F(BadInputCli, CoordinatesBeyondTheRangeAreRefusedBeforeAnyStage) {
  const fs::path out = dir_ / "out.vtk";
  for (const double factor : {1e40, 1e70}) {
    const fs::path in = scaled_box(factor, "huge.obj");
    const CliRun r = run("mesh " + in.string() + " -o " + out.string());
    EXPECT_EQ(r.code, 2) << factor << r.out;
    EXPECT_THAT(r.out, HasSubstr("lie beyond the range")) << r.out;
    EXPECT_THAT(r.out, HasSubstr("rescale the model"));
    EXPECT_FALSE(fs::exists(out));
    EXPECT_THAT(run("loops " + in.string()).out, HasSubstr("weavable: no"));
  }
  const CliRun tiny = run("mesh " + scaled_box(1e-40, "tiny.obj").string() + " -o " + out.string());
  EXPECT_EQ(tiny.code, 2) << tiny.out;
  EXPECT_THAT(tiny.out, HasSubstr("bounding box is only"));
  const CliRun point = run("mesh " + scaled_box(0.0, "point.obj").string() + " -o " + out.string());
  EXPECT_EQ(point.code, 2) << point.out;
  EXPECT_THAT(point.out, HasSubstr("all its nodes coincide"));
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(BadInputCli, LargeAndSmallModelsInsideTheRangeAreMeshed) {
  for (const double factor : {1e20, 1e-20}) {
    const fs::path out = dir_ / "out.vtk";
    const CliRun r = run("mesh " + scaled_box(factor, "box_scaled.obj").string() + " -o " +
                         out.string() + " -q");
    EXPECT_EQ(r.code, 0) << factor << r.out;
    EXPECT_EQ(run("check " + out.string()).code, 0) << factor;
  }
}

TEST_F(BadInputCli, NonFiniteHexNodesAreRefusedByCheckAndQuality) {
  const fs::path bad = hex_file("nan 0 0", 1, "nan.vtk");
  for (const char* command : {"check ", "quality "}) {
    const CliRun r = run(command + bad.string());
    EXPECT_EQ(r.code, 2) << command << r.out;
    EXPECT_THAT(r.out, HasSubstr("non-finite coordinates"));
    EXPECT_THAT(r.out, HasSubstr("n0"));
  }
  // The same hex with finite coordinates passes both: the refusal is the NaN's.
  const fs::path good = hex_file("0 0 0", 1, "good.vtk");
  EXPECT_EQ(run("check " + good.string()).code, 0);
  EXPECT_EQ(run("quality " + good.string()).code, 0);
}

TEST_F(BadInputCli, DuplicatedHexesAreNamedBySheetsAndMesh) {
  const fs::path twice = hex_file("0 0 0", 2, "twice.vtk");
  const CliRun sheets = run("sheets " + twice.string());
  EXPECT_EQ(sheets.code, 2) << sheets.out;
  EXPECT_THAT(sheets.out, HasSubstr("the STC of this hex complex is undefined"));
  EXPECT_THAT(sheets.out, HasSubstr("h0+h1"));
  const CliRun mesh = run("mesh " + twice.string() + " -o " + (dir_ / "out.vtk").string());
  EXPECT_EQ(mesh.code, 2) << mesh.out;
  EXPECT_THAT(mesh.out, HasSubstr("have no boundary face (every face is shared by two or more"));
  EXPECT_EQ(run("sheets " + hex_file("0 0 0", 1, "once.vtk").string()).code, 0);
}

TEST_F(BadInputCli, AByteOrderMarkIsSkipped) {
  const fs::path box = scaled_box(1.0, "plain.obj");
  const fs::path marked = dir_ / "marked.obj";
  std::ofstream(marked, std::ios::binary) << "\xEF\xBB\xBF" << slurp(box);
  const CliRun plain = run("loops " + box.string() + " --json");
  const CliRun with_mark = run("loops " + marked.string() + " --json");
  ASSERT_EQ(plain.code, 0) << plain.out;
  ASSERT_EQ(with_mark.code, 0) << with_mark.out;
  const auto figures = [](const std::string& json) {
    auto j = nlohmann::json::parse(json);
    return std::to_string(j["nodes"].get<int>()) + " " + std::to_string(j["quads"].get<int>()) +
           " " + (j["weavable"].get<bool>() ? "weavable" : "not weavable");
  };
  EXPECT_EQ(figures(with_mark.out), figures(plain.out));
  EXPECT_EQ(figures(with_mark.out), "26 24 weavable");
  // With an extension that does not name the format, the content tells it, mark or not.
  const fs::path hex = hex_file("0 0 0", 1, "hex.vtk"), unnamed = dir_ / "hex.dat";
  std::ofstream(unnamed, std::ios::binary) << "\xEF\xBB\xBF" << slurp(hex);
  EXPECT_EQ(run("check " + unnamed.string()).code, 0) << run("check " + unnamed.string()).out;
}

TEST_F(BadInputCli, RealOptionsRefuseNaN) {
  const fs::path box = scaled_box(1.0, "box1.obj");
  for (const char* option : {"--position-theta", "--shape-target", "--good-start", "--sharp",
                             "--second-convex-min-weight", "--tet-growth"}) {
    const CliRun r =
        run("mesh " + box.string() + " -o " + (dir_ / "o.vtk").string() + " " + option + " nan");
    EXPECT_EQ(r.code, 1) << option << r.out;
    EXPECT_THAT(r.out, HasSubstr("must be a finite number")) << option;
  }
  // A number too large for a double is no finite number either (std::stod throws on it).
  const CliRun huge =
      run("mesh " + box.string() + " -o " + (dir_ / "o.vtk").string() + " --sharp 1e400");
  EXPECT_EQ(huge.code, 1) << huge.out;
  EXPECT_THAT(huge.out, HasSubstr("must be a finite number, not 1e400"));
}

TEST_F(BadInputCli, CountOptionsRefuseNegativeEmptyAndOverflowingValues) {
  // Found by fuzzing: CLI11 read "-1" into an unsigned option as its wrap-around, and an empty
  // or overflowing value without an error.
  const fs::path box = scaled_box(1.0, "box1.obj");
  for (const char* option :
       {"--max-rules", "--loop-moves-max", "--loop-moves-beam-depth", "--loop-moves-beam-width",
        "--loop-moves-evaluations", "--loop-moves-work", "--loop-moves-tiny-depth"}) {
    for (const char* value : {"-1", "''", "99999999999999999999", "1.5", "x"}) {
      const CliRun r = run("mesh " + box.string() + " -o " + (dir_ / "o.vtk").string() + " " +
                           option + " " + value);
      EXPECT_EQ(r.code, 1) << option << " " << value << r.out;
      EXPECT_THAT(r.out, HasSubstr("must be a whole number")) << option << " " << value;
    }
  }
  const CliRun ok =
      run("mesh " + box.string() + " -o " + (dir_ / "o.vtk").string() + " --max-rules 100000 -q");
  EXPECT_EQ(ok.code, 0) << ok.out;
}

TEST_F(BadInputCli, RealOptionsRefuseAnEmptyValue) {
  // Found by fuzzing: CLI11 read --sharp '' as 0, which the weave then refused as thresholds
  // out of order (exit code 2, naming a value the user never gave).
  const fs::path box = scaled_box(1.0, "box1.obj");
  for (const char* option : {"--position-theta", "--shape-target", "--sharp", "--tet-growth"}) {
    const CliRun r =
        run("mesh " + box.string() + " -o " + (dir_ / "o.vtk").string() + " " + option + " ''");
    EXPECT_EQ(r.code, 1) << option << r.out;
    EXPECT_THAT(r.out, HasSubstr("must be a number, not an empty value")) << option;
  }
}

TEST_F(BadInputCli, AnEmptyFormatNameIsRefusedByEveryCommand) {
  // Found by fuzzing: loops and sheets read --format '' as "from the extension", while mesh,
  // check, quality and view refused it.
  const fs::path box = scaled_box(1.0, "box1.obj");
  const fs::path hexes = dir_ / "o.vtk";
  ASSERT_EQ(run("mesh " + box.string() + " -o " + hexes.string() + " -q").code, 0);
  for (const std::string& command : {"loops " + box.string(), "sheets " + hexes.string(),
                                     "check " + hexes.string(), "quality " + hexes.string()}) {
    const CliRun r = run(command + " --format ''");
    EXPECT_EQ(r.code, 2) << command << r.out;
    EXPECT_THAT(r.out, HasSubstr("unknown mesh format ''")) << command;
    // "auto" (the default) guesses from the extension.
    const CliRun a = run(command + " --format auto");
    EXPECT_EQ(a.code, 0) << command << a.out;
  }
}

TEST_F(BadInputCli, AnUnknownCommandIsNamedWithTheCommandsThereAre) {
  const CliRun r = run("meshh x.obj");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_THAT(r.out, HasSubstr("unknown command 'meshh'"));
  EXPECT_THAT(r.out, HasSubstr("mesh, check, loops, sheets"));
  // Options before the command are still CLI11's (--version works, a command is required).
  EXPECT_EQ(run("--version").code, 0);
  EXPECT_EQ(run("").code, 1);
}

TEST_F(BadInputCli, ABoxWithANodePulledFarOutIsNeverWrittenWithCoordinatesThatAreNotFinite) {
  // Found by fuzzing: the 2 x 2 x 2 box with its node (1, 2, 2) moved to x = 1000 (a surface
  // folded through itself) was written with NaN interior nodes, exit code 0, "valid yes" and a
  // min scaled Jacobian of 1.8e308: the local untangling had kept a NaN try as untangled.
  box_with_node_moved("v 1 2 2", "v 1000 2 2", "pulled.obj");
  const CliRun r =
      run("mesh " + (dir_ / "pulled.obj").string() + " -o " + (dir_ / "pulled.vtk").string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, Not(HasSubstr("1.79769e+308"))) << r.out;
  EXPECT_THAT(r.out, Not(HasSubstr("mean inf"))) << r.out;
  // `quality` refuses a file with a coordinate that is not finite (exit code 2).
  const CliRun q = run("quality " + (dir_ / "pulled.vtk").string());
  EXPECT_EQ(q.code, 0) << q.out;
}

TEST_F(BadInputCli, ASurfaceThatPassesThroughItselfIsMeshedWithAWarningNamingTheQuads) {
  // The 2 x 2 x 2 box with the centre of its x = 0 face moved to x = 10: its quads pass
  // through the x = 2 face, so no solid has this boundary. `mesh` says so in a warning naming
  // a pair of quads by line (here without the untangling, which cannot help); `loops` counts
  // the pairs and prints the warning; the box as generated has none.
  box_with_node_moved("v 0 1 1", "v 10 1 1", "through.obj");
  const fs::path box = dir_ / "box1.obj";
  const std::string warning =
      "warning: " + (dir_ / "through.obj").string() + ": the surface passes through itself: ";
  const CliRun r = run("mesh " + (dir_ / "through.obj").string() + " -o " +
                       (dir_ / "through.vtk").string() + " --no-untangle");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("stcweave: " + warning)) << r.out;
  EXPECT_THAT(r.out, ContainsRegex("q[0-9]+ \\(line [0-9]+\\) crosses q[0-9]+ \\(line [0-9]+\\)"))
      << r.out;
  const CliRun l = run("loops " + (dir_ / "through.obj").string());
  EXPECT_EQ(l.code, 0) << l.out;
  EXPECT_THAT(l.out, ContainsRegex("quad pairs crossing each other: [1-9]")) << l.out;
  EXPECT_THAT(l.out, HasSubstr(warning)) << l.out;
  const CliRun b = run("loops " + box.string());
  EXPECT_THAT(b.out, HasSubstr("quad pairs crossing each other: 0\n")) << b.out;
  EXPECT_THAT(b.out, Not(HasSubstr("passes through itself"))) << b.out;
}

TEST_F(BadInputCli, AVtkPointsTypeThatIsNoNumberIsRefused) {
  const auto write = [&](const std::string& type) {
    fs::path file = dir_ / ("points_" + type + ".vtk");
    std::ofstream(file) << "# vtk DataFile Version 3.0\nhex\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                        << "POINTS 8 " << type
                        << "\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n"
                           "1 1 1\nCELLS 1 9\n8 0 1 3 2 4 5 7 6\nCELL_TYPES 1\n12\n";
    return file;
  };
  const CliRun r = run("check " + write("complex").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr(":5: POINTS data type 'complex' is not a VTK numeric type"));
  // Every numeric name VTK and its writers use is read (meshio's VTK 5.1 writes vtktype*).
  for (const char* type : {"float", "double", "int", "signed_char", "vtktypeint32", "vtktypeuint8",
                           "vtkIdType", "bit"})
    EXPECT_EQ(run("check " + write(type).string()).code, 0) << type;
}

TEST_F(BadInputCli, AnExtremeThresholdIsShownShortInTheMessage) {
  const CliRun r = run("mesh " + scaled_box(1.0, "b.obj").string() + " -o " +
                       (dir_ / "o.vtk").string() + " --sharp -1e308");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("sharp (-1e+308)"));
  EXPECT_LT(r.out.size(), 400U) << r.out;
}

TEST_F(BadInputCli, TheFirstCellOfAnotherKindIsNamedWithItsLine) {
  // A prism (MEDIT, which skipped them), a wedge (VTK), a pentagon among quads (OBJ), a C3D8
  // with 4 nodes (Abaqus).
  const fs::path vtk = dir_ / "wedge.vtk", obj = dir_ / "pentagon.obj", inp = dir_ / "short.inp";
  std::ofstream(vtk) << "# vtk DataFile Version 3.0\nw\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                        "POINTS 6 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 1\n0 1 1\n"
                        "CELLS 1 7\n6 0 1 2 3 4 5\nCELL_TYPES 1\n13\n";
  std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 2 0\nv 0 0 1\n"
                        "f 1 2 3 4\nf 1 2 3 5 4\n";
  std::ofstream(inp) << "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n"
                        "*ELEMENT, TYPE=C3D8\n1, 1, 2, 3, 4\n";
  const fs::path medit = dir_ / "prism.mesh";
  std::ofstream(medit) << "MeshVersionFormatted 2\nDimension 3\nVertices\n6\n0 0 0 0\n1 0 0 0\n"
                          "0 1 0 0\n0 0 1 0\n1 0 1 0\n0 1 1 0\nPrisms\n1\n1 2 3 4 5 6 0\nEnd\n";
  const std::vector<std::pair<fs::path, std::string>> cases = {
      {medit, "line 13: a prism (Prisms record 1)"},
      {vtk, "line 13: VTK cell type 13 with 6 nodes"},
      {obj, "line 8: a face with 5 nodes"},
      {inp, "line 7: element 1 of type C3D8 with 4 nodes"}};
  for (const auto& [file, named] : cases) {
    const CliRun r = run("mesh " + file.string() + " -o " + (dir_ / "out.vtk").string());
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_THAT(r.out, HasSubstr("the first other cell: " + named)) << r.out;
  }
}

}  // namespace
