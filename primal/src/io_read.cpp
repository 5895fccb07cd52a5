/// \file
/// Mesh readers. Every reader works on the whole file held in memory, tokenised in place
/// (`std::string_view`) and converted with `std::from_chars`: no iostream per token.
///
/// Every reader follows the same discipline, which is what makes it crash-free on bad
/// input: counts are checked against the bytes left before anything is allocated, every
/// token read reports "unexpected end of file" instead of reading past the end, and cells
/// are collected with the file's own node numbering and the line they were read on, then
/// resolved to rows of `points` in one pass that names the file, line and element of the
/// first unknown node.

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <istream>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "stcweave/primal/io.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::primal {

namespace {

/// Counts a cell that is neither a quad, a hex, a triangle, a tet nor a line; remembers the
/// first one's line and kind for the diagnosis.
/// `text` without a leading UTF-8 byte-order mark (editors on Windows write one); it is no
/// part of the first token, nor of the content that tells the format.
std::string_view without_byte_order_mark(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return text;
}

void note_other_cell(MeshFile& out, std::size_t line, const std::string& what) {
  ++out.other_cells;
  if (out.first_other_cell.empty())
    out.first_other_cell = (line > 0 ? "line " + std::to_string(line) + ": " : "") + what;
}

// ----------------------------------------------------------------------------------------
// Small string helpers

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  }
  return true;
}

bool istarts_with(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && iequals(s.substr(0, prefix.size()), prefix);
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (auto& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string_view trim(std::string_view s) {
  const auto is_space = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
  };
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

/// A token for messages: quoted, cut to 40 characters.
std::string in_quotes(std::string_view s) {
  if (s.size() > 40) return "'" + std::string(s.substr(0, 40)) + "...'";
  return "'" + std::string(s) + "'";
}

// ----------------------------------------------------------------------------------------
// Tokeniser

/// A whitespace-separated piece of the file and the 1-based line it starts on. An empty
/// `text` means the end of the file (or of the line, for `Scanner::next_on_line`).
struct Token {
  std::string_view text;
  std::size_t line = 0;
  [[nodiscard]] bool empty() const { return text.empty(); }
};

/// Walks a text held in memory, token by token, counting lines. With `hash_comments`, a
/// `#` at the start of a token starts a comment that runs to the end of the line.
class Scanner {
 public:
  Scanner(std::string_view text, bool hash_comments) : text_(text), hash_comments_(hash_comments) {}

  /// The next token, across line ends; empty at the end of the text.
  Token next() {
    skip_space(true);
    return take();
  }

  /// The next token on the current line; empty at the end of the line or of the text.
  Token next_on_line() {
    skip_space(false);
    if (pos_ < text_.size() && text_[pos_] == '\n') return {{}, line_};
    return take();
  }

  /// The next token, without consuming it.
  Token peek() {
    const std::size_t pos = pos_;
    const std::size_t line = line_;
    const Token t = next();
    pos_ = pos;
    line_ = line;
    return t;
  }

  /// The rest of the current line (without its end), and moves to the next line.
  std::string_view rest_of_line() {
    const std::size_t begin = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    std::string_view out = text_.substr(begin, pos_ - begin);
    if (pos_ < text_.size()) {
      ++pos_;
      ++line_;
    }
    if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
    return out;
  }

  /// Moves to the start of the next line.
  void skip_line() { (void)rest_of_line(); }

  [[nodiscard]] bool at_end() {
    skip_space(true);
    return pos_ >= text_.size();
  }
  [[nodiscard]] std::size_t line() const { return line_; }
  [[nodiscard]] std::size_t pos() const { return pos_; }
  [[nodiscard]] std::size_t bytes_left() const { return text_.size() - pos_; }
  [[nodiscard]] std::string_view text() const { return text_; }

  /// Moves forward to byte `pos`, counting the lines passed. \pre pos >= this->pos().
  void seek(std::size_t pos) {
    pos = std::min(pos, text_.size());
    for (; pos_ < pos; ++pos_)
      if (text_[pos_] == '\n') ++line_;
  }

 private:
  void skip_space(bool cross_lines) {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        if (!cross_lines) return;
        ++line_;
        ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v' || c == '\0') {
        ++pos_;
      } else if (c == '#' && hash_comments_) {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else {
        return;
      }
    }
  }

  Token take() {
    const std::size_t begin = pos_;
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\f' || c == '\v' || c == '\0')
        break;
      ++pos_;
    }
    return {text_.substr(begin, pos_ - begin), line_};
  }

  std::string_view text_;
  bool hash_comments_ = false;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

/// Parses a whole token as an integer. Returns nothing if it is not one.
std::optional<long long> to_integer(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || ptr != s.data() + s.size() || s.empty()) return std::nullopt;
  return value;
}

/// Parses a whole token as a real (`nan`, `inf` included; Fortran `D` exponents
/// accepted). Overflow gives +-inf and underflow 0, as strtod does. Returns nothing if the
/// token is not a number.
std::optional<double> to_real(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec == std::errc() && ptr == s.data() + s.size()) return value;
  // Rare cases: out of range, or a Fortran exponent (1.0D+03): go through strtod.
  if (s.size() > 64) return std::nullopt;
  std::string copy(s);
  for (auto& c : copy)
    if (c == 'd' || c == 'D') c = 'e';
  char* end = nullptr;
  const double v = std::strtod(copy.c_str(), &end);
  if (end != copy.c_str() + copy.size()) return std::nullopt;
  return v;
}

/// A scanner plus the file name, with reads that fail with a located message.
class Parser {
 public:
  Parser(std::string_view text, std::string name, bool hash_comments)
      : scan(text, hash_comments), name_(std::move(name)) {}

  Scanner scan;

  [[nodiscard]] const std::string& name() const { return name_; }

  /// `name:line: what`.
  [[nodiscard]] std::string where(std::size_t line) const {
    return name_ + ":" + std::to_string(line);
  }

  [[noreturn]] void fail(std::size_t line, const std::string& what) const {
    throw InvalidInput(where(line) + ": " + what);
  }

  [[noreturn]] void fail_end(std::string_view what) const {
    fail(scan.line(), "unexpected end of file while reading " + std::string(what) +
                          "; the file looks truncated: write it again");
  }

  /// The next token; fails at the end of the file.
  Token token(std::string_view what) {
    const Token t = scan.next();
    if (t.empty()) fail_end(what);
    return t;
  }

  long long integer(const Token& t, std::string_view what) const {
    const auto v = to_integer(t.text);
    if (!v)
      fail(t.line, "expected an integer (" + std::string(what) + "), found " + in_quotes(t.text) +
                       "; fix the file");
    return *v;
  }
  long long integer(std::string_view what) { return integer(token(what), what); }

  double real(const Token& t, std::string_view what) const {
    const auto v = to_real(t.text);
    if (!v)
      fail(t.line, "expected a number (" + std::string(what) + "), found " + in_quotes(t.text) +
                       "; fix the file");
    return *v;
  }
  double real(std::string_view what) { return real(token(what), what); }

  /// A count of items, each needing at least `tokens_per_item` tokens: fails if negative,
  /// if more than a node id can address, or if the rest of the file cannot hold them (a
  /// wrong count must not allocate gigabytes).
  std::size_t count(const Token& t, std::string_view what, std::size_t tokens_per_item) const {
    const long long v = integer(t, what);
    check_count(v, t.line, what, tokens_per_item);
    return static_cast<std::size_t>(v);
  }
  std::size_t count(std::string_view what, std::size_t tokens_per_item) {
    return count(token(what), what, tokens_per_item);
  }

  void check_count(long long v, std::size_t line, std::string_view what,
                   std::size_t tokens_per_item) const {
    if (v < 0)
      fail(line,
           "negative count " + std::to_string(v) + " (" + std::string(what) + "); fix the file");
    if (v > std::numeric_limits<std::int32_t>::max())
      fail(line, "count " + std::to_string(v) + " (" + std::string(what) +
                     ") exceeds the 2^31-1 elements stcweave can index; split the mesh");
    const auto needed = static_cast<unsigned long long>(v) * 2ULL * tokens_per_item;
    if (tokens_per_item > 0 && needed > scan.bytes_left() + 1) {
      fail(line, "count " + std::to_string(v) + " (" + std::string(what) +
                     ") is larger than the rest of the file can hold; the file is truncated "
                     "or the count is wrong");
    }
  }

  /// The next token must be `word` (case-insensitive).
  void expect(std::string_view word) {
    const Token t = token(word);
    if (!iequals(t.text, word))
      fail(t.line,
           "expected " + in_quotes(word) + ", found " + in_quotes(t.text) + "; fix the file");
  }

 private:
  std::string name_;
};

// ----------------------------------------------------------------------------------------
// Cells collected with the file's own node numbering, resolved at the end

/// Maps a file's node numbers (1-based indices, Gmsh or Abaqus tags) to rows.
class NodeNumbering {
 public:
  /// Dense numbering `first .. first + n - 1`.
  static NodeNumbering dense(long long first) {
    NodeNumbering m;
    m.first_ = first;
    return m;
  }
  /// Arbitrary tags, registered with `add`.
  static NodeNumbering tagged() {
    NodeNumbering m;
    m.tagged_ = true;
    return m;
  }

  /// Announces about `n` more tags: tags up to 4 times the total go in a dense table,
  /// larger ones in a hash map (a single huge tag must not allocate a huge table).
  void expect(std::size_t n) {
    expected_ += n;
    dense_limit_ = std::max<long long>(dense_limit_, 4 * static_cast<long long>(expected_));
    dense_limit_ = std::min<long long>(dense_limit_, 1LL << 30);
  }

  /// Registers tag -> row; returns false if the tag was already there.
  bool add(long long tag, std::size_t row) {
    if (tag >= 0 && tag < dense_limit_) {
      const auto t = static_cast<std::size_t>(tag);
      if (t >= rows_.size()) rows_.resize(std::max(t + 1, rows_.size() * 2), -1);
      if (rows_[t] >= 0) return false;
      rows_[t] = static_cast<std::int32_t>(row);
      return true;
    }
    return sparse_.emplace(tag, row).second;
  }

