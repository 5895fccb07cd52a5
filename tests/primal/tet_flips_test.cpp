#include "../../primal/src/tet_flips.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace stcweave::primal {
namespace {

double volume(const Points& p, const stc::Tet& t) {
  const Eigen::Vector3d o = p.row(t[0].value()).transpose();
  return (p.row(t[1].value()).transpose() - o)
      .dot((p.row(t[2].value()).transpose() - o).cross(p.row(t[3].value()).transpose() - o));
}

/// Nodes: 0 = a, 1 = b (the axis), then the ring.
Points axis_and_ring(const Eigen::Vector3d& a, const Eigen::Vector3d& b, std::size_t ring) {
  Points p(static_cast<Eigen::Index>(2 + ring), 3);
  p.row(0) = a.transpose();
  p.row(1) = b.transpose();
  for (std::size_t k = 0; k < ring; ++k) {
    const double t = 2.0 * M_PI * static_cast<double>(k) / static_cast<double>(ring);
    p.row(static_cast<Eigen::Index>(2 + k)) << std::cos(t), std::sin(t), 0.0;
  }
  return p;
}

/// The tets around the axis 0-1 through ring nodes 2 .. 2 + count, positively oriented;
/// `closed` joins the last ring node to the first.
std::vector<stc::Tet> fan(const Points& p, std::size_t ring, bool closed) {
  std::vector<stc::Tet> tets;
  const std::size_t count = closed ? ring : ring - 1;
  for (std::size_t k = 0; k < count; ++k) {
    stc::Tet t{NodeId(0), NodeId(1), NodeId(2 + k), NodeId(2 + (k + 1) % ring)};
    if (volume(p, t) < 0.0) std::swap(t[2], t[3]);
    tets.push_back(t);
  }
  return tets;
}

double total_volume(const Points& p, const std::vector<stc::Tet>& tets) {
  double v = 0.0;
  for (const stc::Tet& t : tets) v += volume(p, t);
  return v;
}

double worst(const Points& p, const std::vector<stc::Tet>& tets) {
  double w = INFINITY;
  for (const stc::Tet& t : tets) w = std::min(w, tet_corner_quality(p, t));
  return w;
}

TEST(TetCornerQuality, IsBelowOneForACubeCornerTetAndNegativeWhenInverted) {
  Points p(4, 3);
  p << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  stc::Tet t{NodeId(0), NodeId(1), NodeId(2), NodeId(3)};
  // The corner at node 0 is a cube's (1); the others are worse.
  EXPECT_GT(tet_corner_quality(p, t), 0.0);
  EXPECT_LT(tet_corner_quality(p, t), 1.0);
  std::swap(t[2], t[3]);
  EXPECT_LT(tet_corner_quality(p, t), 0.0);
  // A regular tet: sqrt(2) / 2 at every corner.
  Points r(4, 3);
  r << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  stc::Tet u{NodeId(0), NodeId(1), NodeId(2), NodeId(3)};
  if (volume(r, u) < 0.0) std::swap(u[2], u[3]);
  EXPECT_NEAR(tet_corner_quality(r, u), std::sqrt(2.0) / 2.0, 1e-12);
}

TEST(TetFlips, ThreeTetsAroundAnInteriorEdgeBecomeTwoFillingTheSameBipyramid) {
  const Points p = axis_and_ring({0.0, 0.0, 1.0}, {0.0, 0.0, -1.0}, 3);
  std::vector<stc::Tet> tets = fan(p, 3, true);
  const double before = total_volume(p, tets);
  const TetFlips done = flip_tets(p, tets, 0.0);
  EXPECT_EQ(done.flips, 1u);
  ASSERT_EQ(tets.size(), 2u);
  for (const stc::Tet& t : tets) {
    EXPECT_GT(volume(p, t), 0.0);
    // The axis is gone: each new tet holds one of its ends and the whole ring.
    EXPECT_EQ(std::count(t.begin(), t.end(), NodeId(0)) + std::count(t.begin(), t.end(), NodeId(1)),
              1);
  }
  EXPECT_NEAR(total_volume(p, tets), before, 1e-12);
}

TEST(TetFlips, AFloorOfOneNeverLowersTheWorstTetAndZeroTakesAnyPositiveFlip) {
  // From a flat bipyramid (new tets flat) to a tall one (old tets thin): the rule, checked
  // against qualities computed here, must both refuse and accept over this range.
  bool refused = false;
  bool accepted = false;
  for (const double h : {0.05, 0.1, 0.2, 0.4, 0.8, 1.6, 3.2}) {
    const Points p = axis_and_ring({0.0, 0.0, h}, {0.0, 0.0, -h}, 3);
    const std::vector<stc::Tet> old = fan(p, 3, true);
    std::vector<stc::Tet> strict = old;
    const TetFlips s = flip_tets(p, strict, 1.0);
    std::vector<stc::Tet> any = old;
    const TetFlips a = flip_tets(p, any, 0.0);
    EXPECT_EQ(a.flips, 1u) << "h " << h;
    EXPECT_EQ(s.flips == 1, worst(p, any) >= worst(p, old)) << "h " << h;
    if (s.flips == 1) EXPECT_GE(worst(p, strict), worst(p, old)) << "h " << h;
    refused = refused || s.flips == 0;
    accepted = accepted || s.flips == 1;
  }
  EXPECT_TRUE(refused);
  EXPECT_TRUE(accepted);
}

/// The fan of `ring` tets round the axis a-b, closed or not, is left exactly as it was, even
/// with no quality floor.
void expect_kept(const Eigen::Vector3d& a, const Eigen::Vector3d& b, std::size_t ring,
                 bool closed) {
  const Points p = axis_and_ring(a, b, ring);
  std::vector<stc::Tet> tets = fan(p, ring, closed);
  const std::vector<stc::Tet> before = tets;
  EXPECT_EQ(flip_tets(p, tets, 0.0).flips, 0u);
  EXPECT_EQ(tets, before);
}

TEST(TetFlips, AnAxisThatMissesTheRingsTriangleIsKept) {
  // Both ends above the ring: a concave tent, no two tets can fill it.
  expect_kept({0.0, 0.0, 2.0}, {0.0, 0.0, 1.0}, 3, true);
}

TEST(TetFlips, ABoundaryEdgeWithThreeTetsInAnOpenFanIsKept) {
  expect_kept({0.0, 0.0, 1.0}, {0.0, 0.0, -1.0}, 4, false);  // three tets, one edge open
}

TEST(TetFlips, FourTetsAroundAnEdgeAreNotAThreeTwoFlip) {
  expect_kept({0.0, 0.0, 1.0}, {0.0, 0.0, -1.0}, 4, true);
}

}  // namespace
}  // namespace stcweave::primal
