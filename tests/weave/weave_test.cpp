#include "stcweave/weave/weave.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/hex_complex.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

/// Structural checks that do not rely on the validator under test elsewhere: 8 distinct
/// nodes per hex, every face in at most two hexes, the faces used once are exactly the input
/// quads (same orientation up to rotation), every dual link is symmetric.
void expect_closed_complex(const stc::QuadSurface& input, const WeaveResult& r) {
  for (const auto& h : r.complex.hexes) {
    std::set<NodeId> distinct(h.begin(), h.end());
    EXPECT_EQ(distinct.size(), 8u);
  }
  std::map<std::array<NodeId, 4>, int> uses;
  for (const auto& h : r.complex.hexes)
    for (int f = 0; f < 6; ++f) {
      auto k = stc::hex_face(h, f);
      std::sort(k.begin(), k.end());
      ++uses[k];
    }
  for (const auto& [k, n] : uses) EXPECT_LE(n, 2);
  const stc::QuadSurface boundary = stc::boundary_surface(r.complex);
  const auto canonical = [](stc::Quad q) {
    const auto it = std::min_element(q.begin(), q.end());
    std::rotate(q.begin(), it, q.end());
    return q;
  };
  std::set<stc::Quad> expected, got;
  for (const auto& q : input.quads) expected.insert(canonical(q));
  for (const auto& q : boundary.quads) got.insert(canonical(q));
  EXPECT_EQ(expected, got) << "the faces used once must be exactly the input quads";
  ASSERT_EQ(r.dual.size(), r.complex.hexes.size());
  for (std::size_t h = 0; h < r.dual.size(); ++h)
    for (int f = 0; f < 6; ++f) {
      const DualLink& l = r.dual[h][static_cast<std::size_t>(f)];
      ASSERT_GE(l.id, 0) << "hex face without a neighbour in the woven STC";
      if (!l.is_boundary) {
        const DualLink& back =
            r.dual[static_cast<std::size_t>(l.id)][static_cast<std::size_t>(l.local_face)];
        EXPECT_FALSE(back.is_boundary);
        EXPECT_EQ(back.id, static_cast<std::int32_t>(h));
        EXPECT_EQ(back.local_face, f);
      }
    }
}

TEST(Weave, CubeGivesOneHex) {
  const auto cube = test::box_surface(1, 1, 1);
  WeaveOptions opt;
  opt.check = true;
  const WeaveResult r = weave(cube.surface, opt);
  EXPECT_EQ(r.complex.hexes.size(), 1u);
  EXPECT_EQ(r.complex.num_nodes, 8u);
  expect_closed_complex(cube.surface, r);
}

TEST(Weave, BarsGiveOneHexPerCell) {
  for (int n = 2; n <= 3; ++n) {
    const auto bar = test::box_surface(1, 1, n);
    WeaveOptions opt;
    opt.check = true;
    const WeaveResult r = weave(bar.surface, opt);
    EXPECT_EQ(r.complex.hexes.size(), static_cast<std::size_t>(n)) << "1x1x" << n;
    EXPECT_EQ(r.complex.num_nodes, bar.surface.num_nodes) << "no interior node";
    expect_closed_complex(bar.surface, r);
  }
}

class BoxWeave : public ::testing::TestWithParam<std::tuple<int, int, int>> {};

TEST_P(BoxWeave, GivesTheStructuredCount) {
  const auto [a, b, c] = GetParam();
  const auto box = test::box_surface(a, b, c);
  WeaveOptions opt;
  opt.check = a * b * c <= 27;
  const WeaveResult r = weave(box.surface, opt);
  EXPECT_EQ(r.complex.hexes.size(), static_cast<std::size_t>(a * b * c));
  EXPECT_EQ(r.complex.num_nodes - r.num_input_nodes,
            static_cast<std::size_t>((a - 1) * (b - 1) * (c - 1)));
  expect_closed_complex(box.surface, r);
}

INSTANTIATE_TEST_SUITE_P(UpToFour, BoxWeave,
                         ::testing::Combine(::testing::Range(1, 5), ::testing::Range(1, 5),
                                            ::testing::Range(1, 5)));

TEST(Weave, RhombicDodecahedronCloses) {
  const auto rd = test::rhombic_dodecahedron();
  WeaveOptions opt;
  opt.check = true;
  const WeaveResult r = weave(rd.surface, opt);
  EXPECT_GE(r.complex.hexes.size(), 4u) << "4 hexes is the known minimum";
  expect_closed_complex(rd.surface, r);
}

TEST(Weave, TraceHasSelectionsAndRules) {
  const auto box = test::box_surface(2, 1, 1);
  WeaveOptions opt;
  opt.trace = true;
  const WeaveResult r = weave(box.surface, opt);
  const auto selections = std::count_if(r.trace.begin(), r.trace.end(), [](const TraceEvent& e) {
    return e.kind == TraceEvent::Kind::Selection;
  });
  const auto hex_rules = std::count_if(r.trace.begin(), r.trace.end(), [](const TraceEvent& e) {
    return e.kind == TraceEvent::Kind::Rule && e.hex.is_valid();
  });
  EXPECT_GE(selections, 1);
  EXPECT_EQ(static_cast<std::size_t>(hex_rules), r.complex.hexes.size());
}

TEST(Weave, IsDeterministic) {
  const auto rd = test::rhombic_dodecahedron();
  const WeaveResult a = weave(rd.surface);
  const WeaveResult b = weave(rd.surface);
  EXPECT_EQ(a.complex.hexes, b.complex.hexes);
}

TEST(Weave, OpenSurfaceIsInvalidInput) {
  auto cube = test::box_surface(1, 1, 1);
  cube.surface.quads.pop_back();
  EXPECT_THROW(weave(cube.surface), InvalidInput);
}

TEST(Weave, RuleLimitGivesWeaveError) {
  const auto box = test::box_surface(3, 3, 3);
  WeaveOptions opt;
  opt.max_rules = 5;
  EXPECT_THROW(weave(box.surface, opt), WeaveError);
}

}  // namespace
}  // namespace stcweave::weave