  /// The row of file number `n` among `num_rows` rows, or -1 if it is unknown.
  [[nodiscard]] long long row(long long n, std::size_t num_rows) const {
    if (!tagged_) {
      const long long r = n - first_;
      return (r >= 0 && static_cast<unsigned long long>(r) < num_rows) ? r : -1;
    }
    if (n >= 0 && n < dense_limit_) {
      const auto t = static_cast<std::size_t>(n);
      return t < rows_.size() ? rows_[t] : -1;
    }
    const auto it = sparse_.find(n);
    return it == sparse_.end() ? -1 : static_cast<long long>(it->second);
  }

  /// "1 .. N" or "the node tags of the file" for messages.
  [[nodiscard]] std::string describe(std::size_t num_rows) const {
    if (tagged_) return "the file defines " + std::to_string(num_rows) + " node tags";
    if (num_rows == 0) return "the file defines no nodes";
    return "valid node numbers are " + std::to_string(first_) + " .. " +
           std::to_string(first_ + static_cast<long long>(num_rows) - 1);
  }

 private:
  bool tagged_ = false;
  long long first_ = 0;
  std::size_t expected_ = 0;
  long long dense_limit_ = 1LL << 20;
  std::vector<std::int32_t> rows_;
  std::unordered_map<long long, std::size_t> sparse_;
};

/// Quads and hexes as read (file numbering), with the line and the label of each.
struct RawCells {
  std::vector<long long> quad_nodes;  // 4 per quad
  std::vector<std::size_t> quad_lines;
  std::vector<long long> quad_label;  // element number used in messages
  std::vector<long long> hex_nodes;   // 8 per hex
  std::vector<std::size_t> hex_lines;
  std::vector<long long> hex_label;

  void add_quad(const long long* n, std::size_t line, long long label) {
    quad_nodes.insert(quad_nodes.end(), n, n + 4);
    quad_lines.push_back(line);
    quad_label.push_back(label);
  }
  void add_hex(const long long* n, std::size_t line, long long label) {
    hex_nodes.insert(hex_nodes.end(), n, n + 8);
    hex_lines.push_back(line);
    hex_label.push_back(label);
  }
  /// Nodes of a cell that is only counted (triangle, tet, polygon...): checked, not kept.
  struct Other {
    long long node;
    std::size_t line;
    long long label;
  };
  std::vector<Other> other_nodes;
  void add_other(const long long* n, std::size_t k, std::size_t line, long long label) {
    for (std::size_t i = 0; i < k; ++i) other_nodes.push_back({n[i], line, label});
  }
};

/// Fills `out.quads`, `out.hexes` and `out.quad_lines` from `raw`, checking every node.
/// `element_word` names elements in messages ("cell", "element tag", ...).
void resolve(const Parser& p, const RawCells& raw, const NodeNumbering& numbering,
             std::string_view element_word, MeshFile& out) {
  const auto n = static_cast<std::size_t>(out.points.rows());
  const auto resolve_one = [&](long long node, std::size_t line, std::string_view kind,
                               long long label) {
    const long long r = numbering.row(node, n);
    if (r < 0) {
      p.fail(line, std::string(kind) + " (" + std::string(element_word) + " " +
                       std::to_string(label) + ") uses node " + std::to_string(node) +
                       ", which does not exist (" + numbering.describe(n) +
                       "); fix the connectivity or the node list");
    }
    return NodeId(static_cast<NodeId::value_type>(r));
  };
  for (const auto& o : raw.other_nodes) (void)resolve_one(o.node, o.line, "cell", o.label);
  const std::size_t nq = raw.quad_lines.size();
  out.quads.reserve(out.quads.size() + nq);
  out.quad_lines.reserve(out.quad_lines.size() + nq);
  for (std::size_t q = 0; q < nq; ++q) {
    stc::Quad quad;
    for (std::size_t k = 0; k < 4; ++k)
      quad[k] =
          resolve_one(raw.quad_nodes[4 * q + k], raw.quad_lines[q], "quad", raw.quad_label[q]);
    out.quads.push_back(quad);
    out.quad_lines.push_back(raw.quad_lines[q]);
  }
  const std::size_t nh = raw.hex_lines.size();
  out.hexes.reserve(out.hexes.size() + nh);
  for (std::size_t h = 0; h < nh; ++h) {
    stc::Hex hex;
    for (std::size_t k = 0; k < 8; ++k)
      hex[k] =
          resolve_one(raw.hex_nodes[8 * h + k], raw.hex_lines[h], "hexahedron", raw.hex_label[h]);
    out.hexes.push_back(hex);
  }
}

/// Copies packed xyz triples into `out.points`.
void set_points(const std::vector<double>& xyz, MeshFile& out) {
  const auto n = static_cast<Eigen::Index>(xyz.size() / 3);
  out.points.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index k = 0; k < 3; ++k)
      out.points(i, k) = xyz[static_cast<std::size_t>(3 * i + k)];
}

// ----------------------------------------------------------------------------------------
// OBJ

/// Wavefront OBJ: `v x y z [w | r g b]` and `f a b c ...` with `a`, `a/t`, `a//n`, `a/t/n`,
/// 1-based or negative (relative) indices. Other statements are ignored.
MeshFile read_obj(std::string_view text, const std::string& name) {
  MeshFile out;
  out.format = "obj";
  Parser p(text, name, true);
  std::vector<double> xyz;
  RawCells raw;
  std::size_t unknown_lines = 0;
  std::string first_unknown;
  std::vector<long long> face;
  long long face_number = 0;
  while (!p.scan.at_end()) {
    const Token key = p.scan.next_on_line();
    if (key.text == "v") {
      for (int k = 0; k < 3; ++k) {
        const Token t = p.scan.next_on_line();
        if (t.empty())
          p.fail(key.line, "vertex " + std::to_string(xyz.size() / 3 + 1) +
                               " has fewer than 3 coordinates; fix the 'v' line");
        xyz.push_back(p.real(t, "vertex coordinate"));
      }
    } else if (key.text == "f") {
      ++face_number;
      face.clear();
      const auto nv = static_cast<long long>(xyz.size() / 3);
      for (Token t = p.scan.next_on_line(); !t.empty(); t = p.scan.next_on_line()) {
        std::string_view s = t.text;
        s = s.substr(0, s.find('/'));
        const auto v = to_integer(s);
        if (!v) {
          p.fail(t.line, "face " + std::to_string(face_number) +
                             ": expected a vertex index, found " + in_quotes(t.text) +
                             "; fix the 'f' line");
        }
        if (*v == 0) {
          p.fail(t.line, "face " + std::to_string(face_number) +
                             " uses vertex index 0, but OBJ indices start at 1 (or are negative, "
                             "relative to the last vertex); fix the 'f' line");
        }
        face.push_back(*v > 0 ? *v : nv + *v + 1);  // 1-based
        if (face.back() <= 0) {
          p.fail(t.line, "face " + std::to_string(face_number) + " uses relative index " +
                             std::to_string(*v) + " but only " + std::to_string(nv) +
                             " vertices precede it; fix the 'f' line");
        }
      }
      if (face.size() < 3) {
        p.fail(key.line, "face " + std::to_string(face_number) + " has " +
                             std::to_string(face.size()) +
                             " vertices; a face needs at least 3: fix the 'f' line");
      }
      if (face.size() == 4)
        raw.add_quad(face.data(), key.line, face_number);
      else if (face.size() == 3)
        ++out.triangles;
      else
        note_other_cell(out, key.line, "a face with " + std::to_string(face.size()) + " nodes");
      // Triangles and polygons are only counted, but their indices must exist too.
      if (face.size() != 4) raw.add_other(face.data(), face.size(), key.line, face_number);
    } else if (key.text == "vt" || key.text == "vn" || key.text == "vp" || key.text == "g" ||
               key.text == "o" || key.text == "s" || key.text == "usemtl" || key.text == "mtllib" ||
               key.text == "l" || key.text == "p") {
      // Not geometry we need.
    } else if (!key.empty()) {
      if (unknown_lines++ == 0)
        first_unknown = in_quotes(key.text) + " (line " + std::to_string(key.line) + ")";
    }
    p.scan.skip_line();
  }
  if (unknown_lines > 0)
    out.notes.push_back("ignored " + std::to_string(unknown_lines) +
                        " line(s) with an unknown OBJ statement, first " + first_unknown);
  set_points(xyz, out);
  resolve(p, raw, NodeNumbering::dense(1), "face", out);
  return out;
}

// ----------------------------------------------------------------------------------------
// OFF

/// OFF and its variants (COFF, NOFF, STOFF, ...): header, optional counts on the header
/// line, `#` comments and blank lines anywhere, extra values (colours) after a vertex or a
/// face ignored. Indices are 0-based.
MeshFile read_off(std::string_view text, const std::string& name) {
  MeshFile out;
  out.format = "off";
  Parser p(text, name, true);
  const Token header = p.token("the OFF header");
  std::string_view h = header.text;
  const bool has_off = h.size() >= 3 && iequals(h.substr(h.size() - 3), "OFF");
  if (!has_off)
    p.fail(header.line, "not an OFF file: expected 'OFF' first, found " + in_quotes(h) +
                            "; check the file's format");
  if (h.find('4') != std::string_view::npos || (h.size() > 3 && h.front() == 'n'))
    p.fail(header.line, "OFF variant " + in_quotes(h) +
                            " is not 3-dimensional; convert the file to plain 3D OFF");
  // Counts: on the header line or on the next non-comment line; the edge count may be
  // missing.
  const std::size_t nv = p.count("the vertex count", 3);
  const Token nf_token = p.token("the face count");
  const std::size_t nf = p.count(nf_token, "the face count", 4);
  {
    const Token maybe_edges = p.scan.next_on_line();
    if (!maybe_edges.empty()) (void)p.integer(maybe_edges, "the edge count");
  }
  p.scan.skip_line();
  out.points.resize(static_cast<Eigen::Index>(nv), 3);
  for (std::size_t i = 0; i < nv; ++i) {
    const Token first = p.token("vertex coordinates");
    out.points(static_cast<Eigen::Index>(i), 0) = p.real(first, "vertex coordinate");
    for (Eigen::Index k = 1; k < 3; ++k) {
      const Token t = p.scan.next_on_line();
      if (t.empty())
        p.fail(first.line, "vertex " + std::to_string(i) +
                               " has fewer than 3 coordinates on its line; fix the file");
      out.points(static_cast<Eigen::Index>(i), k) = p.real(t, "vertex coordinate");
    }
    p.scan.skip_line();
  }
  RawCells raw;
  std::vector<long long> face;
  for (std::size_t f = 0; f < nf; ++f) {
    const Token first = p.token("face " + std::to_string(f));
    const long long k = p.integer(first, "number of vertices of a face");
    if (k < 3)
      p.fail(first.line, "face " + std::to_string(f) + " has " + std::to_string(k) +
                             " vertices; a face needs at least 3: fix the file");
    if (k > 1'000'000)
      p.fail(first.line, "face " + std::to_string(f) + " claims " + std::to_string(k) +
                             " vertices; fix the file");
    face.clear();
    for (long long j = 0; j < k; ++j) {
      const Token t = p.scan.next();
      if (t.empty()) p.fail_end("face " + std::to_string(f));
      face.push_back(p.integer(t, "vertex index"));
    }
    if (k == 4) {
      raw.add_quad(face.data(), first.line, static_cast<long long>(f));
    } else {
      if (k == 3)
        ++out.triangles;
      else
        note_other_cell(out, first.line, "a face with " + std::to_string(k) + " nodes");
      raw.add_other(face.data(), face.size(), first.line, static_cast<long long>(f));
    }
    p.scan.skip_line();  // colours
  }
  resolve(p, raw, NodeNumbering::dense(0), "face", out);
  return out;
}

