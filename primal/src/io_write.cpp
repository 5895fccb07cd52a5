/// \file
/// Mesh writers. Each writer formats the whole file in memory (numbers as `%.17g` would print
/// them, through `std::to_chars`, which is specified to give the same characters, so the
/// output is byte-for-byte deterministic and doubles read back exactly), writes it to a
/// temporary file in the target's folder and renames it over the target: a failure never
/// leaves a truncated file in place of a good one.

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <string_view>
#include <system_error>

#include "stcweave/primal/io.hpp"
#include "stcweave/primal/mesh_data.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::primal {

namespace {

/// Appends formatted text to a string.
class Out {
 public:
  Out& operator<<(std::string_view s) {
    text_.append(s);
    return *this;
  }
  Out& operator<<(char c) {
    text_.push_back(c);
    return *this;
  }
  /// An integer, in decimal.
  Out& integer(long long v) {
    std::array<char, 24> buf{};
    const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    text_.append(buf.data(), r.ptr);
    return *this;
  }
  /// A real as `%.17g` prints it (`std::to_chars` with the general format and precision 17
  /// is specified to give printf's characters; it skips printf's format parsing and locale).
  Out& real(double v) {
    std::array<char, 40> buf{};
    const auto r =
        std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::general, 17);
    text_.append(buf.data(), r.ptr);
    return *this;
  }
  /// `x y z` of row `i` of `points`.
  Out& point(const Points& points, Eigen::Index i, char separator = ' ') {
    real(points(i, 0)) << separator;
    real(points(i, 1)) << separator;
    return real(points(i, 2));
  }
  [[nodiscard]] const std::string& text() const { return text_; }

 private:
  std::string text_;
};

/// Checks that every node id in `cells` is a row of `points`.
template <class Cells>
void check_nodes(const Cells& cells, const Points& points, std::string_view kind,
                 const std::filesystem::path& path) {
  for (std::size_t c = 0; c < cells.size(); ++c) {
    for (const NodeId v : cells[c]) {
      if (!v.is_valid() || v.value() >= points.rows()) {
        throw InvalidInput("cannot write " + path.string() + ": " + std::string(kind) + " " +
                           std::to_string(c) + " uses node " + v.str() + " but the mesh has " +
                           std::to_string(points.rows()) +
                           " points; the mesh is inconsistent (a bug in the caller)");
      }
    }
  }
}

/// Writes all of `text` to the open `f`, flushes and closes it: true when all of that
/// succeeded; else false, with `error` the errno after the flush.
bool write_and_close(std::FILE* f, const std::string& text, int& error) {
  const std::size_t written = std::fwrite(text.data(), 1, text.size(), f);
  const bool flushed = std::fflush(f) == 0;
  error = errno;
  const bool closed = std::fclose(f) == 0;
  return written == text.size() && flushed && closed;
}

/// What a file that is neither a regular file nor a folder is, for messages.
std::string kind_of(std::filesystem::file_type type) {
  switch (type) {
    case std::filesystem::file_type::fifo:
      return "a FIFO";
    case std::filesystem::file_type::socket:
      return "a socket";
    case std::filesystem::file_type::character:
      return "a character device";
    case std::filesystem::file_type::block:
      return "a block device";
    default:
      return "not a regular file";
  }
}

/// Writes `text` into the existing file of type `type` that is not a regular one at `path`
/// (a device such as /dev/stdout or /dev/null, a FIFO), in place.
void write_in_place(const std::filesystem::path& path, std::filesystem::file_type type,
                    const std::string& text) {
  std::FILE* f = std::fopen(path.string().c_str(), "wb");
  if (f == nullptr) {
    throw IoError("cannot write " + path.string() + ": it is " + kind_of(type) +
                  " that cannot be opened for writing (" + std::strerror(errno) +
                  "); check its permissions or give another output path");
  }
  int error = 0;
  if (!write_and_close(f, text, error)) {
    throw IoError("cannot write " + path.string() + " (" + kind_of(type) +
                  ", written in place): " + std::strerror(error));
  }
}

