/// \file
/// Reader of the cell and point data of a hex mesh file (legacy VTK, VTU, Gmsh MSH). The mesh
/// itself is read by `read_mesh`; this reads only the data sections, so that a file written
/// by `write_hex_mesh(mesh, data, ...)` (or by ParaView or Gmsh) gives its arrays back.
///
/// Like the mesh readers it never crashes on bad content: every count is checked against
/// the bytes left before anything is allocated, and a problem is reported as InvalidInput
/// with the file, the line and what to do.

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>

#include "stcweave/primal/mesh_data.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::primal {

namespace {

/// Whitespace tokens of a text with their 1-based line.
class Lexer {
 public:
  Lexer(std::string_view text, std::string name) : text_(text), name_(std::move(name)) {}

  /// The next token ("" at the end of the text).
  std::string_view next() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_])) != 0) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const std::size_t begin = pos_;
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_])) == 0)
      ++pos_;
    return text_.substr(begin, pos_ - begin);
  }
  /// The next token, which must exist.
  std::string_view need(std::string_view what) {
    const std::string_view t = next();
    if (t.empty()) fail("unexpected end of file while reading " + std::string(what));
    return t;
  }
  /// A non-negative count that cannot exceed the tokens left (each value takes >= 2 bytes).
  std::size_t count(std::string_view what, std::size_t per_item = 1) {
    const std::string_view t = need(what);
    char* end = nullptr;
    const std::string s(t);
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (end == s.c_str() || *end != '\0' || v < 0)
      fail("expected " + std::string(what) + " (a non-negative integer), found '" + s + "'");
    if (per_item > 0 && static_cast<unsigned long long>(v) > (bytes_left() / 2 + 1) / per_item)
      fail(std::string(what) + " " + s + " is more than the file holds; the file looks truncated");
    return static_cast<std::size_t>(v);
  }
  /// A real value.
  double real(std::string_view what) {
    const std::string s(need(what));
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0')
      fail("expected " + std::string(what) + " (a number), found '" + s + "'");
    return v;
  }
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  /// Moves past the end of the current line and returns the next line, trimmed.
  std::string_view next_line() {
    skip_line();
    if (pos_ < text_.size()) {
      ++pos_;
      ++line_;
    }
    const std::size_t begin = pos_;
    skip_line();
    std::string_view s = text_.substr(begin, pos_ - begin);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())) != 0)
      s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())) != 0)
      s.remove_suffix(1);
    return s;
  }
  [[nodiscard]] bool at_end() const { return pos_ >= text_.size(); }
  [[noreturn]] void fail(const std::string& what) const {
    throw InvalidInput(name_ + ":" + std::to_string(line_) + ": " + what + "; fix the file");
  }
  [[nodiscard]] std::size_t bytes_left() const { return text_.size() - pos_; }
  [[nodiscard]] std::size_t pos() const { return pos_; }
  void seek(std::size_t pos) {
    for (; pos_ < pos && pos_ < text_.size(); ++pos_)
      if (text_[pos_] == '\n') ++line_;
  }

 private:
  std::string_view text_;
  std::string name_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

bool iequal(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

/// Adds `array` unless an array of that name is there already (the first one wins).
void keep(std::vector<DataArray>& arrays, DataArray array) {
  for (const DataArray& a : arrays)
    if (a.name == array.name) return;
  arrays.push_back(std::move(array));
}

DataType vtk_type(std::string_view type) {
  return iequal(type, "float") || iequal(type, "double") ? DataType::Float64 : DataType::Int32;
}

/// `count * components` values, keeping the first component of each tuple.
DataArray read_tuples(Lexer& lex, std::string name, DataType type, std::size_t count,
                      std::size_t components) {
  DataArray a;
  a.name = std::move(name);
  a.type = type;
  if (components == 0) lex.fail("array '" + a.name + "' has 0 components");
  if (count > lex.bytes_left() / 2 / components + 1)
    lex.fail("array '" + a.name + "' announces more values than the file holds");
  a.values.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t c = 0; c < components; ++c) {
      const double v = lex.real("a value of array '" + a.name + "'");
      if (c == 0) a.values[i] = v;
    }
  }
  return a;
}

