// Hex writers against each format's own node-order convention, read back by a small
// independent parser of the written text (not by our readers), and round trips through our
// readers of a non-box mesh with a positive-volume check (a mirrored node order would give
// negative Jacobians after the round trip).
//
// The conventions (identical for 8-node hexes, research/geometry.md §1.1): VTK_HEXAHEDRON
// (12), Gmsh type 5 (reference element [-1,1]^3: node 1 (-1,-1,-1), 2 (1,-1,-1), 3 (1,1,-1),
// 4 (-1,1,-1), 5..8 the same at +1), MEDIT `Hexahedra`, Abaqus C3D8 (face 1-2-3-4, then
// 5-6-7-8 above it): the bottom face counter-clockwise seen from inside, node i+4 above node i.
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include "stcweave/primal/io.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

namespace fs = std::filesystem;

/// The reference corners of the common convention, as in Gmsh's [-1,1]^3 table.
const std::array<Eigen::Vector3d, 8> kReference = {
    Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, -1, -1), Eigen::Vector3d(1, 1, -1),
    Eigen::Vector3d(-1, 1, -1),  Eigen::Vector3d(-1, -1, 1), Eigen::Vector3d(1, -1, 1),
    Eigen::Vector3d(1, 1, 1),    Eigen::Vector3d(-1, 1, 1)};

/// One hex on the reference corners, with its node ids shuffled (so that an identity
/// numbering cannot hide an ordering mistake) and two unused nodes around.
HexMesh shuffled_reference_hex() {
  const std::array<int, 8> id = {5, 2, 9, 0, 3, 6, 1, 4};  // node id of corner i
  HexMesh m;
  m.points = Points::Constant(10, 3, 7.0);  // nodes 7 and 8 unused, far away
  stc::Hex h{};
  for (std::size_t i = 0; i < 8; ++i) {
    m.points.row(id[i]) = kReference[i].transpose();
    h[i] = NodeId(id[i]);
  }
  m.points.row(8) << 8.0, 8.0, 8.0;
  m.complex.hexes.push_back(h);
  m.complex.num_nodes = 10;
  return m;
}

