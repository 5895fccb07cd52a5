/// \file
/// The browser page: the template (page.html) with the stylesheet, three.js, the page's
/// script and the mesh data put in place. The data is a JSON object whose big arrays are
/// base64 strings of little-endian typed arrays, so that a 50k-hex page stays a few MB and
/// decodes in milliseconds.

#include "stcweave/viewer/page.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string_view>

#include "assets.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::viewer {

namespace {

/// Little-endian bytes of a float32 array.
class Bytes {
 public:
  void f32(float v) {
    std::uint32_t u = 0;
    std::memcpy(&u, &v, sizeof u);
    for (int k = 0; k < 4; ++k) bytes_.push_back(static_cast<std::uint8_t>((u >> (8 * k)) & 0xffU));
  }
  [[nodiscard]] std::string base64() const { return viewer::base64(bytes_); }

 private:
  std::vector<std::uint8_t> bytes_;
};

/// Integers as the page stores them: value - offset (offset = the least value) in the
/// narrowest unsigned little-endian type that holds them (1, 2 or 4 bytes), base64.
nlohmann::json ints_json(const std::vector<std::int32_t>& values) {
  const auto [lo_it, hi_it] = std::minmax_element(values.begin(), values.end());
  const std::int64_t lo = values.empty() ? 0 : *lo_it;
  const std::int64_t span = values.empty() ? 0 : std::int64_t{*hi_it} - lo;
  const int width = span < 256 ? 1 : span < 65536 ? 2 : 4;
  std::vector<std::uint8_t> bytes;
  bytes.reserve(values.size() * static_cast<std::size_t>(width));
  for (const std::int32_t v : values) {
    const auto u = static_cast<std::uint32_t>(std::int64_t{v} - lo);
    for (int k = 0; k < width; ++k)
      bytes.push_back(static_cast<std::uint8_t>((u >> (8 * k)) & 0xffU));
  }
  return {{"offset", lo}, {"bytes", width}, {"data", base64(bytes)}};
}

/// The cell array `name` of `data` when it has one value per hex, else nullptr.
const primal::DataArray* cell_array(const primal::MeshData& data, std::string_view name,
                                    std::size_t hexes) {
  const primal::DataArray* a = data.cell(name);
  if (a == nullptr) return nullptr;
  if (a->values.size() != hexes) {
    throw InvalidInput("viewer: cell array '" + std::string(name) + "' has " +
                       std::to_string(a->values.size()) + " values for " + std::to_string(hexes) +
                       " hexes; it does not belong to this mesh");
  }
  return a;
}

/// `text` with every "</" written "<\/" so that it cannot close the script element.
std::string script_safe(const std::string& text) {
  std::string out;
  out.reserve(text.size() + 16);
  for (std::size_t i = 0; i < text.size(); ++i) {
    out.push_back(text[i]);
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') out.push_back('\\');
  }
  return out;
}

std::string html_escape(std::string_view s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out.push_back(c);
    }
  }
  return out;
}