MeshData read_vtk_data(std::string_view text, const std::string& name) {
  MeshData out;
  Lexer lex(text, name);
  lex.skip_line();  // "# vtk DataFile Version x.y"
  lex.next();       // the title line may hold anything: skip it whole
  lex.skip_line();
  std::vector<DataArray>* target = nullptr;
  std::size_t count = 0;
  for (std::string_view t = lex.next(); !t.empty(); t = lex.next()) {
    if (iequal(t, "CELL_DATA") || iequal(t, "POINT_DATA")) {
      target = iequal(t, "CELL_DATA") ? &out.cells : &out.points;
      count = lex.count(t);
      continue;
    }
    if (target == nullptr) continue;  // the mesh part
    if (iequal(t, "SCALARS")) {
      std::string array(lex.need("a SCALARS name"));
      const DataType type = vtk_type(lex.need("a SCALARS type"));
      std::size_t components = 1;
      const std::string_view after = lex.need("LOOKUP_TABLE");
      if (!iequal(after, "LOOKUP_TABLE")) {
        const std::string comps(after);
        char* end = nullptr;
        const long long c = std::strtoll(comps.c_str(), &end, 10);
        if (*end != '\0' || c < 1 || c > 4) {
          lex.fail(std::string("SCALARS ")
                       .append(array)
                       .append(": expected 1 to 4 components, found '")
                       .append(comps)
                       .append("'"));
        }
        components = static_cast<std::size_t>(c);
        if (!iequal(lex.need("LOOKUP_TABLE"), "LOOKUP_TABLE"))
          lex.fail("SCALARS " + array + " has no LOOKUP_TABLE line");
      }
      lex.need("a LOOKUP_TABLE name");
      keep(*target, read_tuples(lex, std::move(array), type, count, components));
    } else if (iequal(t, "FIELD")) {
      lex.need("a FIELD name");
      const std::size_t arrays = lex.count("the FIELD array count", 4);
      for (std::size_t k = 0; k < arrays; ++k) {
        std::string array(lex.need("a FIELD array name"));
        const std::size_t components = lex.count("the number of components");
        const std::size_t tuples = lex.count("the number of tuples", components);
        const DataType type = vtk_type(lex.need("a FIELD array type"));
        DataArray a = read_tuples(lex, std::move(array), type, tuples, components);
        if (tuples == count) keep(*target, std::move(a));
      }
    } else if (iequal(t, "VECTORS") || iequal(t, "NORMALS") || iequal(t, "TENSORS") ||
               iequal(t, "TEXTURE_COORDINATES") || iequal(t, "COLOR_SCALARS")) {
      lex.need("an array name");
      std::size_t components = iequal(t, "TENSORS") ? 9 : 3;
      if (iequal(t, "TEXTURE_COORDINATES") || iequal(t, "COLOR_SCALARS"))
        components = lex.count("the number of components");
      if (!iequal(t, "COLOR_SCALARS")) lex.need("a data type");
      (void)read_tuples(lex, "skipped", DataType::Float64, count, components);
    } else if (iequal(t, "LOOKUP_TABLE")) {
      lex.need("a LOOKUP_TABLE name");
      const std::size_t size = lex.count("the LOOKUP_TABLE size", 8);
      (void)read_tuples(lex, "lookup table", DataType::Float64, size, 4);
    } else if (iequal(t, "METADATA")) {
      // ParaView's information keys: skip to the blank line that ends them.
      while (!lex.next_line().empty() && !lex.at_end()) {
      }
    } else {
      lex.fail("unexpected '" + std::string(t) +
               "' in a data section (expected SCALARS, FIELD, VECTORS, CELL_DATA or POINT_DATA)");
    }
  }
  return out;
}