/// What a minimal parser finds in a written file: node coordinates by the file's own node
/// label, and the element's node labels in the order written.
struct Parsed {
  std::map<long long, Eigen::Vector3d> nodes;
  std::vector<long long> element;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The text after the first line containing `key` (from `from`).
std::istringstream after(const std::string& text, const std::string& key, std::size_t from = 0) {
  const std::size_t at = text.find(key, from);
  EXPECT_NE(at, std::string::npos) << key;
  const std::size_t eol = text.find('\n', at);
  return std::istringstream(text.substr(eol + 1));
}

Parsed parse_written(const std::string& text, Format format) {
  Parsed p;
  long long n = 0;
  switch (format) {
    case Format::Vtk: {
      std::istringstream pts = after(text, "POINTS ");
      n = std::stoll(text.substr(text.find("POINTS ") + 7));
      for (long long i = 0; i < n; ++i) pts >> p.nodes[i].x() >> p.nodes[i].y() >> p.nodes[i].z();
      std::istringstream cells = after(text, "CELLS ");
      int count = 0;
      cells >> count;
      EXPECT_EQ(count, 8);
      p.element.resize(8);
      for (auto& v : p.element) cells >> v;
      EXPECT_NE(text.find("CELL_TYPES 1\n12\n"), std::string::npos);
      break;
    }
    case Format::Vtu: {
      std::istringstream pts = after(text, "<Points>");
      std::string line;
      std::getline(pts, line);  // the DataArray tag
      for (long long i = 0; i < 10; ++i) pts >> p.nodes[i].x() >> p.nodes[i].y() >> p.nodes[i].z();
      std::istringstream conn = after(text, "Name=\"connectivity\"");
      p.element.resize(8);
      for (auto& v : p.element) conn >> v;
      std::istringstream types = after(text, "Name=\"types\"");
      int type = 0;
      types >> type;
      EXPECT_EQ(type, 12);
      break;
    }
    case Format::Msh: {
      std::istringstream nodes = after(text, "$Nodes");
      long long blocks = 0, total = 0, lo = 0, hi = 0, dim = 0, tag = 0, param = 0, in_block = 0;
      nodes >> blocks >> total >> lo >> hi >> dim >> tag >> param >> in_block;
      std::vector<long long> tags(static_cast<std::size_t>(in_block));
      for (auto& t : tags) nodes >> t;
      for (long long t : tags) nodes >> p.nodes[t].x() >> p.nodes[t].y() >> p.nodes[t].z();
      std::istringstream elems = after(text, "$Elements");
      long long type = 0, count = 0, element_tag = 0;
      elems >> blocks >> total >> lo >> hi >> dim >> tag >> type >> count >> element_tag;
      EXPECT_EQ(type, 5);
      p.element.resize(8);
      for (auto& v : p.element) elems >> v;
      break;
    }
    case Format::Msh2: {
      std::istringstream nodes = after(text, "$Nodes");
      nodes >> n;
      for (long long i = 0; i < n; ++i) {
        long long t = 0;
        nodes >> t;
        nodes >> p.nodes[t].x() >> p.nodes[t].y() >> p.nodes[t].z();
      }
      std::istringstream elems = after(text, "$Elements");
      long long count = 0, tag = 0, type = 0, ntags = 0;
      elems >> count >> tag >> type >> ntags;
      EXPECT_EQ(type, 5);
      for (long long i = 0; i < ntags; ++i) elems >> tag;
      p.element.resize(8);
      for (auto& v : p.element) elems >> v;
      break;
    }
    case Format::Medit: {
      std::istringstream nodes = after(text, "Vertices");
      nodes >> n;
      for (long long i = 1; i <= n; ++i) {
        int ref = 0;
        nodes >> p.nodes[i].x() >> p.nodes[i].y() >> p.nodes[i].z() >> ref;
      }
      std::istringstream elems = after(text, "Hexahedra");
      long long count = 0;
      elems >> count;
      p.element.resize(8);
      for (auto& v : p.element) elems >> v;
      break;
    }
    case Format::Inp: {
      std::istringstream nodes = after(text, "*NODE");
      std::string line;
      while (std::getline(nodes, line) && line[0] != '*') {
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream l(line);
        long long t = 0;
        l >> t;
        l >> p.nodes[t].x() >> p.nodes[t].y() >> p.nodes[t].z();
      }
      EXPECT_NE(text.find("TYPE=C3D8"), std::string::npos);
      std::istringstream elems = after(text, "*ELEMENT");
      std::getline(elems, line);
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream l(line);
      long long tag = 0;
      l >> tag;
      p.element.resize(8);
      for (auto& v : p.element) l >> v;
      break;
    }
    default:
      ADD_FAILURE() << "no parser for this format";
  }
  return p;
}

class WriterConvention : public ::testing::TestWithParam<Format> {
 protected:
  void SetUp() override {
    std::random_device random;
    dir_ = fs::temp_directory_path() / ("stcweave_writers_test_" + std::to_string(random()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

TEST_P(WriterConvention, ElementListsTheCornersInTheFormatsOrder) {
  const HexMesh mesh = shuffled_reference_hex();
  const fs::path path = dir_ / "hex.out";
  write_hex_mesh(mesh, path, GetParam());
  const Parsed p = parse_written(slurp(path), GetParam());
  ASSERT_EQ(p.element.size(), 8u);
  for (std::size_t i = 0; i < 8; ++i) {
    ASSERT_EQ(p.nodes.count(p.element[i]), 1u) << "node label " << p.element[i];
    EXPECT_TRUE(p.nodes.at(p.element[i]).isApprox(kReference[i]))
        << "corner " << i << " of the element is at " << p.nodes.at(p.element[i]).transpose()
        << ", the convention puts it at " << kReference[i].transpose();
  }
}

TEST_P(WriterConvention, RoundTripKeepsEveryHexPositive) {
  // A curved, non-box mesh: a 3x2x2 box bent and sheared so that no hex is a box.
  HexMesh mesh = test::box_hexes(3, 2, 2);
  for (Eigen::Index v = 0; v < mesh.points.rows(); ++v) {
    const double x = mesh.points(v, 0), y = mesh.points(v, 1), z = mesh.points(v, 2);
    mesh.points.row(v) << x + 0.2 * z * z, y + 0.1 * x * x, z + 0.05 * x * y;
  }
  const QualitySummary before = summarize_quality(mesh);
  ASSERT_EQ(before.inverted, 0u);
  const fs::path path = dir_ / "bent.out";
  write_hex_mesh(mesh, path, GetParam());
  const MeshFile f = read_mesh(path, GetParam() == Format::Msh2 ? Format::Msh : GetParam());
  HexMesh back;
  back.points = f.points;
  back.complex.hexes = f.hexes;
  back.complex.num_nodes = static_cast<std::size_t>(f.points.rows());
  ASSERT_EQ(back.complex.hexes.size(), mesh.complex.hexes.size());
  for (std::size_t h = 0; h < back.complex.hexes.size(); ++h) {
    EXPECT_GT(hex_jacobian(back.points, back.complex.hexes[h]), 0.0) << "hex " << h;
    EXPECT_DOUBLE_EQ(hex_scaled_jacobian(back.points, back.complex.hexes[h]), before.per_hex[h]);
  }
}

TEST_P(WriterConvention, ExtensionChoosesTheFormat) {
  // .msh gives MSH 4.1; MSH 2.2 is chosen by name only, so its output differs from .msh's.
  const std::map<Format, std::string> ext = {{Format::Vtk, ".vtk"},    {Format::Vtu, ".vtu"},
                                             {Format::Msh, ".msh"},    {Format::Msh2, ".msh"},
                                             {Format::Medit, ".mesh"}, {Format::Inp, ".inp"}};
  const fs::path a = dir_ / ("a" + ext.at(GetParam()));
  const fs::path b = dir_ / "b.out";
  write_hex_mesh(shuffled_reference_hex(), a);
  write_hex_mesh(shuffled_reference_hex(), b, GetParam());
  if (GetParam() == Format::Msh2)
    EXPECT_NE(slurp(a), slurp(b));
  else
    EXPECT_EQ(slurp(a), slurp(b));
}

TEST_P(WriterConvention, ReplacingAFileLeavesNoTemporary) {
  const fs::path path = dir_ / "hex.out";
  std::ofstream(path) << "old content";
  write_hex_mesh(shuffled_reference_hex(), path, GetParam());
  EXPECT_NE(slurp(path), "old content");
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir_)) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "hex.out");
  }
  EXPECT_EQ(files, 1u);
}

INSTANTIATE_TEST_SUITE_P(AllHexFormats, WriterConvention,
                         ::testing::Values(Format::Vtk, Format::Vtu, Format::Msh, Format::Msh2,
                                           Format::Medit, Format::Inp),
                         [](const auto& info) { return std::string(format_name(info.param)); });

TEST(Writers, UnwritableTargetThrowsIoErrorAndLeavesNothing) {
  const fs::path dir = fs::temp_directory_path() / "stcweave_writers_test_missing_folder";
  std::error_code ec;
  fs::remove_all(dir, ec);
  EXPECT_THROW(write_hex_mesh(shuffled_reference_hex(), dir / "a.msh"), IoError);
  EXPECT_FALSE(fs::exists(dir));
}

TEST(Writers, TextFileIsWrittenWholeOrRefusedWithIoError) {
  const fs::path dir = fs::temp_directory_path() / "stcweave_writers_test_text";
  std::error_code ec;
  fs::remove_all(dir, ec);
  EXPECT_THROW(write_text_file(dir / "page.html", "<p>"), IoError);
  EXPECT_FALSE(fs::exists(dir));
  fs::create_directories(dir);
  write_text_file(dir / "page.html", "first");
  write_text_file(dir / "page.html", "second, longer");
  std::ifstream in(dir / "page.html");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "second, longer");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  fs::remove_all(dir, ec);
}

