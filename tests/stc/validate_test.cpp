#include "stcweave/stc/validate.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
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

// SharedNodesNotAFace: two hexes sharing four or more nodes share exactly a face of both,
// whatever the positions.
namespace stcweave::stc {
namespace {

/// The complex of the given hexes over nodes 0 .. the largest id used.
HexComplex complex_of(std::initializer_list<std::initializer_list<int>> hexes) {
  HexComplex c;
  for (const auto& h : hexes) {
    c.hexes.push_back(hex_of(h));
    for (const int v : h) c.num_nodes = std::max(c.num_nodes, static_cast<std::size_t>(v) + 1);
  }
  return c;
}

/// The examples of the `SharedNodesNotAFace` violation of `c` (empty when none).
std::vector<std::string> bad_intersections(const HexComplex& c, bool pinched = false) {
  const ValidationReport report = validate_hex_complex(c, nullptr, pinched, true);
  const Violation* v = report.find(Invariant::SharedNodesNotAFace);
  return v == nullptr ? std::vector<std::string>{} : v->examples;
}

/// The definition, pair by pair (quadratic): the pairs of hexes with 8 distinct nodes that
/// share four or more nodes other than exactly a face of both, as "h1+h2:n3,n4,n5,n6".
std::vector<std::string> shared_nodes_not_a_face_by_definition(const HexComplex& c) {
  const auto nodes = [&](std::size_t h) {
    return std::set<NodeId>(c.hexes[h].begin(), c.hexes[h].end());
  };
  const auto is_face = [&](std::size_t h, const std::set<NodeId>& s) {
    for (int f = 0; f < 6; ++f) {
      const Quad q = hex_face(c.hexes[h], f);
      if (std::set<NodeId>(q.begin(), q.end()) == s) return true;
    }
    return false;
  };
  std::vector<std::string> out;
  for (std::size_t h = 0; h < c.hexes.size(); ++h) {
    if (nodes(h).size() != 8) continue;
    for (std::size_t g = h + 1; g < c.hexes.size(); ++g) {
      if (nodes(g).size() != 8) continue;
      std::vector<NodeId> s;
      const std::set<NodeId> a = nodes(h);
      const std::set<NodeId> b = nodes(g);
      std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(s));
      bool ok = s.size() < 4;
      if (s.size() == 4) {
        const std::set<NodeId> f(s.begin(), s.end());
        ok = is_face(h, f) && is_face(g, f);
      }
      if (ok) continue;
      std::string example = HexId(h).str() + "+" + HexId(g).str() + ":";
      for (std::size_t i = 0; i < s.size(); ++i) {
        if (i > 0) example += ',';
        example += s[i].str();
      }
      out.push_back(example);
    }
  }
  return out;
}

TEST(ValidateIntersection, FaceAndOneMoreNodeIsRefused) {
  // glued on the top face (4 5 6 7) of the first hex, and its last node is node 0 as well
  const HexComplex c = complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {4, 5, 6, 7, 8, 9, 10, 0}});
  const ValidationReport report = validate_hex_complex(c, nullptr, false, true);
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(report.find(Invariant::HexesShareTwoFaces), nullptr) << report.summary();
  // the check is on by default; without it, this pair is not seen
  EXPECT_NE(validate_hex_complex(c).find(Invariant::SharedNodesNotAFace), nullptr);
  EXPECT_EQ(validate_hex_complex(c, nullptr, false, false).find(Invariant::SharedNodesNotAFace),
            nullptr);
  const Violation* v = report.find(Invariant::SharedNodesNotAFace);
  ASSERT_NE(v, nullptr) << report.summary();
  EXPECT_EQ(v->count, 1U);
  EXPECT_EQ(v->examples, std::vector<std::string>{"h0+h1:n0,n4,n5,n6,n7"});
  EXPECT_EQ(v->name(), "shared_nodes_not_a_face");
  EXPECT_NE(report.summary().find("shared_nodes_not_a_face: 1 (h0+h1:n0,n4,n5,n6,n7)"),
            std::string::npos)
      << report.summary();
  try {
    require_valid(report);
    FAIL() << "require_valid must throw";
  } catch (const InternalError& e) {
    EXPECT_NE(std::string(e.what()).find("shared_nodes_not_a_face"), std::string::npos) << e.what();
  }
  // the face and an edge n0-n1 of both off it: 6 nodes, and still only one shared face
  const HexComplex six = complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {4, 5, 6, 7, 8, 9, 1, 0}});
  const ValidationReport six_report = validate_hex_complex(six, nullptr, false, true);
  EXPECT_EQ(six_report.find(Invariant::HexesShareTwoFaces), nullptr) << six_report.summary();
  EXPECT_EQ(bad_intersections(six), std::vector<std::string>{"h0+h1:n0,n1,n4,n5,n6,n7"});
  // without the extra node: two hexes glued along a face, a valid complex
  const HexComplex glued = complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {4, 5, 6, 7, 8, 9, 10, 11}});
  EXPECT_TRUE(validate_hex_complex(glued, nullptr, false, true).valid);
}