/// Writes `text` to `path` through a temporary file in the same folder + rename. A symbolic
/// link is followed (its target replaced, the link kept); an existing file that is not a
/// regular file nor a folder (a device, a FIFO) is written in place, never replaced.
void commit(const std::filesystem::path& given, const std::string& text) {
  // The status through the links as the kernel follows them (/dev/stdout's link names
  // "pipe:[N]" under /proc, no path to resolve by hand).
  std::error_code status_ec;
  const std::filesystem::file_status status = std::filesystem::status(given, status_ec);
  if (!status_ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) &&
      !std::filesystem::is_directory(status)) {
    write_in_place(given, status.type(), text);
    return;
  }
  std::filesystem::path path = given;
  std::error_code link_ec;
  for (int hops = 0; hops < 40 && std::filesystem::is_symlink(path, link_ec); ++hops) {
    std::filesystem::path to = std::filesystem::read_symlink(path, link_ec);
    if (link_ec) break;
    path = to.is_absolute() ? to : path.parent_path() / to;
  }
  const std::filesystem::path folder =
      path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  std::random_device random;
  const std::string suffix = std::to_string(random()) + std::to_string(random());
  std::string tmp_name(1, '.');  // built piecewise: GCC 12 warns (-Wrestrict) on "." + s
  tmp_name += path.filename().string();
  tmp_name += ".tmp";
  tmp_name += suffix.substr(0, 12);
  const std::filesystem::path tmp = folder / tmp_name;
  std::FILE* f = std::fopen(tmp.string().c_str(), "wb");
  if (f == nullptr)
    throw IoError("cannot write " + path.string() + ": cannot create a file in " + folder.string() +
                  " (" + std::strerror(errno) + "); check that the folder exists and is writable");
  int error = 0;
  const bool whole = write_and_close(f, text, error);
  std::error_code ec;
  if (!whole) {
    std::filesystem::remove(tmp, ec);
    throw IoError("cannot write " + path.string() + ": " + std::strerror(error) +
                  "; check the free space and permissions (the previous file is untouched)");
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw IoError("cannot write " + path.string() + ": cannot replace it (" + ec.message() +
                  "); check permissions, or that it is not a folder");
  }
}

std::string vtk_hex(const HexMesh& mesh) {
  Out o;
  const auto n = mesh.points.rows();
  const std::size_t m = mesh.complex.hexes.size();
  o << "# vtk DataFile Version 4.2\nstcweave hex mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  o << "POINTS ";
  o.integer(n) << " double\n";
  for (Eigen::Index i = 0; i < n; ++i) o.point(mesh.points, i) << '\n';
  o << "CELLS ";
  o.integer(static_cast<long long>(m)) << ' ';
  o.integer(9 * static_cast<long long>(m)) << '\n';
  for (const auto& h : mesh.complex.hexes) {
    o << '8';
    for (const NodeId v : h) o << ' ', o.integer(v.value());
    o << '\n';
  }
  o << "CELL_TYPES ";
  o.integer(static_cast<long long>(m)) << '\n';
  for (std::size_t c = 0; c < m; ++c) o << "12\n";
  return o.text();
}

/// Checks that every array of `data` has a valid name and one value per cell / point.
void check_data(const MeshData& data, std::size_t cells, std::size_t points,
                const std::filesystem::path& path) {
  const auto check = [&](const std::vector<DataArray>& arrays, std::size_t expected,
                         std::string_view kind) {
    for (const DataArray& a : arrays) {
      const bool good_name =
          !a.name.empty() && std::all_of(a.name.begin(), a.name.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
          });
      if (!good_name) {
        throw InvalidInput("cannot write " + path.string() + ": " + std::string(kind) +
                           " array name '" + a.name +
                           "' is empty or has characters other than letters, digits and _");
      }
      if (a.values.size() != expected) {
        throw InvalidInput("cannot write " + path.string() + ": " + std::string(kind) + " array '" +
                           a.name + "' has " + std::to_string(a.values.size()) + " values for " +
                           std::to_string(expected) + " " + std::string(kind) +
                           "s (a bug in the caller)");
      }
    }
  };
  check(data.cells, cells, "cell");
  check(data.points, points, "point");
}

