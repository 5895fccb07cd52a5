#include "stcweave/stc/validate.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <tuple>

#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/hex_complex.hpp"
#include "support/pinched_star.hpp"
#include "support/shapes.hpp"

namespace stcweave::stc {
namespace {

Hex hex_of(std::initializer_list<int> nodes) {
  Hex h{};
  std::size_t i = 0;
  for (int v : nodes) h[i++] = NodeId(v);
  return h;
}

/// The boundary of a box as `test::boundary_of` finds it (an extraction independent of
/// the library), mapped back to the hex mesh's node ids.
QuadSurface independent_boundary(const primal::HexMesh& mesh) {
  const primal::SurfaceMesh compact = test::boundary_of(mesh);
  // boundary_of numbers the boundary nodes in increasing order of their hex-mesh ids.
  std::set<NodeId> used;
  for (const Hex& h : mesh.complex.hexes)
    for (NodeId v : h) used.insert(v);
  std::set<NodeId> on_boundary;
  for (const Quad& q : boundary_surface(mesh.complex).quads) on_boundary.insert(q.begin(), q.end());
  const std::vector<NodeId> original(on_boundary.begin(), on_boundary.end());
  QuadSurface out;
  out.num_nodes = mesh.complex.num_nodes;
  for (Quad q : compact.surface.quads) {
    for (NodeId& v : q) v = original.at(v.index());
    out.quads.push_back(q);
  }
  return out;
}

std::set<Invariant> violated(const ValidationReport& report) {
  std::set<Invariant> out;
  for (const Violation& v : report.violations) out.insert(v.invariant);
  return out;
}

class BoxValidateTest : public ::testing::TestWithParam<std::tuple<int, int, int>> {};

TEST_P(BoxValidateTest, BoxIsValidWithItsBoundary) {
  const auto [a, b, c] = GetParam();
  const primal::HexMesh mesh = test::box_hexes(a, b, c);
  const QuadSurface expected = independent_boundary(mesh);
  const ValidationReport report = validate_hex_complex(mesh.complex, &expected);
  EXPECT_TRUE(report.valid) << report.summary();
  EXPECT_TRUE(report.violations.empty());
  EXPECT_TRUE(report.boundary_compared);
  EXPECT_EQ(report.hexes, static_cast<std::size_t>(a * b * c));
  EXPECT_EQ(report.boundary_faces, static_cast<std::size_t>(2 * (a * b + b * c + c * a)));
  EXPECT_EQ(report.euler_volume, 1);
  EXPECT_EQ(report.euler_boundary, 2);
  EXPECT_NO_THROW(require_valid(report));
  EXPECT_EQ(report.summary().rfind("valid hex complex", 0), 0U) << report.summary();
}

INSTANTIATE_TEST_SUITE_P(SomeBoxes, BoxValidateTest,
                         ::testing::Values(std::make_tuple(1, 1, 1), std::make_tuple(2, 1, 1),
                                           std::make_tuple(2, 3, 4), std::make_tuple(4, 4, 4),
                                           std::make_tuple(1, 5, 2)));

TEST(Validate, HexesSharingTwoFaces) {
  HexComplex c;
  c.num_nodes = 10;
  c.hexes.push_back(hex_of({0, 1, 2, 3, 4, 5, 6, 7}));
  // shares faces (1 2 6 5) and (2 3 7 6) of the first hex, both around edge n2-n6
  c.hexes.push_back(hex_of({3, 2, 1, 8, 7, 6, 5, 9}));
  const ValidationReport report = validate_hex_complex(c);
  EXPECT_FALSE(report.valid);
  const Violation* v = report.find(Invariant::HexesShareTwoFaces);
  ASSERT_NE(v, nullptr) << report.summary();
  EXPECT_EQ(v->count, 1U);
  EXPECT_EQ(v->examples, std::vector<std::string>{"h0+h1"});
  EXPECT_EQ(v->name(), "hexes_share_two_faces");
  EXPECT_NE(report.summary().find("hexes_share_two_faces: 1 (h0+h1)"), std::string::npos)
      << report.summary();
}

TEST(Validate, FaceInThreeHexes) {
  HexComplex c;
  c.num_nodes = 16;
  c.hexes.push_back(hex_of({0, 1, 2, 3, 4, 5, 6, 7}));
  c.hexes.push_back(hex_of({4, 5, 6, 7, 8, 9, 10, 11}));
  c.hexes.push_back(hex_of({4, 5, 6, 7, 12, 13, 14, 15}));
  const ValidationReport report = validate_hex_complex(c);
  const Violation* v = report.find(Invariant::FaceInThreeHexes);
  ASSERT_NE(v, nullptr) << report.summary();
  EXPECT_EQ(v->count, 1U);
  EXPECT_EQ(v->examples, std::vector<std::string>{"h0+h1+h2"});
  EXPECT_THROW(require_valid(report), InternalError);
}

TEST(Validate, HexWithARepeatedNodeOrANodeOutOfRange) {
  HexComplex c = test::box_hexes(2, 1, 1).complex;
  c.hexes[1][7] = c.hexes[1][6];
  ValidationReport report = validate_hex_complex(c);
  const Violation* v = report.find(Invariant::RepeatedNode);
  ASSERT_NE(v, nullptr) << report.summary();
  EXPECT_EQ(v->examples, std::vector<std::string>{"h1"});
  EXPECT_EQ(report.find(Invariant::NodeOutOfRange), nullptr);

  c = test::box_hexes(2, 1, 1).complex;
  c.hexes[0][2] = NodeId(1000);
  report = validate_hex_complex(c);
  v = report.find(Invariant::NodeOutOfRange);
  ASSERT_NE(v, nullptr) << report.summary();
  EXPECT_EQ(v->examples, std::vector<std::string>{"h0"});
  try {
    require_valid(report);
    FAIL() << "require_valid must throw";
  } catch (const InternalError& e) {
    EXPECT_NE(std::string(e.what()).find("node_out_of_range"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("h0"), std::string::npos) << e.what();
  }
}

TEST(Validate, RemovedHexMakesTheBoundaryDiffer) {
  const primal::HexMesh mesh = test::box_hexes(2, 2, 2);
  const QuadSurface expected = independent_boundary(mesh);
  HexComplex c = mesh.complex;
  c.hexes.erase(c.hexes.begin());  // a corner hex
  const ValidationReport report = validate_hex_complex(c, &expected);
  EXPECT_EQ(violated(report),
            (std::set<Invariant>{Invariant::MissingBoundaryQuad, Invariant::ExtraBoundaryQuad}))
      << report.summary();
  EXPECT_EQ(report.find(Invariant::MissingBoundaryQuad)->count, 3U);
  EXPECT_EQ(report.find(Invariant::ExtraBoundaryQuad)->count, 3U);
  // the corner-less box is itself a valid complex
  EXPECT_TRUE(validate_hex_complex(c).valid) << validate_hex_complex(c).summary();
}

TEST(Validate, ReversedExpectedBoundary) {
  const primal::HexMesh mesh = test::box_hexes(2, 1, 3);
  QuadSurface expected = independent_boundary(mesh);
  for (Quad& q : expected.quads) q = reversed(q);
  const ValidationReport report = validate_hex_complex(mesh.complex, &expected);
  EXPECT_EQ(violated(report), std::set<Invariant>{Invariant::ReversedBoundaryQuad})
      << report.summary();
  EXPECT_EQ(report.find(Invariant::ReversedBoundaryQuad)->count, expected.quads.size());
  EXPECT_EQ(report.find(Invariant::ReversedBoundaryQuad)->examples.size(), Violation::kMaxExamples);
  // a rotation of a quad is the same quad
  expected = independent_boundary(mesh);
  std::rotate(expected.quads[0].begin(), expected.quads[0].begin() + 1, expected.quads[0].end());
  EXPECT_TRUE(validate_hex_complex(mesh.complex, &expected).valid);
}

TEST(Validate, TwoBoxesTouchingAlongAnEdgeBreakTheFan) {
  HexComplex c;
  c.num_nodes = 14;
  c.hexes.push_back(hex_of({0, 1, 2, 3, 4, 5, 6, 7}));
  c.hexes.push_back(hex_of({2, 8, 9, 10, 6, 11, 12, 13}));  // shares edge n2-n6 only
  const ValidationReport report = validate_hex_complex(c);
  const Violation* fan = report.find(Invariant::BoundaryEdgeFan);
  ASSERT_NE(fan, nullptr) << report.summary();
  EXPECT_EQ(fan->examples, std::vector<std::string>{"n2-n6"});
  const Violation* link = report.find(Invariant::VertexLink);
  ASSERT_NE(link, nullptr) << report.summary();
  EXPECT_EQ(link->examples, (std::vector<std::string>{"n2", "n6"}));
  EXPECT_NE(report.find(Invariant::EulerCharacteristic), nullptr);
  EXPECT_EQ(report.find(Invariant::InteriorEdgeCycle), nullptr);
}

TEST(Validate, TwoBoxesTouchingAtANodeBreakTheVertexLink) {
  HexComplex c;
  c.num_nodes = 15;
  c.hexes.push_back(hex_of({0, 1, 2, 3, 4, 5, 6, 7}));
  c.hexes.push_back(hex_of({6, 8, 9, 10, 11, 12, 13, 14}));  // shares node n6 only
  const ValidationReport report = validate_hex_complex(c);
  EXPECT_EQ(report.find(Invariant::BoundaryEdgeFan), nullptr) << report.summary();
  const Violation* link = report.find(Invariant::VertexLink);
  ASSERT_NE(link, nullptr) << report.summary();
  EXPECT_EQ(link->examples, std::vector<std::string>{"n6"});
}

TEST(Validate, TwoBoxesAroundOneInteriorEdgeBreakTheCycle) {
  // two 2x2x1 boxes sharing only their central vertical edge n4-n13: the hexes around it
  // form two closed cycles, not one
  const HexComplex box = test::box_hexes(2, 2, 1).complex;
  HexComplex c = box;
  c.num_nodes = 2 * box.num_nodes;
  for (Hex h : box.hexes) {
    for (NodeId& v : h)
      if (v != NodeId(4) && v != NodeId(13)) v = NodeId(v.value() + 18);
    c.hexes.push_back(h);
  }
  const ValidationReport report = validate_hex_complex(c);
  const Violation* v = report.find(Invariant::InteriorEdgeCycle);
  ASSERT_NE(v, nullptr) << report.summary();
  EXPECT_EQ(v->examples, std::vector<std::string>{"n4-n13"});
  EXPECT_EQ(report.find(Invariant::BoundaryEdgeFan), nullptr) << report.summary();
}

TEST(Validate, InvertedHexBreaksFaceOrientation) {
  HexComplex c = test::box_hexes(3, 1, 1).complex;
  Hex& h = c.hexes[1];
  h = Hex{h[4], h[5], h[6], h[7], h[0], h[1], h[2], h[3]};
  const ValidationReport report = validate_hex_complex(c);
  const Violation* v = report.find(Invariant::FaceOrientation);
  ASSERT_NE(v, nullptr) << report.summary();
  EXPECT_EQ(v->count, 2U);
}

TEST(Validate, SolidTorusIsValid) {
  // a ring of four hexes around a hole: χ(volume) = 0 = χ(torus) / 2
  HexComplex c;
  c.num_nodes = 16;
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    c.hexes.push_back(
        hex_of({4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3, 4 * j, 4 * j + 1, 4 * j + 2, 4 * j + 3}));
  }
  const ValidationReport report = validate_hex_complex(c);
  EXPECT_TRUE(report.valid) << report.summary();
  EXPECT_EQ(report.euler_volume, 0);
  EXPECT_EQ(report.euler_boundary, 0);
}

TEST(Validate, TwistedRingIsValid) {
  // a ring of three hexes whose last gluing has a half turn: a twisted solid torus
  HexComplex c;
  c.num_nodes = 12;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const int r = i == 2 ? 2 : 0;
    c.hexes.push_back(hex_of({4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3, 4 * j + r % 4,
                              4 * j + (1 + r) % 4, 4 * j + (2 + r) % 4, 4 * j + (3 + r) % 4}));
  }
  const ValidationReport report = validate_hex_complex(c);
  EXPECT_TRUE(report.valid) << report.summary();
  EXPECT_EQ(report.euler_volume, 0);
}

TEST(Validate, PinchedNodeChangesTheEulerCharacteristic) {
  // identifying two boundary nodes far apart: the merged node's link has two components
  // and χ(boundary) becomes odd
  HexComplex pinched = test::box_hexes(3, 1, 1).complex;
  const NodeId far = pinched.hexes[2][6];
  for (NodeId& v : pinched.hexes[2])
    if (v == far) v = pinched.hexes[0][0];
  const ValidationReport report = validate_hex_complex(pinched);
  EXPECT_NE(report.find(Invariant::VertexLink), nullptr) << report.summary();
  const Violation* euler = report.find(Invariant::EulerCharacteristic);
  ASSERT_NE(euler, nullptr) << report.summary();
  EXPECT_EQ(euler->examples, std::vector<std::string>{"chi(volume)=0 chi(boundary)=1"});
}

TEST(Validate, LargeBoxIsValid) {
  const primal::HexMesh mesh = test::box_hexes(30, 30, 30);
  const ValidationReport report = validate_hex_complex(mesh.complex);
  EXPECT_TRUE(report.valid) << report.summary();
  EXPECT_EQ(report.hexes, 27000U);
}

}  // namespace
}  // namespace stcweave::stc