TEST(ValidateIntersection, TwoOrThreeSharedNodesOffACellAreNotRefusedHere) {
  // n0-n1, an edge of both, and n6, on no face of the first hex with them
  const HexComplex three = complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {0, 1, 8, 9, 10, 11, 6, 12}});
  EXPECT_TRUE(bad_intersections(three).empty());
  // three corners of a face of each, n1 joined to n0 and n2 in the first hex, n0 to n1 and n2
  // in the second
  EXPECT_TRUE(bad_intersections(complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {0, 1, 8, 2, 9, 10, 11, 12}}))
                  .empty());
  // a face diagonal of the first hex, an edge of the second; a body diagonal of both
  EXPECT_TRUE(
      bad_intersections(complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {0, 2, 8, 9, 10, 11, 12, 13}}))
          .empty());
  EXPECT_TRUE(
      bad_intersections(complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {0, 8, 9, 10, 11, 12, 6, 13}}))
          .empty());
  // one more shared node makes four that are not a face of both: refused
  EXPECT_EQ(bad_intersections(complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {0, 1, 8, 9, 10, 11, 6, 7}})),
            std::vector<std::string>{"h0+h1:n0,n1,n6,n7"});
}

TEST(ValidateIntersection, ThreeNodesOfAPinchedFacePairAreLeftToThatCheck) {
  // n1 joined to n0 and n2 in both hexes: the faces (n1 n0 n3 n2) and (n1 n0 n8 n2) are a
  // pinched face pair, refused only with check_pinched_faces, as such
  const HexComplex c = complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {1, 0, 8, 2, 9, 10, 11, 12}});
  EXPECT_TRUE(bad_intersections(c).empty());
  const ValidationReport strict = validate_hex_complex(c, nullptr, true, true);
  EXPECT_EQ(strict.find(Invariant::SharedNodesNotAFace), nullptr) << strict.summary();
  const Violation* pinched = strict.find(Invariant::PinchedFacePair);
  ASSERT_NE(pinched, nullptr) << strict.summary();
  EXPECT_EQ(pinched->examples, std::vector<std::string>{"n1-n0-n2"});
  // with one more shared node (n4 joined to n0 in both) it is refused all the same
  EXPECT_EQ(bad_intersections(complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {1, 0, 8, 2, 9, 4, 11, 12}})),
            std::vector<std::string>{"h0+h1:n0,n1,n2,n4"});
}

TEST(ValidateIntersection, FourSharedNodesThatAreNotAFaceOfBothAreRefused) {
  // the face (n0 n1 n5 n4) of the first hex is a diagonal section of the second
  EXPECT_EQ(bad_intersections(complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {0, 8, 1, 9, 4, 10, 5, 11}})),
            std::vector<std::string>{"h0+h1:n0,n1,n4,n5"});
  // two opposite edges, n0-n4 and n2-n6, of both
  EXPECT_EQ(bad_intersections(complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {0, 8, 2, 9, 4, 10, 6, 11}})),
            std::vector<std::string>{"h0+h1:n0,n2,n4,n6"});
}

