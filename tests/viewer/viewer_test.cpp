// The browser page (viewer/page.hpp) without a browser: the page is self-contained and its
// embedded data, decoded here by a decoder of our own, matches the mesh it was made from
// (hex count, nodes, sheets, chords, the hexes' nodes, the replay order).
#include "stcweave/viewer/page.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>
#include <set>

#include "stcweave/primal/pipeline.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::viewer {
namespace {

std::vector<std::uint8_t> unbase64(const std::string& s) {
  std::vector<std::uint8_t> out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (const char c : s) {
    int v = -1;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    if (c >= '0' && c <= '9') v = c - '0' + 52;
    if (c == '+') v = 62;
    if (c == '/') v = 63;
    if (v < 0) continue;  // padding
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::uint8_t>((acc >> bits) & 0xffU));
    }
  }
  return out;
}

/// Integers as the page stores them: {offset, bytes (1, 2, 4), data: base64 little-endian}.
std::vector<std::int32_t> int32s(const nlohmann::json& j) {
  const std::vector<std::uint8_t> b = unbase64(j.at("data").get<std::string>());
  const std::size_t width = j.at("bytes").get<std::size_t>();
  const std::int64_t offset = j.at("offset").get<std::int64_t>();
  std::vector<std::int32_t> out(b.size() / width);
  for (std::size_t i = 0; i < out.size(); ++i) {
    std::uint64_t u = 0;
    for (std::size_t k = 0; k < width; ++k) u |= std::uint64_t{b[width * i + k]} << (8 * k);
    out[i] = static_cast<std::int32_t>(static_cast<std::int64_t>(u) + offset);
  }
  return out;
}

/// The page's data object.
nlohmann::json embedded(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"stcweave-data\">";
  const std::size_t a = html.find(open);
  const std::size_t b = html.find("</script>", a);
  if (a == std::string::npos || b == std::string::npos) return {};
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

TEST(Base64, KnownVectors) {
  EXPECT_EQ(base64({}), "");
  EXPECT_EQ(base64({'f'}), "Zg==");
  EXPECT_EQ(base64({'f', 'o'}), "Zm8=");
  EXPECT_EQ(base64({'f', 'o', 'o'}), "Zm9v");
  EXPECT_EQ(base64({'f', 'o', 'o', 'b', 'a', 'r'}), "Zm9vYmFy");
  EXPECT_EQ(base64({0xff, 0xfe, 0x00}), "//4A");
}

TEST(Page, DataMatchesTheWovenMesh) {
  if (!has_three_js()) GTEST_SKIP() << "built without three.js (libjs-three)";
  primal::MeshOptions options;
  const primal::MeshResult r =
      primal::mesh_file(test::file_of(test::box_surface(4, 3, 5), "box"), options);
  const stc::HexStc stc = stc::build_hex_stc(r.mesh.complex);
  const primal::WeaveHistory history = primal::weave_history(r.woven);
  const primal::MeshData data = primal::hex_mesh_data(r.mesh, stc, &history);
  PageOptions page;
  page.title = "box </script><b>";
  page.shrinks = history.shrinks;
  page.hex_nodes = history.hex_node;
  const std::string html = page_html(r.mesh, stc, data, page);
  // Self-contained: no external script, stylesheet or image.
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("<img"), std::string::npos);
  EXPECT_NE(html.find("REVISION=\"111\""), std::string::npos);  // three.js is inlined
  EXPECT_EQ(html.find("@DATA@"), std::string::npos);
  const nlohmann::json d = embedded(html);
  ASSERT_TRUE(d.is_object());
  EXPECT_EQ(d["title"], page.title);  // the script element was not closed by the title
  const std::size_t m = r.mesh.complex.hexes.size();
  ASSERT_EQ(m, 60U);
  EXPECT_EQ(d["hexes"], m);
  EXPECT_EQ(d["nodes"], static_cast<std::size_t>(r.mesh.points.rows()));
  EXPECT_EQ(d["sheets"], stc.sheets.size());
  EXPECT_EQ(d["sheets"], 12U);
  EXPECT_EQ(d["chords"], stc.chords.size());
  const auto hexes = int32s(d["hex_nodes"]);
  ASSERT_EQ(hexes.size(), 8 * m);
  for (std::size_t h = 0; h < m; ++h)
    for (std::size_t k = 0; k < 8; ++k)
      EXPECT_EQ(hexes[8 * h + k], r.mesh.complex.hexes[h][k].value());
  const auto sheets = int32s(d["sheet_ids"]);
  ASSERT_EQ(sheets.size(), 3 * m);
  EXPECT_EQ(std::set<std::int32_t>(sheets.begin(), sheets.end()).size(), stc.sheets.size());
  const auto order = int32s(d["order"]);
  ASSERT_EQ(order.size(), m);
  for (std::size_t k = 0; k < m; ++k) EXPECT_EQ(order[k], static_cast<std::int32_t>(k));
  EXPECT_TRUE(d["history"].get<bool>());
  EXPECT_EQ(int32s(d["shrink"]), r.woven.hex_shrink);
  EXPECT_EQ(d["shrinks"].size(), history.shrinks.size());
  const auto neighbours = int32s(d["neighbours"]);
  ASSERT_EQ(neighbours.size(), 6 * m);
  EXPECT_EQ(*std::min_element(neighbours.begin(), neighbours.end()), -1);  // the boundary
  EXPECT_EQ(d["neighbours"]["bytes"], 1);  // 61 values (-1..59): one byte each
  EXPECT_EQ(d["order"]["offset"], 0);
  // Determinism: the same page twice.
  EXPECT_EQ(page_html(r.mesh, stc, data, page), html);
}

TEST(Page, WithoutWeaveDataTheReplayFollowsTheFile) {
  if (!has_three_js()) GTEST_SKIP() << "built without three.js (libjs-three)";
  const primal::HexMesh mesh = test::box_hexes(2, 2, 3);
  const stc::HexStc stc = stc::build_hex_stc(mesh.complex);
  const nlohmann::json d = embedded(page_html(mesh, stc, primal::MeshData{}));
  EXPECT_FALSE(d["history"].get<bool>());
  EXPECT_FALSE(d.contains("shrink"));
  EXPECT_EQ(int32s(d["order"]).size(), 12U);
  EXPECT_EQ(int32s(d["layer"]).size(), 12U);
}

TEST(Page, RefusesDataOfAnotherMesh) {
  if (!has_three_js()) GTEST_SKIP() << "built without three.js (libjs-three)";
  const primal::HexMesh mesh = test::box_hexes(2, 2, 3);
  const stc::HexStc stc = stc::build_hex_stc(mesh.complex);
  const primal::HexMesh other = test::box_hexes(2, 2, 2);
  const primal::MeshData data = primal::hex_mesh_data(other, stc::build_hex_stc(other.complex));
  EXPECT_THROW((void)page_html(mesh, stc, data), InvalidInput);
}

}  // namespace
}  // namespace stcweave::viewer