/// One value of an array, as its type says.
void value(Out& o, const DataArray& a, std::size_t i) {
  if (a.type == DataType::Int32) {
    o.integer(static_cast<long long>(a.values[i]));
  } else {
    o.real(a.values[i]);
  }
}

/// Legacy VTK `CELL_DATA` and `POINT_DATA` sections (SCALARS, one per array).
void vtk_data(Out& o, const MeshData& data, std::size_t cells, std::size_t points) {
  const auto section = [&](const std::vector<DataArray>& arrays, std::string_view keyword,
                           std::size_t count) {
    if (arrays.empty()) return;
    o << keyword << ' ';
    o.integer(static_cast<long long>(count)) << '\n';
    for (const DataArray& a : arrays) {
      o << "SCALARS " << a.name << (a.type == DataType::Int32 ? " int 1\n" : " double 1\n");
      o << "LOOKUP_TABLE default\n";
      for (std::size_t i = 0; i < count; ++i) value(o, a, i), o << '\n';
    }
  };
  section(data.cells, "CELL_DATA", cells);
  section(data.points, "POINT_DATA", points);
}

/// VTU `<PointData>` and `<CellData>` elements (they come first in a `<Piece>`).
void vtu_data(Out& o, const MeshData& data, std::size_t cells, std::size_t points) {
  const auto section = [&](const std::vector<DataArray>& arrays, std::string_view element,
                           std::size_t count) {
    if (arrays.empty()) return;
    o << "      <" << element << ">\n";
    for (const DataArray& a : arrays) {
      o << "        <DataArray type=\"" << (a.type == DataType::Int32 ? "Int32" : "Float64")
        << "\" Name=\"" << a.name << "\" format=\"ascii\">\n";
      for (std::size_t i = 0; i < count; ++i) value(o, a, i), o << '\n';
      o << "        </DataArray>\n";
    }
    o << "      </" << element << ">\n";
  };
  section(data.points, "PointData", points);
  section(data.cells, "CellData", cells);
}

/// Gmsh `$NodeData` and `$ElementData` sections (same syntax in MSH 2.2 and 4.1): one view
/// per array, at time 0, one component, entities tagged 1..count as the writers number them.
void msh_data(Out& o, const MeshData& data, std::size_t cells, std::size_t points) {
  const auto section = [&](const std::vector<DataArray>& arrays, std::string_view keyword,
                           std::size_t count) {
    for (const DataArray& a : arrays) {
      o << '$' << keyword << "\n1\n\"" << a.name << "\"\n1\n0\n3\n0\n1\n";
      o.integer(static_cast<long long>(count)) << '\n';
      for (std::size_t i = 0; i < count; ++i) {
        o.integer(static_cast<long long>(i) + 1) << ' ';
        value(o, a, i), o << '\n';
      }
      o << "$End" << keyword << '\n';
    }
  };
  section(data.points, "NodeData", points);
  section(data.cells, "ElementData", cells);
}

std::string vtu_hex(const HexMesh& mesh, const MeshData& data) {
  Out o;
  const auto n = mesh.points.rows();
  const std::size_t m = mesh.complex.hexes.size();
  o << "<?xml version=\"1.0\"?>\n"
       "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
       "  <UnstructuredGrid>\n"
       "    <Piece NumberOfPoints=\"";
  o.integer(n) << "\" NumberOfCells=\"";
  o.integer(static_cast<long long>(m)) << "\">\n";
  vtu_data(o, data, m, static_cast<std::size_t>(n));
  o << "      <Points>\n"
       "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (Eigen::Index i = 0; i < n; ++i) o.point(mesh.points, i) << '\n';
  o << "        </DataArray>\n      </Points>\n      <Cells>\n"
       "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& h : mesh.complex.hexes) {
    for (std::size_t k = 0; k < 8; ++k) {
      if (k > 0) o << ' ';
      o.integer(h[k].value());
    }
    o << '\n';
  }
  o << "        </DataArray>\n"
       "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t c = 0; c < m; ++c) o.integer(8 * (static_cast<long long>(c) + 1)) << '\n';
  o << "        </DataArray>\n"
       "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t c = 0; c < m; ++c) o << "12\n";
  o << "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n"
       "</VTKFile>\n";
  return o.text();
}