TEST(ValidateIntersection, TwoHexesOnTheSameNodesAreRefused) {
  const std::vector<std::string> all{"h0+h1:n0,n1,n2,n3,n4,n5,n6,n7"};
  // the same hex twice; upside down (the other orientation); turned about its vertical axis
  for (const auto& second : {std::initializer_list<int>{0, 1, 2, 3, 4, 5, 6, 7},
                             std::initializer_list<int>{4, 5, 6, 7, 0, 1, 2, 3},
                             std::initializer_list<int>{1, 2, 3, 0, 5, 6, 7, 4}}) {
    HexComplex c = complex_of({{0, 1, 2, 3, 4, 5, 6, 7}});
    c.hexes.push_back(hex_of(second));
    EXPECT_EQ(bad_intersections(c), all);
    EXPECT_FALSE(validate_hex_complex(c, nullptr, false, true).valid);
  }
  // a duplicate inside a box: its copy shares every node with it, and the box's pairs stay
  // right
  HexComplex box = test::box_hexes(2, 2, 2).complex;
  box.hexes.push_back(box.hexes[5]);
  const std::vector<std::string> found = bad_intersections(box);
  ASSERT_EQ(found.size(), 1U);
  EXPECT_EQ(found.front().rfind("h5+h8:", 0), 0U) << found.front();
}

TEST(ValidateIntersection, HexesSharingAFaceAnEdgeOrANodeAreAccepted) {
  // a face: a valid complex
  EXPECT_TRUE(
      validate_hex_complex(complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {1, 8, 9, 2, 5, 10, 11, 6}}),
                           nullptr, false, true)
          .valid);
  // an edge n2-n6 only, or a node n6 only: not manifolds (the edge fan, the vertex link), but
  // each pair meets in one cell
  EXPECT_TRUE(
      bad_intersections(complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {2, 8, 9, 10, 6, 11, 12, 13}}))
          .empty());
  EXPECT_TRUE(
      bad_intersections(complex_of({{0, 1, 2, 3, 4, 5, 6, 7}, {6, 8, 9, 10, 11, 12, 13, 14}}))
          .empty());
}

TEST(ValidateIntersection, BlockOfTwoByTwoByTwoIsAccepted) {
  // its 28 pairs of hexes: 12 share a face, 12 an edge, 4 the centre node
  const HexComplex c = test::box_hexes(2, 2, 2).complex;
  std::map<std::size_t, int> pairs_by_shared;
  for (std::size_t h = 0; h < c.hexes.size(); ++h) {
    for (std::size_t g = h + 1; g < c.hexes.size(); ++g) {
      std::size_t shared = 0;
      for (const NodeId v : c.hexes[h])
        shared += static_cast<std::size_t>(std::count(c.hexes[g].begin(), c.hexes[g].end(), v));
      ++pairs_by_shared[shared];
    }
  }
  EXPECT_EQ(pairs_by_shared, (std::map<std::size_t, int>{{1, 4}, {2, 12}, {4, 12}}));
  const ValidationReport report = validate_hex_complex(c, nullptr, true, true);
  EXPECT_TRUE(report.valid) << report.summary();
  EXPECT_TRUE(shared_nodes_not_a_face_by_definition(c).empty());
}