nlohmann::json page_data(const primal::HexMesh& mesh, const stc::HexStc& stc,
                         const primal::MeshData& data, const PageOptions& options) {
  const std::size_t m = mesh.complex.hexes.size();
  const auto n = static_cast<std::size_t>(mesh.points.rows());
  if (stc.vertices.size() != m)
    throw InvalidInput("viewer: the STC has " + std::to_string(stc.vertices.size()) +
                       " vertices for " + std::to_string(m) + " hexes; build it from this mesh");
  for (const auto& h : mesh.complex.hexes) {
    for (const NodeId v : h) {
      if (!v.is_valid() || v.index() >= n)
        throw InvalidInput("viewer: a hex uses node " + v.str() + " but the mesh has " +
                           std::to_string(n) + " points");
    }
  }
  nlohmann::json j;
  j["title"] = options.title;
  j["hexes"] = m;
  j["nodes"] = n;
  j["sheets"] = stc.sheets.size();
  j["chords"] = stc.chords.size();
  j["blind_sheets"] = stc::num_blind_sheets(stc);
  j["blind_chords"] = stc::num_blind_chords(stc);
  {
    Bytes b;
    for (std::size_t i = 0; i < n; ++i)
      for (Eigen::Index c = 0; c < 3; ++c)
        b.f32(static_cast<float>(mesh.points(static_cast<Eigen::Index>(i), c)));
    j["points"] = b.base64();
  }
  {
    std::vector<std::int32_t> v;
    v.reserve(8 * m);
    for (const auto& h : mesh.complex.hexes)
      for (const NodeId x : h) v.push_back(x.value());
    j["hex_nodes"] = ints_json(v);
  }
  const auto neighbours = primal::hex_face_neighbours(mesh.complex);
  {
    std::vector<std::int32_t> v;
    v.reserve(6 * m);
    for (const auto& f : neighbours) v.insert(v.end(), f.begin(), f.end());
    j["neighbours"] = ints_json(v);
  }
  {
    const primal::DataArray* sj = cell_array(data, "scaled_jacobian", m);
    Bytes b;
    for (std::size_t h = 0; h < m; ++h) {
      const double v = sj != nullptr
                           ? sj->values[h]
                           : primal::hex_scaled_jacobian(mesh.points, mesh.complex.hexes[h]);
      b.f32(static_cast<float>(v));
    }
    j["scaled_jacobian"] = b.base64();
  }
  {
    std::vector<std::int32_t> sheets;
    std::vector<std::int32_t> chords;
    for (const auto& v : stc.vertices) {
      for (const SheetId s : v.sheets) sheets.push_back(s.value());
      for (const ChordId c : v.chords) chords.push_back(c.value());
    }
    j["sheet_ids"] = ints_json(sheets);
    j["chord_ids"] = ints_json(chords);
  }
  {
    const primal::DataArray* layer = cell_array(data, "layer", m);
    const std::vector<std::int32_t> computed =
        layer != nullptr ? std::vector<std::int32_t>{} : primal::hex_layers(neighbours);
    std::vector<std::int32_t> v(m);
    for (std::size_t h = 0; h < m; ++h)
      v[h] = layer != nullptr ? static_cast<std::int32_t>(layer->values[h]) : computed[h];
    j["layer"] = ints_json(v);
  }
  // The replay order: by creation step when known, else the mesh's hex order.
  const primal::DataArray* step = cell_array(data, "creation_step", m);
  std::vector<std::int32_t> order(m);
  std::iota(order.begin(), order.end(), 0);
  if (step != nullptr) {
    std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
      return step->values[static_cast<std::size_t>(a)] < step->values[static_cast<std::size_t>(b)];
    });
  }
  j["history"] = step != nullptr;
  j["order"] = ints_json(order);
  const auto int_array = [&](std::string_view name, std::string_view key) {
    const primal::DataArray* a = cell_array(data, name, m);
    if (a == nullptr) return;
    std::vector<std::int32_t> v(m);
    for (std::size_t h = 0; h < m; ++h) v[h] = static_cast<std::int32_t>(a->values[h]);
    j[std::string(key)] = ints_json(v);
  };
  int_array("shrink", "shrink");
  int_array("depth", "depth");
  if (const primal::DataArray* rule = cell_array(data, "rule", m)) {
    std::vector<std::int32_t> v(m);
    for (std::size_t h = 0; h < m; ++h) v[h] = static_cast<std::int32_t>(rule->values[h]);
    j["rule"] = ints_json(v);
    nlohmann::json names = nlohmann::json::object();
    for (const int code : {primal::kRuleCross, primal::kRuleCrossRelaxed, primal::kRuleBlindChord,
                           primal::kRuleParallelMerge, primal::kRulePillow, primal::kRuleTetSplit,
                           primal::kRuleOther})
      names[std::to_string(code)] = primal::rule_name(code);
    j["rule_names"] = names;
  }
  if (options.hex_nodes.size() == m) {
    std::vector<std::int32_t> v;
    v.reserve(m);
    for (const NodeId x : options.hex_nodes) v.push_back(x.is_valid() ? x.value() : -1);
    j["rule_node"] = ints_json(v);
  }
  nlohmann::json shrinks = nlohmann::json::array();
  for (const primal::ShrinkRecord& r : options.shrinks) {
    shrinks.push_back({{"shrink", r.shrink},
                       {"loop", r.loop},
                       {"side", r.side == 0 ? "A" : "B"},
                       {"length", r.length},
                       {"depth", r.depth},
                       {"decided_by", r.decided_by},
                       {"failed", r.failed}});
  }
  j["shrinks"] = shrinks;
  return j;
}

}  // namespace