std::string msh41_hex(const HexMesh& mesh) {
  Out o;
  const auto n = mesh.points.rows();
  const auto m = static_cast<long long>(mesh.complex.hexes.size());
  o << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n";
  if (n == 0) {
    o << "0 0 0 0\n";
  } else {
    o << "1 ";
    o.integer(n) << " 1 ";
    o.integer(n) << "\n3 1 0 ";
    o.integer(n) << '\n';
    for (Eigen::Index i = 0; i < n; ++i) o.integer(i + 1) << '\n';
    for (Eigen::Index i = 0; i < n; ++i) o.point(mesh.points, i) << '\n';
  }
  o << "$EndNodes\n$Elements\n";
  if (m == 0) {
    o << "0 0 0 0\n";
  } else {
    o << "1 ";
    o.integer(m) << " 1 ";
    o.integer(m) << "\n3 1 5 ";
    o.integer(m) << '\n';
    long long tag = 0;
    for (const auto& h : mesh.complex.hexes) {
      o.integer(++tag);
      for (const NodeId v : h) o << ' ', o.integer(v.value() + 1);
      o << '\n';
    }
  }
  o << "$EndElements\n";
  return o.text();
}

std::string msh22_hex(const HexMesh& mesh) {
  Out o;
  const auto n = mesh.points.rows();
  o << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n";
  o.integer(n) << '\n';
  for (Eigen::Index i = 0; i < n; ++i) o.integer(i + 1) << ' ', o.point(mesh.points, i) << '\n';
  o << "$EndNodes\n$Elements\n";
  o.integer(static_cast<long long>(mesh.complex.hexes.size())) << '\n';
  long long tag = 0;
  for (const auto& h : mesh.complex.hexes) {
    o.integer(++tag) << " 5 2 0 1";
    for (const NodeId v : h) o << ' ', o.integer(v.value() + 1);
    o << '\n';
  }
  o << "$EndElements\n";
  return o.text();
}

std::string medit_hex(const HexMesh& mesh) {
  Out o;
  const auto n = mesh.points.rows();
  o << "MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n";
  o.integer(n) << '\n';
  for (Eigen::Index i = 0; i < n; ++i) o.point(mesh.points, i) << " 0\n";
  o << "\nHexahedra\n";
  o.integer(static_cast<long long>(mesh.complex.hexes.size())) << '\n';
  for (const auto& h : mesh.complex.hexes) {
    for (const NodeId v : h) o.integer(v.value() + 1) << ' ';
    o << "0\n";
  }
  o << "\nEnd\n";
  return o.text();
}

std::string inp_hex(const HexMesh& mesh) {
  Out o;
  const auto n = mesh.points.rows();
  o << "*Heading\n stcweave hex mesh\n*NODE\n";
  for (Eigen::Index i = 0; i < n; ++i) {
    o.integer(i + 1) << ", ";
    o.real(mesh.points(i, 0)) << ", ";
    o.real(mesh.points(i, 1)) << ", ";
    o.real(mesh.points(i, 2)) << '\n';
  }
  o << "*ELEMENT, TYPE=C3D8, ELSET=Volume1\n";
  long long tag = 0;
  for (const auto& h : mesh.complex.hexes) {
    o.integer(++tag);
    for (const NodeId v : h) o << ", ", o.integer(v.value() + 1);
    o << '\n';
  }
  return o.text();
}