// ----------------------------------------------------------------------------------------
// Legacy VTK

/// Cells of a legacy VTK section in either layout: `offsets` (n+1 entries) into `conn`.
struct CellArray {
  std::vector<long long> offsets{0};
  std::vector<long long> conn;
  std::vector<std::size_t> lines;  // line of each cell's first entry
  std::size_t header_line = 0;
  [[nodiscard]] std::size_t size() const { return offsets.size() - 1; }
};

/// Reads `KEYWORD a b` + data of CELLS / POLYGONS / LINES / ...: the classic layout (`a`
/// cells, `b` integers, records `k i1 .. ik`) or the VTK 5.1 one (`a` offsets, `b`
/// connectivity entries, then `OFFSETS type` and `CONNECTIVITY type` arrays).
CellArray read_vtk_cells(Parser& p, const Token& keyword) {
  CellArray cells;
  cells.header_line = keyword.line;
  const std::string what(keyword.text);
  const long long a = p.integer(what + " count");
  const long long b = p.integer(what + " size");
  const Token next = p.scan.peek();
  if (iequals(next.text, "OFFSETS")) {
    p.check_count(a, keyword.line, what + " offsets", 1);
    p.check_count(b, keyword.line, what + " connectivity", 1);
    (void)p.token("OFFSETS");
    (void)p.token("the OFFSETS type");
    cells.offsets.clear();
    for (long long i = 0; i < a; ++i) {
      const Token t = p.token(what + " offsets");
      cells.offsets.push_back(p.integer(t, "offset"));
      const long long o = cells.offsets.back();
      if (o < 0 || o > b || (i == 0 && o != 0) ||
          (i > 0 && o < cells.offsets[static_cast<std::size_t>(i) - 1])) {
        p.fail(t.line, "offset " + std::to_string(i) + " is " + std::to_string(o) +
                           ": offsets must start at 0, never decrease and stay within the " +
                           std::to_string(b) + " connectivity entries; fix the file");
      }
    }
    if (cells.offsets.empty()) cells.offsets.push_back(0);
    if (cells.offsets.back() != b) {
      p.fail(keyword.line, "the last offset is " + std::to_string(cells.offsets.back()) + " but " +
                               what + " declares " + std::to_string(b) +
                               " connectivity entries; fix the file");
    }
    p.expect("CONNECTIVITY");
    (void)p.token("the CONNECTIVITY type");
    cells.conn.reserve(static_cast<std::size_t>(b));
    std::vector<std::size_t> entry_lines;
    entry_lines.reserve(static_cast<std::size_t>(b));
    for (long long i = 0; i < b; ++i) {
      const Token t = p.token(what + " connectivity");
      cells.conn.push_back(p.integer(t, "point index"));
      entry_lines.push_back(t.line);
    }
    for (std::size_t c = 0; c + 1 < cells.offsets.size(); ++c) {
      const auto o = static_cast<std::size_t>(cells.offsets[c]);
      cells.lines.push_back(o < entry_lines.size() ? entry_lines[o] : keyword.line);
    }
    return cells;
  }
  p.check_count(a, keyword.line, what + " count", 2);
  p.check_count(b, keyword.line, what + " size", 1);
  cells.conn.reserve(static_cast<std::size_t>(b - std::min(a, b)));
  cells.offsets.reserve(static_cast<std::size_t>(a) + 1);
  cells.lines.reserve(static_cast<std::size_t>(a));
  for (long long c = 0; c < a; ++c) {
    const Token t = p.token(what + " (cell " + std::to_string(c) + ")");
    const long long k = p.integer(t, "number of points of a cell");
    if (k < 0 || k > b)
      p.fail(t.line, "cell " + std::to_string(c) + " claims " + std::to_string(k) +
                         " points; fix the file");
    for (long long j = 0; j < k; ++j) cells.conn.push_back(p.integer(what + " point index"));
    cells.offsets.push_back(static_cast<long long>(cells.conn.size()));
    cells.lines.push_back(t.line);
  }
  if (static_cast<long long>(cells.conn.size()) + a != b) {
    p.fail(keyword.line, what + " declares " + std::to_string(b) + " integers but its " +
                             std::to_string(a) + " records hold " +
                             std::to_string(static_cast<long long>(cells.conn.size()) + a) +
                             "; fix the size on this line");
  }
  return cells;
}

/// Skips a `FIELD name n` block: n arrays `name ncomp ntuples type` + values.
void skip_vtk_field(Parser& p) {
  (void)p.token("the FIELD name");
  const long long n = p.integer("the FIELD array count");
  for (long long i = 0; i < n; ++i) {
    const Token array_name = p.token("a FIELD array");
    if (iequals(array_name.text, "METADATA")) {
      while (!p.scan.at_end() && !trim(p.scan.rest_of_line()).empty()) {
      }
      --i;
      continue;
    }
    const long long comps = p.integer("FIELD array components");
    const long long tuples = p.integer("FIELD array tuples");
    (void)p.token("FIELD array type");
    if (comps < 0 || tuples < 0) p.fail(array_name.line, "negative FIELD array size; fix the file");
    const long long values = comps * tuples;
    p.check_count(values, array_name.line, "FIELD array values", 1);
    for (long long k = 0; k < values; ++k) (void)p.token("FIELD array values");
  }
}

/// What a VTK cell type contributes.
enum class CellKind { Ignore, Triangle, Quad, Tet, Hex, Other };