/// The cubes of Z^3 modulo the lattice spanned by (n1 0 0), (s n2 0), (t u n3): a closed
/// complex of n1 n2 n3 hexes (a flat 3-torus), node (x y z) with 0 <= x < n1, 0 <= y < n2,
/// 0 <= z < n3 numbered x + n1 (y + n2 z).
HexComplex torus(int n1, int s, int n2, int t, int u, int n3) {
  const auto floor_div = [](int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
  const auto node = [&](int x, int y, int z) {
    const int k = floor_div(z, n3);
    x -= k * t;
    y -= k * u;
    z -= k * n3;
    const int j = floor_div(y, n2);
    x -= j * s;
    y -= j * n2;
    x -= floor_div(x, n1) * n1;
    return NodeId(x + n1 * (y + n2 * z));
  };
  HexComplex c;
  c.num_nodes = static_cast<std::size_t>(n1 * n2 * n3);
  for (int z = 0; z < n3; ++z) {
    for (int y = 0; y < n2; ++y) {
      for (int x = 0; x < n1; ++x) {
        c.hexes.push_back({node(x, y, z), node(x + 1, y, z), node(x + 1, y + 1, z),
                           node(x, y + 1, z), node(x, y, z + 1), node(x + 1, y, z + 1),
                           node(x + 1, y + 1, z + 1), node(x, y + 1, z + 1)});
      }
    }
  }
  return c;
}

TEST(ValidateIntersection, ShearedTorusIsRefusedByThisCheckAlone) {
  // With periods of 3 the cubes of the 3-torus meet in one cell: valid.
  const HexComplex straight = torus(3, 0, 3, 0, 0, 3);
  const ValidationReport valid = validate_hex_complex(straight, nullptr, true, true);
  EXPECT_TRUE(valid.valid) << valid.summary();
  EXPECT_EQ(valid.euler_volume, 0);
  // With (2 2 0) in the lattice, the cube at (0 0 0) and the one at (1 1 0) share their
  // vertical edges at (1 1) and at (2 2) ~ (0 0): a diagonal section of both, not a face
  // (and the cubes one layer up or down share one diagonal of it). Every edge cycle and
  // vertex link is right (a closed manifold, chi 0): only this check sees it.
  const HexComplex sheared = torus(4, 2, 2, 0, 0, 3);
  const ValidationReport report = validate_hex_complex(sheared, nullptr, true, true);
  EXPECT_EQ(violated(report), std::set<Invariant>{Invariant::SharedNodesNotAFace})
      << report.summary();
  const Violation* v = report.find(Invariant::SharedNodesNotAFace);
  ASSERT_NE(v, nullptr);
  const std::vector<std::string> expected = shared_nodes_not_a_face_by_definition(sheared);
  EXPECT_EQ(v->count, expected.size());
  ASSERT_FALSE(expected.empty());
  EXPECT_EQ(v->examples.front(), expected.front());
  EXPECT_EQ(v->examples.front(), "h0+h5:n0,n5,n8,n13");              // nodes (0 0 z) and (1 1 z)
  EXPECT_FALSE(validate_hex_complex(sheared, nullptr, true).valid);  // by default
  EXPECT_TRUE(validate_hex_complex(sheared, nullptr, true, false).valid);  // without the check
  // the check alone gives the same violation; none on the straight torus
  const Violation alone = shared_nodes_not_a_face(sheared);
  EXPECT_EQ(alone.count, v->count);
  EXPECT_EQ(alone.examples, v->examples);
  EXPECT_EQ(alone.invariant, Invariant::SharedNodesNotAFace);
  EXPECT_EQ(shared_nodes_not_a_face(straight).count, 0U);
}

TEST(ValidateIntersection, MatchesTheDefinitionOnBoxesWithMergedNodes) {
  // Boxes with random pairs of nodes merged: every kind of intersection, compared pair by
  // pair with the quadratic definition (hexes left with a repeated node excluded by both).
  std::mt19937 rng(11);
  std::size_t refused = 0;
  std::size_t accepted = 0;
  for (int trial = 0; trial < 300; ++trial) {
    HexComplex c = test::box_hexes(3, 2, 2).complex;
    std::uniform_int_distribution<int> pick(0, static_cast<int>(c.num_nodes) - 1);
    const int merges = 1 + trial % 3;
    for (int m = 0; m < merges; ++m) {
      const NodeId from(pick(rng));
      const NodeId to(pick(rng));
      for (Hex& h : c.hexes)
        for (NodeId& v : h)
          if (v == from) v = to;
    }
    const std::vector<std::string> expected = shared_nodes_not_a_face_by_definition(c);
    const ValidationReport report = validate_hex_complex(c, nullptr, false, true);
    const Violation* v = report.find(Invariant::SharedNodesNotAFace);
    if (expected.empty()) {
      EXPECT_EQ(v, nullptr) << "trial " << trial << ": " << report.summary();
      ++accepted;
      continue;
    }
    ++refused;
    ASSERT_NE(v, nullptr) << "trial " << trial;
    EXPECT_EQ(v->count, expected.size()) << "trial " << trial;
    const std::size_t shown = std::min(expected.size(), Violation::kMaxExamples);
    EXPECT_EQ(v->examples,
              std::vector<std::string>(expected.begin(),
                                       expected.begin() + static_cast<std::ptrdiff_t>(shown)))
        << "trial " << trial;
  }
  EXPECT_GT(refused, 50U);
  EXPECT_GT(accepted, 20U);
}

}  // namespace
}  // namespace stcweave::stc