std::string_view xml_attr(std::string_view tag, std::string_view key) {
  std::size_t pos = 0;
  while ((pos = tag.find(key, pos)) != std::string_view::npos) {
    const bool starts = pos == 0 || std::isspace(static_cast<unsigned char>(tag[pos - 1])) != 0;
    const std::size_t eq = pos + key.size();
    if (starts && eq + 1 < tag.size() && tag[eq] == '=' &&
        (tag[eq + 1] == '"' || tag[eq + 1] == '\'')) {
      const char quote = tag[eq + 1];
      const std::size_t end = tag.find(quote, eq + 2);
      if (end == std::string_view::npos) return {};
      return tag.substr(eq + 2, end - eq - 2);
    }
    pos = eq;
  }
  return {};
}

MeshData read_vtu_data(std::string_view text, const std::string& name) {
  MeshData out;
  Lexer lex(text, name);
  const std::size_t piece = text.find("<Piece");
  if (piece == std::string_view::npos) return out;
  const std::string_view piece_tag = text.substr(piece, text.find('>', piece) - piece);
  const auto number = [&](std::string_view key) -> std::size_t {
    const std::string v(xml_attr(piece_tag, key));
    char* end = nullptr;
    const long long n = std::strtoll(v.c_str(), &end, 10);
    lex.seek(piece);
    if (v.empty() || *end != '\0' || n < 0) lex.fail("<Piece> has no valid " + std::string(key));
    return static_cast<std::size_t>(n);
  };
  const std::size_t cells = number("NumberOfCells");
  const std::size_t points = number("NumberOfPoints");
  const auto section = [&](std::string_view element, std::size_t count,
                           std::vector<DataArray>& arrays) {
    std::string open_tag(1, '<');  // built piecewise: GCC 12 warns (-Wrestrict) on "<" + s
    open_tag += element;
    std::string close_tag("</");
    close_tag += element;
    const std::size_t begin = text.find(open_tag, piece);
    if (begin == std::string_view::npos) return;
    const std::size_t end = text.find(close_tag, begin);
    const std::size_t self_closing = text.find("/>", begin);
    if (self_closing != std::string_view::npos && self_closing < text.find('>', begin) + 1 &&
        self_closing + 1 == text.find('>', begin))
      return;  // <CellData/>
    if (end == std::string_view::npos) {
      lex.seek(begin);
      lex.fail("<" + std::string(element) + "> is not closed");
    }
    std::size_t pos = begin;
    while ((pos = text.find("<DataArray", pos)) != std::string_view::npos && pos < end) {
      const std::size_t tag_end = text.find('>', pos);
      lex.seek(pos);
      if (tag_end == std::string_view::npos) lex.fail("a DataArray tag is not closed");
      const std::string_view tag = text.substr(pos, tag_end - pos);
      std::string array(xml_attr(tag, "Name"));
      if (array.empty()) lex.fail("a DataArray of <" + std::string(element) + "> has no Name");
      if (xml_attr(tag, "format") != "ascii") {
        lex.fail("DataArray '" + array +
                 "' is not stored as ascii; save the file with ASCII data (ParaView: Data "
                 "Mode = Ascii)");
      }
      const std::string_view type = xml_attr(tag, "type");
      const std::string comps(xml_attr(tag, "NumberOfComponents"));
      const std::size_t components =
          comps.empty() ? 1 : static_cast<std::size_t>(std::strtoull(comps.c_str(), nullptr, 10));
      const std::size_t data_end = text.find('<', tag_end);
      if (data_end == std::string_view::npos) lex.fail("DataArray '" + array + "' is not closed");
      Lexer values(text.substr(0, data_end), name);
      values.seek(tag_end + 1);
      const DataType dt = type.starts_with("Float") ? DataType::Float64 : DataType::Int32;
      keep(arrays, read_tuples(values, std::move(array), dt, count, components));
      if (!values.next().empty())
        lex.fail("DataArray '" + std::string(xml_attr(tag, "Name")) + "' has more than " +
                 std::to_string(count * components) + " values");
      pos = data_end;
    }
  };
  section("PointData", points, out.points);
  section("CellData", cells, out.cells);
  return out;
}