/// Legacy VTK, ASCII: UNSTRUCTURED_GRID (classic or 5.1 cells) or POLYDATA (POLYGONS).
/// Reading stops at POINT_DATA / CELL_DATA.
MeshFile read_vtk(std::string_view text, const std::string& name) {
  MeshFile out;
  out.format = "vtk";
  Parser p(text, name, false);
  const std::string_view first = trim(p.scan.rest_of_line());
  if (!istarts_with(first, "# vtk DataFile"))
    p.fail(1, "not a legacy VTK file: the first line must be '# vtk DataFile Version x.y', found " +
                  in_quotes(first) + "; check the file's format");
  (void)p.scan.rest_of_line();  // title
  const Token encoding = p.token("ASCII or BINARY");
  if (iequals(encoding.text, "BINARY")) {
    p.fail(encoding.line,
           "binary legacy VTK is not supported; convert the file to ASCII (for example "
           "`meshio convert --ascii in.vtk out.vtk`, or save as ASCII from ParaView)");
  }
  if (!iequals(encoding.text, "ASCII"))
    p.fail(encoding.line, "expected ASCII or BINARY on line 3, found " + in_quotes(encoding.text) +
                              "; fix the header");
  std::string dataset;
  bool have_points = false;
  std::optional<CellArray> cells;
  std::optional<CellArray> polygons;
  std::vector<long long> types;
  std::size_t types_line = 0;
  std::size_t strip_triangles = 0;
  while (true) {
    const Token key = p.scan.next();
    if (key.empty()) break;
    if (iequals(key.text, "DATASET")) {
      const Token t = p.token("the DATASET type");
      dataset = lower(t.text);
      if (dataset != "unstructured_grid" && dataset != "polydata") {
        p.fail(t.line, "DATASET " + std::string(t.text) +
                           " is not supported (only UNSTRUCTURED_GRID and POLYDATA hold "
                           "cells); convert the mesh to an unstructured grid");
      }
    } else if (iequals(key.text, "POINTS")) {
      if (have_points) p.fail(key.line, "a second POINTS section; fix the file");
      const std::size_t n = p.count("the POINTS count", 3);
      // Coordinates are read as reals whatever the declared type; only a type that holds no
      // number (or a misspelt one) is refused. VTK 5.1 writers (meshio) use vtktype* names.
      const Token type = p.token("the POINTS data type");
      bool numeric = istarts_with(type.text, "vtktype") || iequals(type.text, "vtkidtype");
      for (const char* t :
           {"float", "double", "int", "unsigned_int", "long", "unsigned_long", "short",
            "unsigned_short", "char", "signed_char", "unsigned_char", "bit"})
        numeric = numeric || iequals(type.text, t);
      if (!numeric) {
        p.fail(type.line, "POINTS data type '" + std::string(type.text) +
                              "' is not a VTK numeric type (float, double, int, ...); fix the "
                              "POINTS line");
      }
      out.points.resize(static_cast<Eigen::Index>(n), 3);
      for (std::size_t i = 0; i < n; ++i)
        for (Eigen::Index k = 0; k < 3; ++k)
          out.points(static_cast<Eigen::Index>(i), k) = p.real("POINTS coordinates");
      have_points = true;
    } else if (iequals(key.text, "CELLS")) {
      cells = read_vtk_cells(p, key);
    } else if (iequals(key.text, "POLYGONS")) {
      polygons = read_vtk_cells(p, key);
    } else if (iequals(key.text, "VERTICES") || iequals(key.text, "LINES")) {
      (void)read_vtk_cells(p, key);
    } else if (iequals(key.text, "TRIANGLE_STRIPS")) {
      const CellArray strips = read_vtk_cells(p, key);
      for (std::size_t c = 0; c < strips.size(); ++c) {
        const long long k = strips.offsets[c + 1] - strips.offsets[c];
        if (k >= 3) strip_triangles += static_cast<std::size_t>(k - 2);
      }
    } else if (iequals(key.text, "CELL_TYPES")) {
      types_line = key.line;
      const std::size_t n = p.count("the CELL_TYPES count", 1);
      types.reserve(n);
      for (std::size_t i = 0; i < n; ++i) types.push_back(p.integer("a cell type"));
    } else if (iequals(key.text, "POINT_DATA") || iequals(key.text, "CELL_DATA")) {
      break;  // attributes: nothing we need
    } else if (iequals(key.text, "FIELD")) {
      skip_vtk_field(p);
    } else if (iequals(key.text, "METADATA")) {
      while (!p.scan.at_end() && !trim(p.scan.rest_of_line()).empty()) {
      }
    } else {
      p.fail(key.line, "unexpected keyword " + in_quotes(key.text) +
                           " (expected DATASET, POINTS, CELLS, CELL_TYPES, POLYGONS, "
                           "POINT_DATA or CELL_DATA); fix the file");
    }
  }
  if (dataset.empty()) p.fail(p.scan.line(), "no DATASET line; fix the file");
  if (!have_points) p.fail(p.scan.line(), "no POINTS section; the file holds no mesh");

  RawCells raw;
  std::array<long long, 8> nodes{};
  if (dataset == "polydata") {
    if (polygons) {
      for (std::size_t c = 0; c < polygons->size(); ++c) {
        const auto b = static_cast<std::size_t>(polygons->offsets[c]);
        const auto k = static_cast<std::size_t>(polygons->offsets[c + 1]) - b;
        if (k == 4) {
          raw.add_quad(&polygons->conn[b], polygons->lines[c], static_cast<long long>(c));
        } else {
          if (k == 3)
            ++out.triangles;
          else
            note_other_cell(out, polygons->lines[c],
                            "a polygon with " + std::to_string(k) + " nodes");
          raw.add_other(&polygons->conn[b], k, polygons->lines[c], static_cast<long long>(c));
        }
      }
    }
    out.triangles += strip_triangles;
    if (cells && cells->size() > 0)
      out.notes.push_back("ignored a CELLS section in a POLYDATA file (line " +
                          std::to_string(cells->header_line) + ")");
  } else if (cells) {
    if (types.size() != cells->size()) {
      p.fail(types_line != 0 ? types_line : cells->header_line,
             "CELL_TYPES lists " + std::to_string(types.size()) + " types but CELLS has " +
                 std::to_string(cells->size()) + " cells; fix the file");
    }
    std::size_t mislabelled = 0;
    std::size_t first_mislabelled = 0;
    std::size_t voxels = 0;
    for (std::size_t c = 0; c < cells->size(); ++c) {
      const auto b = static_cast<std::size_t>(cells->offsets[c]);
      const auto k = static_cast<std::size_t>(cells->offsets[c + 1]) - b;
      const long long* n = cells->conn.data() + b;
      const long long type = types[c];
      std::size_t need = 0;  // corners needed
      CellKind kind = CellKind::Other;
      switch (type) {
        case 1:
        case 2:
        case 3:
        case 4:
        case 21:
        case 35:
        case 68:
          kind = CellKind::Ignore;
          break;
        case 5:
        case 22:
        case 34:
        case 69:
          need = 3;
          kind = CellKind::Triangle;
          break;
        case 7:  // polygon
          kind = k == 3 ? CellKind::Triangle : (k == 4 ? CellKind::Quad : CellKind::Other);
          need = k == 4 ? 4 : 0;
          break;
        case 6:
          kind = CellKind::Triangle;
          break;  // strip: counted below
        case 8:
        case 9:
        case 23:
        case 28:
        case 30:
        case 70:
          need = 4;
          kind = CellKind::Quad;
          break;
        case 10:
        case 24:
        case 71:
          if (type == 10 && k == 8) {
            kind = CellKind::Hex;
            need = 8;
            if (mislabelled++ == 0) first_mislabelled = cells->lines[c];
          } else {
            kind = CellKind::Tet;
            need = 4;
          }
          break;
        case 11:
        case 12:
        case 25:
        case 29:
        case 33:
        case 72:
          need = 8;
          kind = CellKind::Hex;
          break;
        default:
          kind = CellKind::Other;
          break;
      }
      if (k < need) {
        p.fail(cells->lines[c], "cell " + std::to_string(c) + " of type " + std::to_string(type) +
                                    " has " + std::to_string(k) + " points, at least " +
                                    std::to_string(need) +
                                    " expected; fix the CELLS or CELL_TYPES");
      }
      for (std::size_t j = 0; j < k; ++j) {
        if (n[j] < 0 || n[j] >= out.points.rows()) {
          p.fail(cells->lines[c],
                 "cell " + std::to_string(c) + " uses point " + std::to_string(n[j]) +
                     ", which does not exist (valid indices are 0 .. " +
                     std::to_string(out.points.rows() - 1) + "); fix the CELLS or POINTS");
        }
      }
      switch (kind) {
        case CellKind::Ignore:
          break;
        case CellKind::Triangle:
          out.triangles += type == 6 ? (k >= 3 ? k - 2 : 0) : 1;
          break;
        case CellKind::Tet:
          ++out.tetrahedra;
          break;
        case CellKind::Other:
          note_other_cell(
              out, cells->lines[c],
              "VTK cell type " + std::to_string(type) + " with " + std::to_string(k) + " nodes");
          break;
        case CellKind::Quad:
          if (type == 8) {  // VTK_PIXEL: lexicographic order
            const std::array<long long, 4> q{n[0], n[1], n[3], n[2]};
            raw.add_quad(q.data(), cells->lines[c], static_cast<long long>(c));
          } else {
            raw.add_quad(n, cells->lines[c], static_cast<long long>(c));
          }
          break;
        case CellKind::Hex:
          if (type == 11) {  // VTK_VOXEL: lexicographic order
            ++voxels;
            constexpr std::array<std::size_t, 8> kVoxel{0, 1, 3, 2, 4, 5, 7, 6};
            for (std::size_t j = 0; j < 8; ++j) nodes[j] = n[kVoxel[j]];
            raw.add_hex(nodes.data(), cells->lines[c], static_cast<long long>(c));
          } else {
            raw.add_hex(n, cells->lines[c], static_cast<long long>(c));
          }
          break;
      }
    }
    if (mislabelled > 0) {
      out.notes.push_back(std::to_string(mislabelled) +
                          " cell(s) labelled VTK_TETRA (10) have 8 points and were read as "
                          "hexahedra (VTK_HEXAHEDRON is 12), first at line " +
                          std::to_string(first_mislabelled));
    }
    if (voxels > 0)
      out.notes.push_back(std::to_string(voxels) +
                          " VTK_VOXEL (11) cell(s) reordered to hexahedron order");
  }
  resolve(p, raw, NodeNumbering::dense(0), "cell", out);
  return out;
}

// ----------------------------------------------------------------------------------------
// VTU (ASCII)

/// The value of attribute `attr` in the XML tag `tag` (`<...>`), or empty.
std::string_view xml_attribute(std::string_view tag, std::string_view attr) {
  std::size_t pos = 0;
  while ((pos = tag.find(attr, pos)) != std::string_view::npos) {
    const bool starts = pos > 0 && (tag[pos - 1] == ' ' || tag[pos - 1] == '\t' ||
                                    tag[pos - 1] == '\n' || tag[pos - 1] == '\r');
    std::size_t q = pos + attr.size();
    while (q < tag.size() && (tag[q] == ' ' || tag[q] == '\t')) ++q;
    if (starts && q < tag.size() && tag[q] == '=') {
      ++q;
      while (q < tag.size() && (tag[q] == ' ' || tag[q] == '\t')) ++q;
      if (q < tag.size() && (tag[q] == '"' || tag[q] == '\'')) {
        const char quote = tag[q];
        const std::size_t end = tag.find(quote, q + 1);
        if (end != std::string_view::npos) return tag.substr(q + 1, end - q - 1);
      }
    }
    pos += attr.size();
  }
  return {};
}

