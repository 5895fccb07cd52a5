#include "stcweave/stc/hex_stc.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <tuple>

#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/graph_io.hpp"
#include "support/shapes.hpp"

namespace stcweave::stc {
namespace {

/// A ring of `n` hexes: a square tube whose cross-section i has nodes 4i..4i+3; hex i joins
/// section i (bottom) to section i+1 (top). With `twisted`, the last hex is glued back to
/// section 0 after a quarter turn, which makes its two transverse directions one
/// self-intersecting sheet.
HexComplex ring_hexes(int n, bool twisted) {
  HexComplex c;
  c.num_nodes = static_cast<std::size_t>(4 * n);
  const auto node = [](int section, int k) { return NodeId(4 * section + k); };
  for (int i = 0; i < n; ++i) {
    Hex h{};
    for (int k = 0; k < 4; ++k) h[static_cast<std::size_t>(k)] = node(i, k);
    for (int k = 0; k < 4; ++k) {
      const bool last = i + 1 == n;
      const int kk = last && twisted ? (k + 1) % 4 : k;
      h[static_cast<std::size_t>(k + 4)] = node((i + 1) % n, kk);
    }
    c.hexes.push_back(h);
  }
  return c;
}

std::set<SheetId> sheets_of(const StcVertex& v) {
  return {v.sheets.begin(), v.sheets.end()};
}

class BoxStcTest : public ::testing::TestWithParam<std::tuple<int, int, int>> {};

TEST_P(BoxStcTest, CountsAndStructureMatchTheStructuredBox) {
  const auto [a, b, c] = GetParam();
  const HexComplex complex = test::box_hexes(a, b, c).complex;
  const HexStc stc = build_hex_stc(complex);
  const std::size_t faces = static_cast<std::size_t>(a * b + b * c + c * a);
  EXPECT_EQ(stc.sheets.size(), static_cast<std::size_t>(a + b + c));
  EXPECT_EQ(stc.chords.size(), faces);
  EXPECT_EQ(stc.boundary_points.size(), 2 * faces);
  EXPECT_EQ(stc.boundary.quads.size(), 2 * faces);
  EXPECT_EQ(num_blind_chords(stc), 0U);
  EXPECT_EQ(num_blind_sheets(stc), 0U);
  EXPECT_EQ(num_self_intersecting_sheets(stc), 0U);
  ASSERT_EQ(stc.vertices.size(), complex.hexes.size());

  // Every hex: three distinct sheets and three distinct chords, consistent with them.
  std::size_t hex_sheet_incidences = 0;
  for (std::size_t h = 0; h < stc.vertices.size(); ++h) {
    const StcVertex& v = stc.vertices[h];
    EXPECT_EQ(sheets_of(v).size(), 3U) << HexId(h);
    EXPECT_EQ(std::set<ChordId>(v.chords.begin(), v.chords.end()).size(), 3U) << HexId(h);
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const Chord& chord = stc.chord(v.chords[axis]);
      std::array<SheetId, 2> expected{v.sheets[(axis + 1) % 3], v.sheets[(axis + 2) % 3]};
      std::sort(expected.begin(), expected.end());
      EXPECT_EQ(chord.sheets, expected) << HexId(h) << " axis " << axis;
    }
  }
  // Sheets: one boundary loop each; a sheet across direction d has the box's size
  // orthogonal to it in hexes. Their hexes count each hex three times in total.
  for (const Sheet& sheet : stc.sheets) {
    EXPECT_EQ(sheet.boundary_loops.size(), 1U);
    EXPECT_FALSE(sheet.self_intersecting);
    hex_sheet_incidences += sheet.hexes.size();
    EXPECT_TRUE(std::is_sorted(sheet.hexes.begin(), sheet.hexes.end()));
    const std::size_t n = sheet.hexes.size();
    EXPECT_TRUE(n == static_cast<std::size_t>(b * c) || n == static_cast<std::size_t>(a * c) ||
                n == static_cast<std::size_t>(a * b));
    // A loop of a box sheet crosses the perimeter of the layer's cross-section.
    EXPECT_EQ(sheet.boundary_loops[0].size() % 2, 0U);
  }
  EXPECT_EQ(hex_sheet_incidences, 3 * complex.hexes.size());
  // Chords: open, two distinct ends whose boundary points name the chord back.
  std::size_t chord_hexes = 0;
  for (std::size_t c_id = 0; c_id < stc.chords.size(); ++c_id) {
    const Chord& chord = stc.chords[c_id];
    EXPECT_FALSE(chord.closed);
    ASSERT_TRUE(chord.ends[0].is_valid() && chord.ends[1].is_valid());
    EXPECT_NE(chord.ends[0], chord.ends[1]);
    for (QuadId end : chord.ends) EXPECT_EQ(stc.boundary_point(end).chord, ChordId(c_id));
    EXPECT_EQ(stc.boundary_point(chord.ends[0]).hex, chord.hexes.front());
    EXPECT_EQ(stc.boundary_point(chord.ends[1]).hex, chord.hexes.back());
    chord_hexes += chord.hexes.size();
  }
  EXPECT_EQ(chord_hexes, 3 * complex.hexes.size());
  // Graphs.
  EXPECT_EQ(boost::num_vertices(stc.dual_graph), complex.hexes.size() + 2 * faces);
  EXPECT_EQ(boost::num_edges(stc.dual_graph),
            (6 * complex.hexes.size() + 2 * faces) / 2);  // every face once
  EXPECT_EQ(boost::num_vertices(stc.sheet_graph), stc.sheets.size());
  EXPECT_EQ(boost::num_edges(stc.sheet_graph), stc.chords.size());
}

std::vector<std::tuple<int, int, int>> all_small_boxes() {
  std::vector<std::tuple<int, int, int>> boxes;
  for (int a = 1; a <= 4; ++a)
    for (int b = 1; b <= 4; ++b)
      for (int c = 1; c <= 4; ++c) boxes.emplace_back(a, b, c);
  return boxes;
}

INSTANTIATE_TEST_SUITE_P(AllBoxesUpTo4, BoxStcTest, ::testing::ValuesIn(all_small_boxes()),
                         [](const auto& info) {
                           return std::to_string(std::get<0>(info.param)) + "x" +
                                  std::to_string(std::get<1>(info.param)) + "x" +
                                  std::to_string(std::get<2>(info.param));
                         });

TEST(HexStc, ChordHexesAreOrderedFromEndToEnd) {
  const HexStc stc = build_hex_stc(test::box_hexes(3, 1, 1).complex);
  const Chord& chord = stc.chord(stc.vertex(HexId(0)).chords[0]);  // along x
  ASSERT_EQ(chord.hexes.size(), 3U);
  std::vector<HexId> hexes = chord.hexes;
  if (hexes.front() != HexId(0)) std::reverse(hexes.begin(), hexes.end());
  EXPECT_EQ(hexes, (std::vector<HexId>{HexId(0), HexId(1), HexId(2)}));
  EXPECT_EQ(stc.vertex(HexId(1)).chords[0], stc.vertex(HexId(0)).chords[0]);
  // The chords along y and z in a 3x1x1 bar have one hex each.
  EXPECT_EQ(stc.chord(stc.vertex(HexId(1)).chords[1]).hexes.size(), 1U);
  EXPECT_EQ(stc.chord(stc.vertex(HexId(1)).chords[2]).hexes.size(), 1U);
}

TEST(HexStc, RingHasOneBlindChordAndSheetsWithTwoLoops) {
  const HexStc stc = build_hex_stc(ring_hexes(4, false));
  // the ring chord, plus one chord per hex in each transverse direction
  EXPECT_EQ(stc.chords.size(), 9U);
  EXPECT_EQ(num_blind_chords(stc), 1U);
  const Chord& ring = stc.chord(stc.vertex(HexId(0)).chords[2]);
  EXPECT_TRUE(ring.closed);
  EXPECT_FALSE(ring.ends[0].is_valid());
  EXPECT_EQ(ring.hexes, (std::vector<HexId>{HexId(0), HexId(1), HexId(2), HexId(3)}));
  EXPECT_NE(ring.sheets[0], ring.sheets[1]);
  // two sheets go around the ring (two loops each), one crosses each hex (one loop)
  EXPECT_EQ(stc.sheets.size(), 6U);
  std::multiset<std::size_t> loops;
  for (const Sheet& s : stc.sheets) loops.insert(s.boundary_loops.size());
  EXPECT_EQ(loops, (std::multiset<std::size_t>{1, 1, 1, 1, 2, 2}));
  EXPECT_EQ(num_self_intersecting_sheets(stc), 0U);
  EXPECT_EQ(stc.boundary_points.size(), 16U);
}

TEST(HexStc, TwistedRingHasASelfIntersectingSheetAndASelfLoop) {
  const HexStc stc = build_hex_stc(ring_hexes(4, true));
  EXPECT_EQ(num_self_intersecting_sheets(stc), 1U);
  EXPECT_EQ(stc.sheets.size(), 5U);
  const StcVertex& v = stc.vertex(HexId(2));
  EXPECT_EQ(v.sheets[0], v.sheets[1]);
  EXPECT_NE(v.sheets[0], v.sheets[2]);
  EXPECT_TRUE(stc.sheet(v.sheets[0]).self_intersecting);
  const Chord& ring = stc.chord(v.chords[2]);
  EXPECT_TRUE(is_blind(ring));
  EXPECT_EQ(ring.sheets[0], ring.sheets[1]);
  // the ring chord is a self-loop of the sheet graph
  std::size_t self_loops = 0;
  for (const auto e : boost::make_iterator_range(boost::edges(stc.sheet_graph)))
    if (boost::source(e, stc.sheet_graph) == boost::target(e, stc.sheet_graph)) ++self_loops;
  EXPECT_EQ(self_loops, 1U);
}

TEST(HexStc, SheetGraphJoinsTheTwoSheetsOfEachChord) {
  const HexStc stc = build_hex_stc(test::box_hexes(2, 3, 1).complex);
  for (const auto e : boost::make_iterator_range(boost::edges(stc.sheet_graph))) {
    const Chord& chord = stc.chord(stc.sheet_graph[e].chord);
    std::array<std::size_t, 2> ends{boost::source(e, stc.sheet_graph),
                                    boost::target(e, stc.sheet_graph)};
    std::sort(ends.begin(), ends.end());
    EXPECT_EQ(ends[0], chord.sheets[0].index());
    EXPECT_EQ(ends[1], chord.sheets[1].index());
  }
  // dual graph: a hex has degree 6; a boundary point degree 1 and is joined to its hex
  for (std::size_t h = 0; h < stc.num_hexes(); ++h)
    EXPECT_EQ(boost::degree(dual_vertex_of_hex(HexId(h)), stc.dual_graph), 6U);
  for (std::size_t q = 0; q < stc.boundary_points.size(); ++q) {
    const std::size_t v = dual_vertex_of_boundary_point(stc, QuadId(q));
    ASSERT_EQ(boost::degree(v, stc.dual_graph), 1U);
    EXPECT_EQ(stc.dual_graph[v].kind, DualVertexKind::BoundaryPoint);
    const auto e = *boost::out_edges(v, stc.dual_graph).first;
    EXPECT_EQ(boost::target(e, stc.dual_graph), stc.boundary_point(QuadId(q)).hex.index());
    EXPECT_EQ(stc.dual_graph[e].chord, stc.boundary_point(QuadId(q)).chord);
  }
}

TEST(HexStc, BoundaryMatchesBoundarySurface) {
  const HexComplex complex = test::box_hexes(2, 2, 3).complex;
  const HexStc stc = build_hex_stc(complex);
  EXPECT_EQ(stc.boundary.quads, boundary_surface(complex).quads);
}

TEST(HexStc, IsDeterministic) {
  const HexComplex complex = test::box_hexes(3, 2, 4).complex;
  std::ostringstream first;
  std::ostringstream second;
  write_graphs(first, build_hex_stc(complex), {StcGraph::Dual, StcGraph::Sheet},
               GraphFormat::GraphMl);
  write_graphs(second, build_hex_stc(complex), {StcGraph::Dual, StcGraph::Sheet},
               GraphFormat::GraphMl);
  EXPECT_EQ(first.str(), second.str());
}

TEST(HexStc, RefusesBadNodes) {
  HexComplex complex = test::box_hexes(1, 1, 1).complex;
  complex.hexes[0][7] = NodeId(99);
  EXPECT_THROW((void)build_hex_stc(complex), InvalidInput);
  complex.hexes[0][7] = complex.hexes[0][6];
  try {
    (void)build_hex_stc(complex);
    FAIL() << "a repeated node must be refused";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("h0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("twice"), std::string::npos) << e.what();
  }
}

TEST(HexStc, RefusesNonManifoldComplexes) {
  // three hexes on one face
  HexComplex three;
  three.num_nodes = 16;
  three.hexes.push_back(
      {NodeId(0), NodeId(1), NodeId(2), NodeId(3), NodeId(4), NodeId(5), NodeId(6), NodeId(7)});
  three.hexes.push_back(
      {NodeId(4), NodeId(5), NodeId(6), NodeId(7), NodeId(8), NodeId(9), NodeId(10), NodeId(11)});
  three.hexes.push_back(
      {NodeId(4), NodeId(5), NodeId(6), NodeId(7), NodeId(12), NodeId(13), NodeId(14), NodeId(15)});
  try {
    (void)build_hex_stc(three);
    FAIL() << "a face in three hexes must be refused";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("non-manifold"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("undefined"), std::string::npos) << e.what();
  }
  // two cubes touching along an edge only
  HexComplex edge;
  edge.num_nodes = 14;
  edge.hexes.push_back(
      {NodeId(0), NodeId(1), NodeId(2), NodeId(3), NodeId(4), NodeId(5), NodeId(6), NodeId(7)});
  edge.hexes.push_back(
      {NodeId(2), NodeId(8), NodeId(9), NodeId(10), NodeId(6), NodeId(11), NodeId(12), NodeId(13)});
  EXPECT_THROW((void)build_hex_stc(edge), InvalidInput);
}

TEST(HexStc, RefusesTwoHexesSharingTwoFaces) {
  // the same hex twice: every face in both, so no chord through them has an order
  HexComplex twice = test::box_hexes(1, 1, 1).complex;
  twice.hexes.push_back(twice.hexes[0]);
  try {
    (void)build_hex_stc(twice);
    FAIL() << "two hexes sharing two faces must be refused";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("undefined"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("h0+h1 share two faces"), std::string::npos) << e.what();
  }
  // a valid two-hex bar is accepted
  EXPECT_NO_THROW((void)build_hex_stc(test::box_hexes(2, 1, 1).complex));
}

TEST(HexStc, EmptyComplexHasAnEmptyStc) {
  const HexStc stc = build_hex_stc(HexComplex{});
  EXPECT_TRUE(stc.sheets.empty());
  EXPECT_TRUE(stc.chords.empty());
  EXPECT_EQ(boost::num_vertices(stc.dual_graph), 0U);
}

// --- graph export (graph_io.hpp) ---

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(GraphIo, GraphMlHasOneNodePerVertexAndOneEdgePerEdge) {
  const HexStc stc = build_hex_stc(test::box_hexes(2, 1, 1).complex);
  std::ostringstream sheets;
  write_graph(sheets, stc, StcGraph::Sheet, GraphFormat::GraphMl);
  EXPECT_EQ(count(sheets.str(), "<node id="), 4U);
  EXPECT_EQ(count(sheets.str(), "<edge id="), 5U);
  EXPECT_NE(sheets.str().find("<node id=\"s0\">"), std::string::npos);
  EXPECT_NE(sheets.str().find("<edge id=\"c4\""), std::string::npos);
  EXPECT_EQ(count(sheets.str(), "<graph "), 1U);
  EXPECT_NE(sheets.str().find("</graphml>"), std::string::npos);

  std::ostringstream dual;
  write_graph(dual, stc, StcGraph::Dual, GraphFormat::GraphMl);
  EXPECT_EQ(count(dual.str(), "<node id="), 2U + 10U);
  EXPECT_EQ(count(dual.str(), "<edge id="), 11U);
  EXPECT_NE(dual.str().find("source=\"h0\" target=\"h1\""), std::string::npos) << dual.str();
}

TEST(GraphIo, DotNamesVerticesWithIds) {
  const HexStc stc = build_hex_stc(ring_hexes(4, true));
  std::ostringstream sheets;
  write_graph(sheets, stc, StcGraph::Sheet, GraphFormat::Dot);
  const std::string text = sheets.str();
  EXPECT_EQ(text.rfind("graph G {", 0), 0U) << text;
  EXPECT_EQ(count(text, "--"), stc.chords.size());
  EXPECT_NE(text.find("self_intersecting=true"), std::string::npos);
  EXPECT_NE(text.find("style=dashed"), std::string::npos);  // the blind ring chord
  std::ostringstream dual;
  write_graph(dual, stc, StcGraph::Dual, GraphFormat::Dot);
  EXPECT_NE(dual.str().find("h0--h1"), std::string::npos) << dual.str();
  EXPECT_NE(dual.str().find("q0"), std::string::npos);
}

TEST(GraphIo, WritesFilesAtomically) {
  const HexStc stc = build_hex_stc(test::box_hexes(1, 2, 1).complex);
  const auto folder = std::filesystem::temp_directory_path() / "stcweave_graph_io_test";
  std::filesystem::create_directories(folder);
  const auto path = folder / "graphs.graphml";
  write_graph_file(path, stc, {StcGraph::Dual, StcGraph::Sheet}, GraphFormat::GraphMl);
  std::ifstream in(path);
  std::stringstream read;
  read << in.rdbuf();
  std::ostringstream expected;
  write_graphs(expected, stc, {StcGraph::Dual, StcGraph::Sheet}, GraphFormat::GraphMl);
  EXPECT_EQ(read.str(), expected.str());
  EXPECT_EQ(count(read.str(), "<graph "), 2U);
  EXPECT_FALSE(std::filesystem::exists(folder / "graphs.graphml.tmp"));
  EXPECT_THROW(
      write_graph_file(folder / "missing" / "g.dot", stc, {StcGraph::Sheet}, GraphFormat::Dot),
      IoError);
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace stcweave::stc