std::string obj_surface(const SurfaceMesh& mesh) {
  Out o;
  o << "# stcweave quad surface\n";
  for (Eigen::Index i = 0; i < mesh.points.rows(); ++i) o << "v ", o.point(mesh.points, i) << '\n';
  for (const auto& q : mesh.surface.quads) {
    o << 'f';
    for (const NodeId v : q) o << ' ', o.integer(v.value() + 1);
    o << '\n';
  }
  return o.text();
}

std::string off_surface(const SurfaceMesh& mesh) {
  Out o;
  o << "OFF\n";
  o.integer(mesh.points.rows()) << ' ';
  o.integer(static_cast<long long>(mesh.surface.quads.size())) << " 0\n";
  for (Eigen::Index i = 0; i < mesh.points.rows(); ++i) o.point(mesh.points, i) << '\n';
  for (const auto& q : mesh.surface.quads) {
    o << '4';
    for (const NodeId v : q) o << ' ', o.integer(v.value());
    o << '\n';
  }
  return o.text();
}

std::string vtk_surface(const SurfaceMesh& mesh) {
  Out o;
  const auto m = static_cast<long long>(mesh.surface.quads.size());
  o << "# vtk DataFile Version 4.2\nstcweave quad surface\nASCII\nDATASET POLYDATA\nPOINTS ";
  o.integer(mesh.points.rows()) << " double\n";
  for (Eigen::Index i = 0; i < mesh.points.rows(); ++i) o.point(mesh.points, i) << '\n';
  o << "POLYGONS ";
  o.integer(m) << ' ';
  o.integer(5 * m) << '\n';
  for (const auto& q : mesh.surface.quads) {
    o << '4';
    for (const NodeId v : q) o << ' ', o.integer(v.value());
    o << '\n';
  }
  return o.text();
}

}  // namespace

void write_hex_mesh(const HexMesh& mesh, const std::filesystem::path& path, Format format) {
  write_hex_mesh(mesh, MeshData{}, path, format);
}

void write_hex_mesh(const HexMesh& mesh, const MeshData& data, const std::filesystem::path& path,
                    Format format) {
  if (format == Format::Auto) format = format_from_path(path);
  check_nodes(mesh.complex.hexes, mesh.points, "hex", path);
  const std::size_t cells = mesh.complex.hexes.size();
  const auto points = static_cast<std::size_t>(mesh.points.rows());
  check_data(data, cells, points, path);
  std::string text;
  switch (format) {
    case Format::Vtk: {
      text = vtk_hex(mesh);
      Out o;
      vtk_data(o, data, cells, points);
      text += o.text();
      break;
    }
    case Format::Vtu:
      text = vtu_hex(mesh, data);
      break;
    case Format::Msh:
    case Format::Msh2: {
      text = format == Format::Msh ? msh41_hex(mesh) : msh22_hex(mesh);
      Out o;
      msh_data(o, data, cells, points);
      text += o.text();
      break;
    }
    case Format::Medit:
      text = medit_hex(mesh);
      break;
    case Format::Inp:
      text = inp_hex(mesh);
      break;
    case Format::Auto:
    case Format::Obj:
    case Format::Off:
    case Format::Mfem:
      throw InvalidInput("cannot write " + path.string() + " as " +
                         std::string(format_name(format)) +
                         ": a hex mesh is written as vtk, vtu, msh, msh2, mesh or inp");
  }
  commit(path, text);
}

void write_surface(const SurfaceMesh& mesh, const std::filesystem::path& path, Format format) {
  if (format == Format::Auto) format = format_from_path(path);
  check_nodes(mesh.surface.quads, mesh.points, "quad", path);
  std::string text;
  switch (format) {
    case Format::Obj:
      text = obj_surface(mesh);
      break;
    case Format::Off:
      text = off_surface(mesh);
      break;
    case Format::Vtk:
      text = vtk_surface(mesh);
      break;
    default:
      throw InvalidInput("cannot write the surface " + path.string() + " as " +
                         std::string(format_name(format)) +
                         ": a quad surface is written as obj, off or vtk");
  }
  commit(path, text);
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  commit(path, text);
}

}  // namespace stcweave::primal