/// VTK XML UnstructuredGrid with ASCII data arrays (one Piece).
MeshFile read_vtu(std::string_view text, const std::string& name) {
  MeshFile out;
  out.format = "vtu";
  Parser p(text, name, false);
  // Only for messages: counts the lines up to `pos`.
  const auto line_at = [&](std::size_t pos) {
    pos = std::min(pos, text.size());
    return static_cast<std::size_t>(
               std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n')) +
           1;
  };
  if (text.find("<VTKFile") == std::string_view::npos)
    p.fail(1, "not a VTK XML file (no <VTKFile> element); check the file's format");
  const std::size_t vtkfile = text.find("<VTKFile");
  {
    const std::string_view tag = text.substr(vtkfile, text.find('>', vtkfile) - vtkfile);
    const std::string_view type = xml_attribute(tag, "type");
    if (type != "UnstructuredGrid")
      p.fail(line_at(vtkfile), "VTKFile type " + in_quotes(type) +
                                   " is not supported; save the mesh as an UnstructuredGrid");
  }
  const std::size_t piece = text.find("<Piece", vtkfile);
  if (piece == std::string_view::npos) p.fail(line_at(text.size()), "no <Piece>; fix the file");
  const std::string_view piece_tag = text.substr(piece, text.find('>', piece) - piece);
  const auto np = to_integer(xml_attribute(piece_tag, "NumberOfPoints"));
  const auto nc = to_integer(xml_attribute(piece_tag, "NumberOfCells"));
  if (!np || !nc)
    p.fail(line_at(piece), "<Piece> needs NumberOfPoints and NumberOfCells; fix the file");
  // Finds the DataArray named `array` inside the element `<section>` (or the first array
  // when `array` is empty), parses its ASCII values.
  const auto read_array = [&](std::string_view section, std::string_view array,
                              std::size_t expected, auto&& store) {
    const std::size_t s = text.find("<" + std::string(section), piece);
    const std::size_t s_end = text.find("</" + std::string(section), piece);
    if (s == std::string_view::npos || s_end == std::string_view::npos)
      p.fail(line_at(piece), "no <" + std::string(section) + "> in the Piece; fix the file");
    std::size_t pos = s;
    while (true) {
      pos = text.find("<DataArray", pos);
      if (pos == std::string_view::npos || pos > s_end)
        p.fail(line_at(s), "no DataArray " + in_quotes(array) + " in <" + std::string(section) +
                               ">; fix the file");
      const std::size_t tag_end = text.find('>', pos);
      if (tag_end == std::string_view::npos) p.fail_end("a DataArray tag");
      const std::string_view tag = text.substr(pos, tag_end - pos);
      if (!array.empty() && xml_attribute(tag, "Name") != array) {
        pos = tag_end;
        continue;
      }
      const std::string_view fmt = xml_attribute(tag, "format");
      if (fmt != "ascii") {
        p.fail(line_at(pos), "DataArray " + in_quotes(xml_attribute(tag, "Name")) +
                                 " is stored as " + in_quotes(fmt) +
                                 "; only ASCII VTU is supported: save the file with ASCII data "
                                 "(ParaView: Data Mode = Ascii)");
      }
      const std::size_t data_end = text.find('<', tag_end);
      if (data_end == std::string_view::npos) p.fail_end("a DataArray");
      p.scan.seek(tag_end + 1);
      std::size_t n = 0;
      while (p.scan.pos() < data_end) {
        const Token t = p.scan.next();
        if (t.empty()) break;
        std::string_view v = t.text;
        const std::size_t cut = v.find('<');
        if (cut != std::string_view::npos) v = v.substr(0, cut);
        if (v.empty()) break;
        if (n >= expected)
          p.fail(t.line, "DataArray " + in_quotes(xml_attribute(tag, "Name")) + " has more than " +
                             std::to_string(expected) + " values; fix the file");
        store(n++, Token{v, t.line});
      }
      if (n != expected) {
        p.fail(line_at(pos), "DataArray " + in_quotes(xml_attribute(tag, "Name")) + " has " +
                                 std::to_string(n) + " values, " + std::to_string(expected) +
                                 " expected; fix the file");
      }
      return;
    }
  };
  p.check_count(*np, line_at(piece), "NumberOfPoints", 3);
  p.check_count(*nc, line_at(piece), "NumberOfCells", 2);
  // Arrays may come in any order: each search starts again from the top of the file.
  const auto restart = [&]() { p.scan = Scanner(text, false); };
  restart();
  out.points.resize(static_cast<Eigen::Index>(*np), 3);
  read_array("Points", "", static_cast<std::size_t>(*np) * 3, [&](std::size_t i, Token t) {
    out.points(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) =
        p.real(t, "point coordinate");
  });
  const auto cells = static_cast<std::size_t>(*nc);
  std::vector<long long> offsets(cells);
  std::vector<long long> types(cells);
  restart();
  read_array("Cells", "offsets", cells,
             [&](std::size_t i, Token t) { offsets[i] = p.integer(t, "offset"); });
  restart();
  read_array("Cells", "types", cells,
             [&](std::size_t i, Token t) { types[i] = p.integer(t, "cell type"); });
  const long long total = offsets.empty() ? 0 : offsets.back();
  for (std::size_t i = 0; i < cells; ++i) {
    if (offsets[i] < (i == 0 ? 0 : offsets[i - 1]) || offsets[i] > total)
      p.fail(line_at(piece), "offset " + std::to_string(i) + " (" + std::to_string(offsets[i]) +
                                 ") is out of order; fix the offsets array");
  }
  restart();  // the count is checked against the whole file
  p.check_count(total, line_at(piece), "connectivity entries", 1);
  std::vector<long long> conn(static_cast<std::size_t>(total));
  std::vector<std::size_t> conn_lines(static_cast<std::size_t>(total));
  restart();
  read_array("Cells", "connectivity", static_cast<std::size_t>(total), [&](std::size_t i, Token t) {
    conn[i] = p.integer(t, "point index");
    conn_lines[i] = t.line;
  });
  RawCells raw;
  std::size_t mislabelled = 0;
  for (std::size_t c = 0; c < cells; ++c) {
    const auto b = static_cast<std::size_t>(c == 0 ? 0 : offsets[c - 1]);
    const auto k = static_cast<std::size_t>(offsets[c]) - b;
    const std::size_t line = k > 0 ? conn_lines[b] : line_at(piece);
    const long long type = types[c];
    const bool hex = ((type == 12 || type == 25 || type == 29 || type == 72) && k >= 8) ||
                     (type == 10 && k == 8);
    if (type == 10 && k == 8) ++mislabelled;
    if (hex) {
      raw.add_hex(&conn[b], line, static_cast<long long>(c));
    } else if (type == 11 && k == 8) {
      const std::array<long long, 8> h{conn[b],     conn[b + 1], conn[b + 3], conn[b + 2],
                                       conn[b + 4], conn[b + 5], conn[b + 7], conn[b + 6]};
      raw.add_hex(h.data(), line, static_cast<long long>(c));
    } else if ((type == 9 || type == 23 || type == 28 || (type == 7 && k == 4)) && k >= 4) {
      raw.add_quad(&conn[b], line, static_cast<long long>(c));
    } else if (type == 5 || type == 22 || (type == 7 && k == 3)) {
      ++out.triangles;
    } else if (type == 10 || type == 24) {
      ++out.tetrahedra;
    } else if (type == 1 || type == 2 || type == 3 || type == 4 || type == 21) {
      // points and lines
    } else {
      note_other_cell(
          out, line,
          "VTK cell type " + std::to_string(type) + " with " + std::to_string(k) + " nodes");
    }
    for (std::size_t j = 0; j < k; ++j) {
      if (conn[b + j] < 0 || conn[b + j] >= out.points.rows())
        p.fail(line, "cell " + std::to_string(c) + " uses point " + std::to_string(conn[b + j]) +
                         ", which does not exist; fix the connectivity");
    }
  }
  if (mislabelled > 0) {
    out.notes.push_back(std::to_string(mislabelled) +
                        " cell(s) labelled VTK_TETRA (10) have 8 points and were read as "
                        "hexahedra (VTK_HEXAHEDRON is 12)");
  }
  resolve(p, raw, NodeNumbering::dense(0), "cell", out);
  return out;
}

// ----------------------------------------------------------------------------------------
// Gmsh MSH 2.2 and 4.1

/// Nodes and dimension of a Gmsh element type (0 nodes: unknown type).
struct GmshType {
  int nodes = 0;
  int dim = -1;
};

GmshType gmsh_type(long long type) {
  switch (type) {
    case 15:
      return {1, 0};
    case 1:
      return {2, 1};
    case 8:
      return {3, 1};
    case 26:
      return {4, 1};
    case 27:
      return {5, 1};
    case 28:
      return {6, 1};
    case 2:
      return {3, 2};
    case 9:
      return {6, 2};
    case 20:
      return {9, 2};
    case 21:
      return {10, 2};
    case 22:
      return {12, 2};
    // NOLINTNEXTLINE(bugprone-branch-clone): a table of node counts by element type
    case 23:
      return {15, 2};
    case 24:
      return {15, 2};
    case 25:
      return {21, 2};
    case 3:
      return {4, 2};
    case 10:
      return {9, 2};
    case 16:
      return {8, 2};
    case 36:
      return {16, 2};
    case 37:
      return {25, 2};
    case 38:
      return {36, 2};
    case 4:
      return {4, 3};
    case 11:
      return {10, 3};
    case 29:
      return {20, 3};
    case 30:
      return {35, 3};
    case 31:
      return {56, 3};
    case 5:
      return {8, 3};
    case 12:
      return {27, 3};
    case 17:
      return {20, 3};
    case 92:
      return {64, 3};
    case 93:
      return {125, 3};
    case 6:
      return {6, 3};
    case 13:
      return {18, 3};
    case 18:
      return {15, 3};
    case 7:
      return {5, 3};
    case 14:
      return {14, 3};
    case 19:
      return {13, 3};
    default:
      return {};
  }
}

bool gmsh_is_quad(long long t) {
  return t == 3 || t == 10 || t == 16 || (t >= 36 && t <= 38);
}
bool gmsh_is_hex(long long t) {
  return t == 5 || t == 12 || t == 17 || t == 92 || t == 93;
}
bool gmsh_is_triangle(long long t) {
  return t == 2 || t == 9 || (t >= 20 && t <= 25);
}
bool gmsh_is_tet(long long t) {
  return t == 4 || t == 11 || (t >= 29 && t <= 31);
}

/// Reads one element's node tags: exactly the type's count if known, else the rest of the
/// line. Classifies it into `out` / `raw`.
void read_gmsh_element(Parser& p, long long tag, long long type, std::size_t line,
                       std::vector<long long>& nodes, RawCells& raw, MeshFile& out,
                       std::size_t& unknown) {
  const GmshType info = gmsh_type(type);
  nodes.clear();
  if (info.nodes > 0) {
    for (int k = 0; k < info.nodes; ++k) {
      const Token t = p.scan.next();
      if (t.empty()) p.fail_end("element " + std::to_string(tag));
      nodes.push_back(p.integer(t, "node tag"));
    }
  } else {
    for (Token t = p.scan.next_on_line(); !t.empty(); t = p.scan.next_on_line())
      nodes.push_back(p.integer(t, "node tag"));
  }
  if (gmsh_is_hex(type)) {
    raw.add_hex(nodes.data(), line, tag);
  } else if (gmsh_is_quad(type)) {
    raw.add_quad(nodes.data(), line, tag);
  } else if (gmsh_is_triangle(type)) {
    ++out.triangles;
  } else if (gmsh_is_tet(type)) {
    ++out.tetrahedra;
  } else if (info.dim == 0 || info.dim == 1) {
    // points and lines: the geometry's skeleton
  } else {
    if (info.nodes == 0) ++unknown;
    note_other_cell(out, line,
                    "element " + std::to_string(tag) + " of Gmsh type " + std::to_string(type));
  }
}

/// Skips to the line after `$End<section>`.
void skip_gmsh_section(Parser& p, const Token& start) {
  const std::string end = "$End" + std::string(start.text.substr(1));
  while (true) {
    const Token t = p.scan.next();
    if (t.empty())
      p.fail(start.line, "section " + std::string(start.text) + " has no " + end +
                             "; the file looks truncated");
    if (t.text == end) return;
    p.scan.skip_line();
  }
}

MeshFile read_msh(std::string_view text, const std::string& name) {
  MeshFile out;
  Parser p(text, name, false);
  int major = 0;
  NodeNumbering numbering = NodeNumbering::tagged();
  std::vector<double> xyz;
  RawCells raw;
  std::vector<long long> nodes;
  std::size_t unknown = 0;
  bool have_format = false;
  const auto expect_end = [&](std::string_view section) {
    const Token t = p.token("$End" + std::string(section));
    if (t.text != "$End" + std::string(section))
      p.fail(t.line, "expected $End" + std::string(section) + ", found " + in_quotes(t.text) +
                         "; the counts of the section do not match its content");
  };
  const auto add_node = [&](long long tag, std::size_t line) {
    if (!numbering.add(tag, xyz.size() / 3))
      p.fail(line, "node tag " + std::to_string(tag) + " is defined twice; fix the file");
  };
  while (true) {
    const Token section = p.scan.next();
    if (section.empty()) break;
    if (section.text.empty() || section.text.front() != '$')
      p.fail(section.line, "expected a section ($MeshFormat, $Nodes, $Elements, ...), found " +
                               in_quotes(section.text) + "; check the file's format");
    if (section.text == "$MeshFormat") {
      const Token version = p.token("the MSH version");
      const long long file_type = p.integer("the MSH file type");
      (void)p.integer("the MSH data size");
      if (file_type != 0) {
        p.fail(version.line,
               "binary MSH files are not supported; save the mesh as ASCII "
               "(gmsh -save -format msh41 with Mesh.Binary = 0)");
      }
      if (version.text == "4.1") {
        major = 4;
      } else if (istarts_with(version.text, "2")) {
        major = 2;
      } else {
        p.fail(version.line, "MSH version " + in_quotes(version.text) +
                                 " is not supported (2.2 and 4.1 are); re-save the mesh with "
                                 "Gmsh as MSH 4.1 or 2.2");
      }
      out.format = major == 4 ? "msh4" : "msh2";
      have_format = true;
      p.scan.skip_line();
      expect_end("MeshFormat");
    } else if (section.text == "$Nodes") {
      if (!have_format) p.fail(section.line, "$Nodes before $MeshFormat; fix the file");
      if (major == 2) {
        const std::size_t n = p.count("the node count", 4);
        xyz.reserve(xyz.size() + 3 * n);
        numbering.expect(n);
        for (std::size_t i = 0; i < n; ++i) {
          const Token t = p.token("a node");
          add_node(p.integer(t, "node tag"), t.line);
          for (int k = 0; k < 3; ++k) xyz.push_back(p.real("node coordinates"));
        }
      } else {
        const std::size_t blocks = p.count("the number of node blocks", 4);
        const std::size_t n = p.count("the node count", 4);
        (void)p.integer("the minimum node tag");
        (void)p.integer("the maximum node tag");
        xyz.reserve(xyz.size() + 3 * n);
        numbering.expect(n);
        std::vector<std::pair<long long, std::size_t>> tags;
        std::size_t read = 0;
        for (std::size_t b = 0; b < blocks; ++b) {
          const Token block = p.token("a node block");
          const long long dim = p.integer(block, "entity dimension");
          (void)p.integer("entity tag");
          const long long parametric = p.integer("parametric flag");
          const std::size_t in_block = p.count("nodes in block", 4);
          if (dim < 0 || dim > 3)
            p.fail(block.line,
                   "node block with entity dimension " + std::to_string(dim) + "; fix the file");
          const std::size_t params = parametric != 0 ? static_cast<std::size_t>(dim) : 0;
          tags.clear();
          for (std::size_t i = 0; i < in_block; ++i) {
            const Token t = p.token("node tags");
            tags.emplace_back(p.integer(t, "node tag"), t.line);
          }
          for (std::size_t i = 0; i < in_block; ++i) {
            add_node(tags[i].first, tags[i].second);
            for (int k = 0; k < 3; ++k) xyz.push_back(p.real("node coordinates"));
            for (std::size_t k = 0; k < params; ++k) (void)p.real("parametric coordinates");
          }
          read += in_block;
        }
        if (read != n) {
          p.fail(section.line, "$Nodes announces " + std::to_string(n) +
                                   " nodes but its blocks hold " + std::to_string(read) +
                                   "; fix the file");
        }
      }
      expect_end("Nodes");
    } else if (section.text == "$Elements") {
      if (!have_format) p.fail(section.line, "$Elements before $MeshFormat; fix the file");
      if (major == 2) {
        const std::size_t n = p.count("the element count", 4);
        for (std::size_t i = 0; i < n; ++i) {
          const Token t = p.token("an element");
          const long long tag = p.integer(t, "element tag");
          const long long type = p.integer("element type");
          const long long ntags = p.integer("number of element tags");
          if (ntags < 0 || ntags > 64)
            p.fail(t.line, "element " + std::to_string(tag) + " has " + std::to_string(ntags) +
                               " tags; fix the file");
          for (long long k = 0; k < ntags; ++k) (void)p.integer("element tags");
          read_gmsh_element(p, tag, type, t.line, nodes, raw, out, unknown);
        }
      } else {
        const std::size_t blocks = p.count("the number of element blocks", 4);
        const std::size_t n = p.count("the element count", 2);
        (void)p.integer("the minimum element tag");
        (void)p.integer("the maximum element tag");
        std::size_t read = 0;
        for (std::size_t b = 0; b < blocks; ++b) {
          (void)p.integer("entity dimension");
          (void)p.integer("entity tag");
          const long long type = p.integer("element type");
          const std::size_t in_block = p.count("elements in block", 2);
          for (std::size_t i = 0; i < in_block; ++i) {
            const Token t = p.token("an element");
            read_gmsh_element(p, p.integer(t, "element tag"), type, t.line, nodes, raw, out,
                              unknown);
          }
          read += in_block;
        }
        if (read != n) {
          p.fail(section.line, "$Elements announces " + std::to_string(n) +
                                   " elements but its blocks hold " + std::to_string(read) +
                                   "; fix the file");
        }
      }
      expect_end("Elements");
    } else {
      skip_gmsh_section(p, section);
    }
  }
  if (!have_format) p.fail(1, "no $MeshFormat section: not a Gmsh MSH file; check the format");
  if (unknown > 0)
    out.notes.push_back(std::to_string(unknown) +
                        " element(s) of an unknown Gmsh type counted as other cells");
  set_points(xyz, out);
  resolve(p, raw, numbering, "element tag", out);
  return out;
}

// ----------------------------------------------------------------------------------------
// MEDIT

/// MEDIT `.mesh` (ASCII): keywords followed by a count and records; `#` comments.
MeshFile read_medit(std::string_view text, const std::string& name) {
  MeshFile out;
  out.format = "medit";
  Parser p(text, name, true);
  long long dim = 3;
  bool have_vertices = false;
  RawCells raw;
  std::array<long long, 8> nodes{};
  bool used_quads_keyword = false;
  // Keywords whose records are skipped: name -> integers per record (-1: `dim` reals).
  struct Skip {
    std::string_view word;
    int ints;
    int reals;  // -1: dim reals
  };
  static constexpr std::array<Skip, 20> kSkip{{{"Corners", 1, 0},
                                               {"RequiredVertices", 1, 0},
                                               {"Ridges", 1, 0},
                                               {"RequiredEdges", 1, 0},
                                               {"RequiredTriangles", 1, 0},
                                               {"RequiredQuadrilaterals", 1, 0},
                                               {"Edges", 3, 0},
                                               {"EdgesP2", 4, 0},
                                               {"Normals", 0, -1},
                                               {"Tangents", 0, -1},
                                               {"NormalAtVertices", 2, 0},
                                               {"TangentAtVertices", 2, 0},
                                               {"TangentAtEdges", 3, 0},
                                               {"NormalAtTriangleVertices", 3, 0},
                                               {"NormalAtQuadrilateralVertices", 3, 0},
                                               {"Prisms", 7, 0},
                                               {"Pyramids", 6, 0},
                                               {"TrianglesP2", 7, 0},
                                               {"TetrahedraP2", 11, 0},
                                               {"QuadrilateralsQ2", 10, 0}}};
  long long element = 0;
  bool ended = false;
  while (!ended) {
    const Token key = p.scan.next();
    if (key.empty()) break;
    const std::string_view k = key.text;
    if (k == "MeshVersionFormatted") {
      const long long v = p.integer("the MEDIT version");
      if (v < 1 || v > 4)
        p.fail(key.line, "MeshVersionFormatted " + std::to_string(v) +
                             " is not a MEDIT version (1 to 4); fix the file");
    } else if (k == "Dimension") {
      dim = p.integer("the dimension");
      if (dim != 2 && dim != 3)
        p.fail(key.line, "Dimension " + std::to_string(dim) + " is not 2 or 3; fix the file");
    } else if (k == "Vertices") {
      if (have_vertices) p.fail(key.line, "a second Vertices section; fix the file");
      have_vertices = true;
      const std::size_t n = p.count("the number of vertices", static_cast<std::size_t>(dim) + 1);
      out.points.resize(static_cast<Eigen::Index>(n), 3);
      for (std::size_t i = 0; i < n; ++i) {
        for (Eigen::Index c = 0; c < 3; ++c)
          out.points(static_cast<Eigen::Index>(i), c) =
              c < dim ? p.real("vertex coordinates") : 0.0;
        (void)p.integer("the vertex reference");
      }
    } else if (k == "Quadrilaterals" || k == "Quads" || k == "Hexahedra" || k == "Hexaedra" ||
               k == "Triangles" || k == "Tetrahedra" || k == "HexahedraQ2") {
      if (k == "Quads") used_quads_keyword = true;
      const bool quad = k == "Quadrilaterals" || k == "Quads";
      const bool hex = k == "Hexahedra" || k == "Hexaedra" || k == "HexahedraQ2";
      const std::size_t per = quad  ? 4
                              : hex ? (k == "HexahedraQ2" ? 27 : 8)
                                    : (k == "Triangles" ? 3 : 4);
      const std::size_t n = p.count("the number of " + std::string(k), per + 1);
      for (std::size_t i = 0; i < n; ++i) {
        const Token first = p.token(std::string(k));
        ++element;
        for (std::size_t j = 0; j < per; ++j) {
          const long long v = j == 0 ? p.integer(first, "a vertex number")
                                     : p.integer(std::string(k) + " vertex numbers");
          if (j < 8) nodes[j] = v;
        }
        (void)p.integer("the element reference");
        if (quad)
          raw.add_quad(nodes.data(), first.line, static_cast<long long>(i) + 1);
        else if (hex)
          raw.add_hex(nodes.data(), first.line, static_cast<long long>(i) + 1);
        else if (k == "Triangles")
          ++out.triangles;
        else
          ++out.tetrahedra;
        if (!quad && !hex)
          raw.add_other(nodes.data(), std::min<std::size_t>(per, 8), first.line,
                        static_cast<long long>(i) + 1);
      }
    } else if (k == "End") {
      ended = true;
    } else if (k == "Identifier" || k == "Geometry") {
      p.scan.skip_line();
      if (k == "Identifier") p.scan.skip_line();
    } else {
      const auto* skip =
          std::find_if(kSkip.begin(), kSkip.end(), [&](const Skip& s) { return s.word == k; });
      if (skip == kSkip.end()) {
        p.fail(key.line, "unknown MEDIT keyword " + in_quotes(k) +
                             " (expected Vertices, Quadrilaterals, Hexahedra, Triangles, "
                             "Tetrahedra, ... or End); fix the file");
      }
      const auto per = static_cast<std::size_t>(skip->ints) +
                       static_cast<std::size_t>(skip->reals < 0 ? dim : skip->reals);
      const std::size_t n = p.count("the number of " + std::string(k), per);
      const bool volume = k == "Prisms" || k == "Pyramids";
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < per; ++j) {
          const Token t = p.token(std::string(k));
          if (volume && j == 0) {
            note_other_cell(out, t.line,
                            std::string(k == "Prisms" ? "a prism" : "a pyramid") + " (" +
                                std::string(k) + " record " + std::to_string(i + 1) + ")");
          }
        }
      }
    }
  }
  if (!have_vertices) p.fail(p.scan.line(), "no Vertices section; the file holds no mesh");
  if (used_quads_keyword)
    out.notes.push_back("non-standard keyword 'Quads' read as 'Quadrilaterals'");
  resolve(p, raw, NodeNumbering::dense(1), "element", out);
  return out;
}