MeshData read_msh_data(std::string_view text, const std::string& name) {
  MeshData out;
  Lexer lex(text, name);
  for (std::string_view t = lex.next(); !t.empty(); t = lex.next()) {
    const bool cells = t == "$ElementData";
    if (!cells && t != "$NodeData") continue;
    const std::size_t strings = lex.count("the number of string tags");
    std::string array;
    for (std::size_t i = 0; i < strings; ++i) {
      std::string_view s = lex.next_line();
      if (i == 0) {
        if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
        array = std::string(s);
      }
    }
    const std::size_t reals = lex.count("the number of real tags");
    for (std::size_t i = 0; i < reals; ++i) (void)lex.real("a real tag");
    const std::size_t ints = lex.count("the number of integer tags");
    if (ints < 3) lex.fail("a data section needs 3 integer tags (time step, components, count)");
    (void)lex.count("the time step");
    const std::size_t components = lex.count("the number of components");
    const std::size_t entries = lex.count("the number of entries", components + 1);
    for (std::size_t i = 3; i < ints; ++i) (void)lex.count("an integer tag");
    if (components == 0) lex.fail("data '" + array + "' has 0 components");
    DataArray a;
    a.name = array;
    a.type = DataType::Float64;
    std::vector<bool> seen;
    for (std::size_t e = 0; e < entries; ++e) {
      const std::size_t tag = lex.count("an entity tag", 0);
      if (tag == 0 || tag > entries * 4 + 1024)
        lex.fail("entity tag " + std::to_string(tag) + " of data '" + array +
                 "' is out of range (tags are 1-based and dense in our files)");
      if (a.values.size() < tag) a.values.resize(tag, 0.0);
      for (std::size_t c = 0; c < components; ++c) {
        const double v = lex.real("a value of data '" + array + "'");
        if (c == 0) a.values[tag - 1] = v;
      }
    }
    const std::string end = cells ? "$EndElementData" : "$EndNodeData";
    if (lex.need(end) != end) {
      lex.fail(
          std::string("expected ").append(end).append(" after data '").append(array).append("'"));
    }
    keep(cells ? out.cells : out.points, std::move(a));
  }
  return out;
}

}  // namespace

MeshData read_mesh_data(std::string_view text, Format format, const std::string& name) {
  if (format == Format::Auto) {
    const std::string_view head = text.substr(0, std::min<std::size_t>(text.size(), 256));
    if (head.find("# vtk") != std::string_view::npos) {
      format = Format::Vtk;
    } else if (head.find("<?xml") != std::string_view::npos ||
               head.find("<VTKFile") != std::string_view::npos) {
      format = Format::Vtu;
    } else if (head.find("$MeshFormat") != std::string_view::npos) {
      format = Format::Msh;
    }
  }
  switch (format) {
    case Format::Vtk:
      return read_vtk_data(text, name);
    case Format::Vtu:
      return read_vtu_data(text, name);
    case Format::Msh:
    case Format::Msh2:
      return read_msh_data(text, name);
    default:
      return {};
  }
}

MeshData read_mesh_data(const std::filesystem::path& path, Format format) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open " + path.string() + " to read its cell data; check the path");
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw IoError("cannot read " + path.string());
  if (format == Format::Auto) {
    try {
      format = format_from_path(path);
    } catch (const InvalidInput&) {
      format = Format::Auto;  // recognised from the content
    }
  }
  return read_mesh_data(ss.str(), format, path.string());
}

}  // namespace stcweave::primal