TEST(Writers, ALinkIsFollowedAndAFifoWrittenInPlace) {
  // Found by fuzzing: the rename over the target replaced a symbolic link, a FIFO or a device
  // (as root, /dev/full) with a regular file.
  const fs::path dir = fs::temp_directory_path() / "stcweave_writers_test_special";
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir);
  write_text_file(dir / "target.json", "old");
  fs::create_symlink("target.json", dir / "link.json");
  write_text_file(dir / "link.json", "through the link");
  EXPECT_TRUE(fs::is_symlink(dir / "link.json"));
  std::ifstream in(dir / "target.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "through the link");

  const fs::path fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // A reader that does not block, so that the writer's open does not wait for one.
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  write_text_file(fifo, "into the pipe");
  std::array<char, 64> buf{};
  const ::ssize_t got = ::read(reader, buf.data(), buf.size());
  ::close(reader);
  EXPECT_EQ(std::string(buf.data(), got > 0 ? static_cast<std::size_t>(got) : 0), "into the pipe");
  EXPECT_EQ(fs::status(fifo).type(), fs::file_type::fifo);
  fs::remove_all(dir, ec);
}

TEST(Writers, ASpecialFileThatRefusesTheTextIsAnIoErrorNamingWhatItIs) {
  using ::testing::HasSubstr;
  // A device that takes no byte: the write fails after the open, and the device stays one.
  if (fs::exists("/dev/full")) {
    try {
      write_text_file("/dev/full", "text");
      ADD_FAILURE() << "/dev/full took the text";
    } catch (const IoError& e) {
      EXPECT_THAT(e.what(), HasSubstr("a character device, written in place"));
      EXPECT_THAT(e.what(), HasSubstr(std::strerror(ENOSPC)));
    }
    EXPECT_EQ(fs::status("/dev/full").type(), fs::file_type::character);
  }
  // A socket cannot be opened at all.
  const fs::path dir = fs::temp_directory_path() / "stcweave_writers_test_socket";
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir);
  const fs::path socket_path = dir / "s.vtk";
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  ::sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const std::string name = socket_path.string();
  ASSERT_LT(name.size(), sizeof(address.sun_path));
  std::copy(name.begin(), name.end(), address.sun_path);
  ASSERT_EQ(::bind(fd, reinterpret_cast<const ::sockaddr*>(&address), sizeof(address)), 0);
  try {
    write_text_file(socket_path, "text");
    ADD_FAILURE() << "a socket took the text";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("it is a socket that cannot be opened for writing"));
    EXPECT_THAT(e.what(), HasSubstr("give another output path"));
  }
  EXPECT_EQ(fs::status(socket_path).type(), fs::file_type::socket);
  ::close(fd);
  fs::remove_all(dir, ec);
}

}  // namespace
}  // namespace stcweave::primal