// ----------------------------------------------------------------------------------------
// MFEM

/// Vertices of an MFEM geometry type (0: unknown).
int mfem_geometry_nodes(long long geometry) {
  switch (geometry) {
    case 0:
      return 1;
    case 1:
      return 2;
    case 2:
      return 3;
    // NOLINTNEXTLINE(bugprone-branch-clone): a table of corner counts by element type
    case 3:
      return 4;
    case 4:
      return 4;
    case 5:
      return 8;
    case 6:
      return 6;
    case 7:
      return 5;
    default:
      return 0;
  }
}

/// MFEM mesh v1.0 (and v1.1/v1.2 without their extra sections): `dimension`, `elements`,
/// `boundary` (skipped), `vertices`, and for curved meshes `nodes` (H1 space; the first
/// nvertices dofs are the vertices).
MeshFile read_mfem(std::string_view text, const std::string& name) {
  MeshFile out;
  out.format = "mfem";
  Parser p(text, name, true);
  const std::string_view header = trim(p.scan.rest_of_line());
  if (!istarts_with(header, "MFEM mesh v1."))
    p.fail(1, "unsupported MFEM header " + in_quotes(header) +
                  " (expected 'MFEM mesh v1.0'); convert the mesh to MFEM mesh v1.0");
  RawCells raw;
  long long dim = 0;
  bool have_vertices = false;
  std::size_t num_vertices = 0;
  std::size_t vertices_line = 0;
  std::vector<long long> nodes;
  bool have_elements = false;
  const auto read_element = [&](long long index, bool keep) {
    const Token first = p.token("an element");
    (void)p.integer(first, "element attribute");
    const long long geometry = p.integer("element geometry");
    const int nv = mfem_geometry_nodes(geometry);
    if (nv == 0)
      p.fail(first.line, "element " + std::to_string(index) + " has unknown geometry " +
                             std::to_string(geometry) + " (MFEM types are 0 to 7); fix the file");
    nodes.clear();
    for (int k = 0; k < nv; ++k) nodes.push_back(p.integer("element vertices"));
    if (!keep) return;
    if (geometry == 5) {
      raw.add_hex(nodes.data(), first.line, index);
    } else if (geometry == 3) {
      raw.add_quad(nodes.data(), first.line, index);
    } else if (geometry == 2) {
      ++out.triangles;
    } else if (geometry == 4) {
      ++out.tetrahedra;
    } else if (geometry >= 6) {
      note_other_cell(
          out, first.line,
          "element " + std::to_string(index) + " of MFEM geometry " + std::to_string(geometry));
    }
    if (geometry != 5 && geometry != 3)
      raw.add_other(nodes.data(), nodes.size(), first.line, index);
  };
  while (true) {
    const Token key = p.scan.next();
    if (key.empty() || key.text == "mfem_mesh_end") break;
    if (key.text == "dimension") {
      dim = p.integer("the dimension");
      if (dim < 1 || dim > 3)
        p.fail(key.line, "dimension " + std::to_string(dim) + " is not 1, 2 or 3; fix the file");
    } else if (key.text == "elements") {
      have_elements = true;
      const std::size_t n = p.count("the number of elements", 3);
      for (std::size_t i = 0; i < n; ++i) read_element(static_cast<long long>(i), true);
    } else if (key.text == "boundary") {
      const std::size_t n = p.count("the number of boundary elements", 3);
      for (std::size_t i = 0; i < n; ++i) read_element(static_cast<long long>(i), false);
    } else if (key.text == "vertices") {
      have_vertices = true;
      vertices_line = key.line;
      num_vertices = p.count("the number of vertices", 1);
      const Token next = p.scan.peek();
      if (next.text == "nodes") continue;  // curved mesh: coordinates come from `nodes`
      const long long sdim = p.integer("the space dimension");
      if (sdim < 1 || sdim > 3)
        p.fail(next.line,
               "space dimension " + std::to_string(sdim) + " is not 1, 2 or 3; fix the file");
      p.check_count(static_cast<long long>(num_vertices), next.line, "vertices",
                    static_cast<std::size_t>(sdim));
      out.points.resize(static_cast<Eigen::Index>(num_vertices), 3);
      out.points.setZero();
      for (std::size_t i = 0; i < num_vertices; ++i) {
        for (long long c = 0; c < sdim; ++c)
          out.points(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)) =
              p.real("vertex coordinates");
      }
    } else if (key.text == "nodes") {
      if (!have_vertices)
        p.fail(key.line, "'nodes' before 'vertices': the vertex count is unknown; fix the file");
      p.expect("FiniteElementSpace");
      std::string collection;
      long long vdim = 0;
      long long ordering = -1;
      std::size_t collection_line = key.line;
      while (true) {
        const Token t = p.scan.peek();
        if (t.text == "FiniteElementCollection:") {
          (void)p.token("FiniteElementCollection");
          const Token c = p.token("the finite element collection");
          collection = std::string(c.text);
          collection_line = c.line;
        } else if (t.text == "VDim:") {
          (void)p.token("VDim");
          vdim = p.integer("VDim");
        } else if (t.text == "Ordering:") {
          (void)p.token("Ordering");
          ordering = p.integer("Ordering");
        } else {
          break;
        }
      }
      const bool h1 = istarts_with(collection, "H1_") || istarts_with(collection, "H1Pos_") ||
                      collection == "Linear" || collection == "Quadratic" || collection == "Cubic";
      if (!h1) {
        p.fail(collection_line, "curved MFEM mesh with node space " + in_quotes(collection) +
                                    ": only H1 (continuous) nodes are supported, where the "
                                    "first dofs are the vertices; project the nodes to H1");
      }
      if (vdim < 1 || vdim > 3)
        p.fail(collection_line, "VDim " + std::to_string(vdim) + " is not 1, 2 or 3; fix the file");
      out.points.resize(static_cast<Eigen::Index>(num_vertices), 3);
      out.points.setZero();
      const auto v = static_cast<std::size_t>(vdim);
      if (ordering == 1) {  // byVDIM: x y z of dof 0, dof 1, ...
        p.check_count(static_cast<long long>(num_vertices), key.line, "vertex dofs", v);
        for (std::size_t i = 0; i < num_vertices; ++i) {
          for (std::size_t c = 0; c < v; ++c)
            out.points(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)) =
                p.real("node coordinates");
        }
        // The remaining dofs (edge, face, interior) are not needed.
        while (!p.scan.at_end()) {
          const Token t = p.scan.peek();
          if (t.text == "mfem_mesh_end") break;
          if (!to_real(t.text)) break;
          (void)p.scan.next();
        }
      } else if (ordering == 0) {  // byNODES: all x, then all y, then all z
        std::vector<double> values;
        while (!p.scan.at_end()) {
          const Token t = p.scan.peek();
          const auto value = to_real(t.text);
          if (!value) break;
          (void)p.scan.next();
          values.push_back(*value);
        }
        const std::size_t ndofs = values.size() / v;
        if (values.size() % v != 0 || ndofs < num_vertices) {
          p.fail(key.line, "the nodes hold " + std::to_string(values.size()) +
                               " values, not a multiple of VDim " + std::to_string(vdim) +
                               " covering the " + std::to_string(num_vertices) +
                               " vertices; the file looks truncated");
        }
        for (std::size_t i = 0; i < num_vertices; ++i) {
          for (std::size_t c = 0; c < v; ++c)
            out.points(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)) =
                values[c * ndofs + i];
        }
      } else {
        p.fail(key.line, "MFEM nodes without 'Ordering: 0' or 'Ordering: 1'; fix the file");
      }
    } else {
      p.fail(key.line, "unknown MFEM section " + in_quotes(key.text) +
                           " (expected dimension, elements, boundary, vertices or nodes); "
                           "convert the mesh to MFEM mesh v1.0");
    }
  }
  if (!have_elements) p.fail(p.scan.line(), "no 'elements' section; the file holds no mesh");
  if (!have_vertices) p.fail(p.scan.line(), "no 'vertices' section; the file holds no mesh");
  if (out.points.rows() != static_cast<Eigen::Index>(num_vertices)) {
    p.fail(vertices_line,
           "the vertices have no coordinates (neither a space dimension and "
           "coordinates nor a 'nodes' section); fix the file");
  }
  if (dim == 0) p.fail(1, "no 'dimension' section; fix the file");
  resolve(p, raw, NodeNumbering::dense(0), "element", out);
  return out;
}