bool has_three_js() {
  return detail::has_three();
}

std::string base64(const std::vector<std::uint8_t>& bytes) {
  static constexpr std::string_view kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (std::uint32_t{bytes[i + 1]} << 8) |
                            std::uint32_t{bytes[i + 2]};
    out.push_back(kAlphabet[(v >> 18) & 63U]);
    out.push_back(kAlphabet[(v >> 12) & 63U]);
    out.push_back(kAlphabet[(v >> 6) & 63U]);
    out.push_back(kAlphabet[v & 63U]);
  }
  if (i + 1 == bytes.size()) {
    const std::uint32_t v = std::uint32_t{bytes[i]} << 16;
    out.push_back(kAlphabet[(v >> 18) & 63U]);
    out.push_back(kAlphabet[(v >> 12) & 63U]);
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (std::uint32_t{bytes[i + 1]} << 8);
    out.push_back(kAlphabet[(v >> 18) & 63U]);
    out.push_back(kAlphabet[(v >> 12) & 63U]);
    out.push_back(kAlphabet[(v >> 6) & 63U]);
    out.push_back('=');
  }
  return out;
}

std::string page_html(const primal::HexMesh& mesh, const stc::HexStc& stc,
                      const primal::MeshData& data, const PageOptions& options) {
  if (!detail::has_three()) {
    throw Unsupported(
        "stcweave was built without three.js, so it cannot make the browser page: install "
        "Debian's libjs-three (./dev.sh installs it) and rebuild");
  }
  const std::string json = script_safe(page_data(mesh, stc, data, options).dump());
  const std::string_view tpl = detail::page_html();
  std::string out;
  out.reserve(tpl.size() + json.size() + detail::three_js().size() + 200000);
  // Markers of the template, in the order they appear.
  const std::array<std::pair<std::string_view, std::string>, 6> parts = {{
      {"@TITLE@", html_escape(options.title)},
      {"/*@CSS@*/", std::string(detail::page_css())},
      {"@DATA@", json},
      {"/*@THREE@*/", std::string(detail::three_js())},
      {"/*@ORBIT@*/", std::string(detail::orbit_controls_js())},
      {"/*@PAGE@*/", std::string(detail::page_js())},
  }};
  std::size_t pos = 0;
  for (const auto& [marker, text] : parts) {
    const std::size_t at = tpl.find(marker, pos);
    if (at == std::string_view::npos)
      throw InternalError("viewer: the page template has no " + std::string(marker) +
                          " marker (after byte " + std::to_string(pos) + ")");
    out.append(tpl.substr(pos, at - pos));
    out.append(text);
    pos = at + marker.size();
  }
  out.append(tpl.substr(pos));
  return out;
}

void write_page(const std::filesystem::path& path, const primal::HexMesh& mesh,
                const stc::HexStc& stc, const primal::MeshData& data, const PageOptions& options) {
  const std::string text = page_html(mesh, stc, data, options);
  primal::write_text_file(path, text);
}

}  // namespace stcweave::viewer