namespace stcweave::stc {
namespace {

TEST(UniqueEdges, OfABoxAreItsGridEdgesSortedOnce) {
  // An a x b x c box has a(b+1)(c+1) + (a+1)b(c+1) + (a+1)(b+1)c edges.
  const auto box = test::box_hexes(3, 2, 1);
  const auto edges = unique_edges(box.complex);
  EXPECT_EQ(edges.size(), 3u * 3 * 2 + 4u * 2 * 2 + 4u * 3 * 1);
  EXPECT_TRUE(std::is_sorted(edges.begin(), edges.end()));
  EXPECT_TRUE(std::adjacent_find(edges.begin(), edges.end()) == edges.end());
  for (const auto& [a, b] : edges) EXPECT_LT(a, b);
}

/// Every hex edge as a sorted pair, sorted and deduplicated: the definition, for comparison.
std::vector<std::pair<std::int32_t, std::int32_t>> sorted_hex_edges(const HexComplex& c) {
  std::vector<std::pair<std::int32_t, std::int32_t>> all;
  for (const Hex& h : c.hexes) {
    for (const auto& e : kHexEdges) {
      const std::int32_t a = h[static_cast<std::size_t>(e[0])].value();
      const std::int32_t b = h[static_cast<std::size_t>(e[1])].value();
      all.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  return all;
}

TEST(UniqueEdges, MatchASortOfEveryHexEdge) {
  // Node values shuffled so that the smaller end of an edge is any corner of the hex; and
  // the same complex with ids out of range (huge, negative), which the buckets cannot index.
  HexComplex box = test::box_hexes(4, 3, 2).complex;
  std::vector<std::int32_t> relabel(box.num_nodes);
  for (std::size_t v = 0; v < relabel.size(); ++v) relabel[v] = static_cast<std::int32_t>(v);
  std::mt19937 rng(7);
  std::shuffle(relabel.begin(), relabel.end(), rng);
  for (Hex& h : box.hexes)
    for (NodeId& v : h) v = NodeId(relabel[v.index()]);
  EXPECT_EQ(unique_edges(box), sorted_hex_edges(box));
  EXPECT_EQ(unique_edges(test::pinched_star().complex),
            sorted_hex_edges(test::pinched_star().complex));
  box.hexes[6][1] = NodeId(1 << 30);  // far beyond the entries: sorted without buckets
  EXPECT_EQ(unique_edges(box), sorted_hex_edges(box));
  box.hexes[5][3] = NodeId(-4);
  EXPECT_EQ(unique_edges(box), sorted_hex_edges(box));
  EXPECT_TRUE(unique_edges(HexComplex{}).empty());
}

TEST(Validate, PinchedFacePairIsReportedOnlyWhenAsked) {
  // Eight hexes around one node whose link has two edges between the same two vertices:
  // the faces n26-n0-x-n1 of two different hexes share the edges n26-n0 and n26-n1.
  const HexComplex star = test::pinched_star().complex;
  QuadSurface boundary = boundary_surface(star);
  boundary.num_nodes = 26;
  const ValidationReport plain = validate_hex_complex(star, &boundary);
  EXPECT_TRUE(plain.valid) << plain.summary();
  const ValidationReport strict = validate_hex_complex(star, &boundary, true);
  EXPECT_FALSE(strict.valid);
  EXPECT_EQ(violated(strict), std::set<Invariant>{Invariant::PinchedFacePair}) << strict.summary();
  const Violation* v = strict.find(Invariant::PinchedFacePair);
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(v->count, 1u);
  ASSERT_EQ(v->examples.size(), 1u);
  EXPECT_EQ(v->examples.front(), "n26-n0-n1");
  EXPECT_EQ(v->name(), "pinched_face_pair");
}

TEST(Validate, BoxesHaveNoPinchedFacePair) {
  for (const auto& [a, b, c] : {std::tuple{1, 1, 1}, std::tuple{3, 2, 2}, std::tuple{4, 4, 4}}) {
    const HexComplex box = test::box_hexes(a, b, c).complex;
    const ValidationReport r = validate_hex_complex(box, nullptr, true);
    EXPECT_TRUE(r.valid) << r.summary();
  }
}

}  // namespace
}  // namespace stcweave::stc