// ----------------------------------------------------------------------------------------
// Abaqus INP

/// Abaqus `.inp`: `*NODE` (id, x, y, z) and `*ELEMENT, TYPE=...` (id, nodes; a line ending
/// with a comma continues on the next). Other keywords and their data are skipped.
MeshFile read_inp(std::string_view text, const std::string& name) {
  MeshFile out;
  out.format = "inp";
  Parser p(text, name, false);
  NodeNumbering numbering = NodeNumbering::tagged();
  std::vector<double> xyz;
  RawCells raw;
  enum class Block { None, Node, Element };
  Block block = Block::None;
  std::string element_type;
  std::vector<std::string_view> fields;
  std::vector<long long> nodes;
  const auto split = [&](std::string_view line) {
    fields.clear();
    std::size_t start = 0;
    while (start <= line.size()) {
      std::size_t comma = line.find(',', start);
      if (comma == std::string_view::npos) comma = line.size();
      fields.push_back(trim(line.substr(start, comma - start)));
      start = comma + 1;
    }
  };
  while (!p.scan.at_end()) {
    const std::size_t line = p.scan.line();
    std::string_view text_line = trim(p.scan.rest_of_line());
    if (text_line.empty() || text_line.starts_with("**")) continue;
    if (text_line.front() == '*') {
      split(text_line);
      const std::string keyword = lower(fields[0]);
      block = Block::None;
      if (keyword == "*node") {
        block = Block::Node;
      } else if (keyword == "*element") {
        block = Block::Element;
        element_type.clear();
        for (std::size_t i = 1; i < fields.size(); ++i) {
          const std::string f = lower(fields[i]);
          if (f.starts_with("type")) {
            const std::size_t eq = f.find('=');
            if (eq != std::string::npos) element_type = std::string(trim(f.substr(eq + 1)));
          }
        }
        if (element_type.empty()) p.fail(line, "*ELEMENT without TYPE=; fix the file");
      }
      continue;
    }
    if (block == Block::Node) {
      split(text_line);
      if (fields.size() < 3) p.fail(line, "a *NODE line needs an id and coordinates; fix the file");
      const long long id = p.integer(Token{fields[0], line}, "node id");
      if (!numbering.add(id, xyz.size() / 3))
        p.fail(line, "node " + std::to_string(id) + " is defined twice; fix the file");
      for (std::size_t c = 1; c <= 3; ++c)
        xyz.push_back(c < fields.size() ? p.real(Token{fields[c], line}, "node coordinate") : 0.0);
    } else if (block == Block::Element) {
      nodes.clear();
      std::string_view current = text_line;
      std::size_t element_line = line;
      long long id = 0;
      bool first = true;
      while (true) {
        split(current);
        const bool continued = current.back() == ',';
        for (std::size_t i = 0; i < fields.size(); ++i) {
          if (fields[i].empty()) continue;
          const long long v = p.integer(Token{fields[i], element_line}, "element field");
          if (first) {
            id = v;
            first = false;
          } else {
            nodes.push_back(v);
          }
        }
        if (!continued || p.scan.at_end()) break;
        element_line = p.scan.line();
        current = trim(p.scan.rest_of_line());
        if (current.empty()) break;
      }
      const std::string& t = element_type;
      const auto is = [&](std::string_view prefix) { return t.starts_with(prefix); };
      if ((is("c3d8") || is("c3d20") || is("c3d27")) && nodes.size() >= 8) {
        raw.add_hex(nodes.data(), line, id);
      } else if ((is("s4") || is("s8") || is("s9") || is("m3d4") || is("m3d8") || is("m3d9") ||
                  is("r3d4") || is("sfm3d4") || is("sfm3d8") || is("cps4") || is("cpe4") ||
                  is("cax4") || is("cps8") || is("cpe8") || is("cax8")) &&
                 nodes.size() >= 4) {
        raw.add_quad(nodes.data(), line, id);
      } else if (is("s3") || is("m3d3") || is("r3d3") || is("stri") || is("cps3") || is("cpe3") ||
                 is("cax3") || is("m3d6") || is("stri65") || is("cps6")) {
        ++out.triangles;
      } else if (is("c3d4") || is("c3d10")) {
        ++out.tetrahedra;
      } else if (is("t3d") || is("b3") || is("b2") || is("t2d") || is("mass") || is("spring") ||
                 is("dashpot")) {
        // lines and points
      } else {
        std::string shown = element_type;
        for (char& ch : shown) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
        note_other_cell(out, line,
                        "element " + std::to_string(id) + " of type " + shown + " with " +
                            std::to_string(nodes.size()) + " nodes");
      }
    }
  }
  set_points(xyz, out);
  resolve(p, raw, numbering, "element", out);
  return out;
}

// ----------------------------------------------------------------------------------------
// Dispatch

/// The format guessed from the first bytes, or Auto.
Format sniff(std::string_view text) {
  text = without_byte_order_mark(text);
  std::size_t i = 0;
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  const std::string_view s = text.substr(i);
  if (s.starts_with("MFEM")) return Format::Mfem;
  if (istarts_with(s, "# vtk")) return Format::Vtk;
  if (s.starts_with("$MeshFormat")) return Format::Msh;
  if (s.starts_with("MeshVersionFormatted")) return Format::Medit;
  if (s.starts_with("<?xml") || s.starts_with("<VTKFile")) return Format::Vtu;
  if (s.starts_with("OFF") || s.starts_with("COFF") || s.starts_with("NOFF")) return Format::Off;
  return Format::Auto;
}

MeshFile read_text(std::string_view text, Format format, const std::string& name) {
  text = without_byte_order_mark(text);
  if (text.empty()) throw InvalidInput(name + ":1: the file is empty; give a mesh file");
  // A file starting with MFEM is MFEM whatever its extension (MFEM uses `.mesh` too).
  if (sniff(text) == Format::Mfem) format = Format::Mfem;
  MeshFile out;
  switch (format) {
    case Format::Obj:
      out = read_obj(text, name);
      break;
    case Format::Off:
      out = read_off(text, name);
      break;
    case Format::Vtk:
      out = read_vtk(text, name);
      break;
    case Format::Vtu:
      out = read_vtu(text, name);
      break;
    case Format::Msh:
    case Format::Msh2:
      out = read_msh(text, name);
      break;
    case Format::Medit:
      out = read_medit(text, name);
      break;
    case Format::Mfem:
      out = read_mfem(text, name);
      break;
    case Format::Inp:
      out = read_inp(text, name);
      break;
    case Format::Auto:
      throw InvalidInput(name +
                         ": cannot tell the mesh format from the content; name the format "
                         "(obj, off, vtk, vtu, msh, msh2, mesh, mfem, inp)");
  }
  out.path = name;
  return out;
}

}  // namespace

// ------------------------------------------------------------------------------------------
// Public API

std::string_view format_name(Format format) {
  switch (format) {
    case Format::Auto:
      return "auto";
    case Format::Obj:
      return "obj";
    case Format::Off:
      return "off";
    case Format::Vtk:
      return "vtk";
    case Format::Vtu:
      return "vtu";
    case Format::Msh:
      return "msh";
    case Format::Msh2:
      return "msh2";
    case Format::Medit:
      return "medit";
    case Format::Mfem:
      return "mfem";
    case Format::Inp:
      return "inp";
  }
  return "auto";
}

Format format_from_name(std::string_view name) {
  const std::string n = lower(trim(name));
  if (n == "obj") return Format::Obj;
  if (n == "off") return Format::Off;
  if (n == "vtk") return Format::Vtk;
  if (n == "vtu") return Format::Vtu;
  if (n == "msh" || n == "msh4" || n == "msh41") return Format::Msh;
  if (n == "msh2" || n == "msh22") return Format::Msh2;
  if (n == "mesh" || n == "medit") return Format::Medit;
  if (n == "mfem") return Format::Mfem;
  if (n == "inp" || n == "abaqus") return Format::Inp;
  throw InvalidInput("unknown mesh format " + in_quotes(name) +
                     "; valid names are obj, off, vtk, vtu, msh, msh2, mesh (or medit), mfem, "
                     "inp");
}

Format format_from_path(const std::filesystem::path& path) {
  const std::string ext = lower(path.extension().string());
  if (ext == ".obj") return Format::Obj;
  if (ext == ".off") return Format::Off;
  if (ext == ".vtk") return Format::Vtk;
  if (ext == ".vtu") return Format::Vtu;
  if (ext == ".msh") return Format::Msh;
  if (ext == ".mesh") return Format::Medit;
  if (ext == ".inp") return Format::Inp;
  if (ext == ".meshb")
    throw InvalidInput(path.string() +
                       ": binary MEDIT (.meshb) is not supported; convert it to ASCII .mesh");
  throw InvalidInput(path.string() + ": cannot tell the mesh format from the extension " +
                     in_quotes(ext.empty() ? std::string("(none)") : ext) +
                     "; use .obj, .off, .vtk, .vtu, .msh, .mesh or .inp, or name the format");
}

MeshFile read_mesh(std::istream& in, Format format, const std::string& name) {
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw IoError(name + ": cannot read the stream; check the input");
  if (format == Format::Auto) {
    format = sniff(text);
  }
  return read_text(text, format, name);
}

MeshFile read_mesh(const std::filesystem::path& path, Format format) {
  const std::string name = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw IoError(name + ": is a folder, not a mesh file; give a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(name + ": cannot open the file; check that it exists and is readable");
  std::string text;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size > 0) {
    text.resize(static_cast<std::size_t>(size));
    in.seekg(0, std::ios::beg);
    in.read(text.data(), size);
    if (in.gcount() != size) throw IoError(name + ": cannot read the whole file; check the disk");
  } else {
    in.clear();
    in.seekg(0, std::ios::beg);
    text.assign((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  if (format == Format::Auto) {
    const Format by_content = sniff(text);
    if (by_content == Format::Mfem) {
      format = Format::Mfem;
    } else {
      const std::string ext = lower(path.extension().string());
      const bool known = ext == ".obj" || ext == ".off" || ext == ".vtk" || ext == ".vtu" ||
                         ext == ".msh" || ext == ".mesh" || ext == ".inp" || ext == ".meshb";
      if (known || by_content == Format::Auto)
        format = format_from_path(path);
      else
        format = by_content;
    }
  }
  return read_text(text, format, name);
}

}  // namespace stcweave::primal
