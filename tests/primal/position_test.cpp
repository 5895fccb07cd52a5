// Node positioning with a fixed boundary (`stcweave/primal/position.hpp`): scrambled and
// collapsed boxes come back to the grid (min scaled Jacobian >= 0.99), a bent box whose
// harmonic placement is tangled is untangled, fixed nodes never move, and topologies or
// fixed corners that no position can fix are reported by element instead of iterated on.
#include "stcweave/primal/position.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "primal/position_helpers.hpp"
#include "stcweave/primal/recover.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

struct BoxCase {
  int a, b, c;
};

class ScrambledBox : public ::testing::TestWithParam<BoxCase> {};

TEST_P(ScrambledBox, ComesBackToTheGrid) {
  const auto [a, b, c] = GetParam();
  HexMesh mesh = test::box_hexes(a, b, c, 1.0, 1.5, 0.8);
  PositionOptions options;
  options.fixed = test::boundary_nodes(mesh);
  test::scramble(mesh, options.fixed, 0.5, 42);
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_EQ(r.inverted_after, 0u);
  EXPECT_TRUE(r.inverted.empty());
  EXPECT_TRUE(r.impossible.empty());
  EXPECT_GE(r.min_scaled_jacobian_after, 0.99) << r.stop;
  EXPECT_EQ(r.certified.valid, mesh.complex.hexes.size());
  EXPECT_TRUE(r.converged) << r.stop;
  EXPECT_EQ(r.stop, "converged");
  EXPECT_GT(r.iterations, 0u);
  EXPECT_GE(r.outer_iterations, 1u);
  EXPECT_LE(r.energy_after, r.energy_before);
  EXPECT_DOUBLE_EQ(summarize_quality(mesh).min_scaled_jacobian, r.min_scaled_jacobian_after);
}

TEST_P(ScrambledBox, CollapsedInteriorComesBackToTheGrid) {
  const auto [a, b, c] = GetParam();
  HexMesh mesh = test::box_hexes(a, b, c, 1.0, 1.5, 0.8);
  PositionOptions options;
  options.fixed = test::boundary_nodes(mesh);
  test::collapse(mesh, options.fixed);
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_GT(r.inverted_before, 0u);
  EXPECT_EQ(r.inverted_after, 0u);
  EXPECT_GE(r.min_scaled_jacobian_after, 0.99) << r.stop;
}

INSTANTIATE_TEST_SUITE_P(Boxes, ScrambledBox,
                         ::testing::Values(BoxCase{3, 3, 3}, BoxCase{4, 3, 2}, BoxCase{5, 5, 5},
                                           BoxCase{2, 2, 7}),
                         [](const auto& info) {
                           return std::to_string(info.param.a) + "x" +
                                  std::to_string(info.param.b) + "x" + std::to_string(info.param.c);
                         });

TEST(Position, FixedNodesKeepTheirCoordinatesBitForBit) {
  HexMesh mesh = test::box_hexes(4, 4, 4);
  PositionOptions options;
  options.fixed = test::boundary_nodes(mesh);
  // some interior nodes fixed too, off the grid
  mesh.points.row(31) += Eigen::RowVector3d(0.1, -0.05, 0.02);
  options.fixed[31] = true;
  test::scramble(mesh, options.fixed, 0.5, 7);
  const Points before = mesh.points;
  const PositionReport r = position_nodes(mesh, options);
  for (std::size_t v = 0; v < options.fixed.size(); ++v)
    if (options.fixed[v]) {
      EXPECT_EQ(mesh.points(static_cast<Eigen::Index>(v), 0),
                before(static_cast<Eigen::Index>(v), 0));
      EXPECT_EQ(mesh.points(static_cast<Eigen::Index>(v), 1),
                before(static_cast<Eigen::Index>(v), 1));
      EXPECT_EQ(mesh.points(static_cast<Eigen::Index>(v), 2),
                before(static_cast<Eigen::Index>(v), 2));
    }
  EXPECT_EQ(r.free_nodes, 26u);
  EXPECT_EQ(r.inverted_after, 0u);
}

TEST(Position, IsDeterministic) {
  HexMesh a = test::box_hexes(3, 4, 3);
  PositionOptions options;
  options.fixed = test::boundary_nodes(a);
  test::scramble(a, options.fixed, 0.5, 3);
  HexMesh b = a;
  const PositionReport ra = position_nodes(a, options);
  const PositionReport rb = position_nodes(b, options);
  EXPECT_TRUE(a.points == b.points);
  EXPECT_EQ(ra.iterations, rb.iterations);
  EXPECT_EQ(ra.energy_after, rb.energy_after);
}

TEST(Position, ProgressIsToldEveryRoundAndChangesNothing) {
  HexMesh a = test::box_hexes(3, 4, 3);
  PositionOptions options;
  options.fixed = test::boundary_nodes(a);
  test::scramble(a, options.fixed, 0.5, 3);
  HexMesh b = a;
  const PositionReport quiet = position_nodes(a, options);
  std::vector<PositionProgress> told;
  options.progress = [&told](const PositionProgress& p) { told.push_back(p); };
  const PositionReport loud = position_nodes(b, options);
  EXPECT_TRUE(a.points == b.points) << "a progress callback changed the positions";
  EXPECT_EQ(quiet.iterations, loud.iterations);
  std::vector<PositionProgress> rounds;
  for (const PositionProgress& p : told)
    if (p.phase == PositionProgress::Phase::Untangle) rounds.push_back(p);
  ASSERT_GT(loud.outer_iterations, 0u) << loud.stop;
  ASSERT_EQ(rounds.size(), loud.outer_iterations);
  for (std::size_t i = 0; i < rounds.size(); ++i) {
    EXPECT_EQ(rounds[i].step, i + 1);
    EXPECT_EQ(rounds[i].limit, static_cast<std::size_t>(options.max_outer_iterations));
    if (i > 0) EXPECT_GE(rounds[i].iterations, rounds[i - 1].iterations);
  }
  EXPECT_EQ(rounds.back().iterations, loud.iterations);
  // The last round's count is the report's (no repair: nothing is left inverted).
  EXPECT_EQ(loud.corners_inverted_after, 0u) << loud.stop;
  EXPECT_EQ(rounds.back().inverted, loud.corners_inverted_after);
  // Phases come in order: untangle rounds first, then any local sweeps.
  bool local = false;
  for (const PositionProgress& p : told) {
    if (p.phase != PositionProgress::Phase::Untangle) local = true;
    if (local) EXPECT_NE(p.phase, PositionProgress::Phase::Untangle);
  }
  EXPECT_STREQ(phase_name(PositionProgress::Phase::Untangle), "untangle");
  EXPECT_STREQ(phase_name(PositionProgress::Phase::Repair), "repair");
  EXPECT_STREQ(phase_name(PositionProgress::Phase::Shape), "shape");
  EXPECT_STREQ(phase_name(PositionProgress::Phase::Clusters), "clusters");
}

TEST(Position, ResultDoesNotDependOnTheThreadCount) {
  HexMesh a = test::box_hexes(17, 16, 16);  // 4352 hexes: above the parallel threshold
  PositionOptions options;
  options.fixed = test::boundary_nodes(a);
  test::scramble(a, options.fixed, 0.5, 5);
  HexMesh b = a;
  options.threads = 1;
  const PositionReport ra = position_nodes(a, options);
  options.threads = 3;
  const PositionReport rb = position_nodes(b, options);
  EXPECT_TRUE(a.points == b.points);
  EXPECT_EQ(ra.iterations, rb.iterations);
  EXPECT_EQ(ra.inverted_after, 0u);
}

TEST(Position, UntanglesABentBoxWhoseHarmonicPlacementIsTangled) {
  // research/geometry.md §3.3: a 6^3 grid bent into a 270-degree C; the harmonic map of the
  // bent boundary inverts many hexes; the untangler reaches 0 (measured min SJ there 0.78).
  HexMesh mesh = test::box_hexes(6, 6, 6);
  test::bend(mesh, 6.0, 6.0, 1.0, 1.5 * M_PI);
  ASSERT_EQ(summarize_quality(mesh).inverted, 0u);
  PositionOptions options;
  options.num_fixed = test::boundary_first(mesh);
  options.start = StartPosition::Harmonic;
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_GT(r.inverted_before, 0u) << "the harmonic start should be tangled";
  EXPECT_EQ(r.inverted_after, 0u) << r.stop;
  EXPECT_GT(r.min_scaled_jacobian_after, 0.5);
  EXPECT_EQ(r.certified.valid, mesh.complex.hexes.size());
}

/// The 8^3 box bent into a 270-degree C, boundary nodes first, and options that start from
/// its (tangled) harmonic placement.
HexMesh bent_box(PositionOptions& options) {
  HexMesh mesh = test::box_hexes(8, 8, 8);
  test::bend(mesh, 8.0, 8.0, 1.0, 1.5 * M_PI);
  options.num_fixed = test::boundary_first(mesh);
  options.start = StartPosition::Harmonic;
  return mesh;
}

TEST(Position, PreconditionedUntanglingNeedsFewerIterationsThanPlainLbfgs) {
  // An 8^3 bent box like the one above, untangled with and without the Laplacian
  // preconditioner (primal/src/position_lbfgs.hpp; tests/primal/position_lbfgs_test.cpp tests
  // the solver alone): both reach
  // 0 inverted hexes, and the preconditioned L-BFGS in fewer iterations (measured 2026-12-05;
  // the Example_3 corpus mesh: 5,881 -> 1,616, docs/geometry.md).
  PositionOptions options;
  HexMesh plain = bent_box(options);
  HexMesh preconditioned = plain;
  options.precondition = false;
  const PositionReport rp = position_nodes(plain, options);
  options.precondition = true;
  const PositionReport rq = position_nodes(preconditioned, options);
  EXPECT_GT(rq.inverted_before, 0u);
  EXPECT_EQ(rp.inverted_after, 0u) << rp.stop;
  EXPECT_EQ(rq.inverted_after, 0u) << rq.stop;
  EXPECT_LT(rq.iterations, rp.iterations);
  EXPECT_GT(rq.min_scaled_jacobian_after, 0.5);
  // Deterministic like the rest: the same input gives the same positions.
  HexMesh again = bent_box(options);
  const PositionReport ra = position_nodes(again, options);
  EXPECT_EQ(ra.iterations, rq.iterations);
  EXPECT_TRUE(again.points == preconditioned.points);
}

TEST(Position, StallFractionDecidesWhichDropsCount) {
  // Rounds of one iteration leave the bent box tangled for many rounds. With stall_fraction 1
  // no drop counts: stalled after exactly stall_iterations rounds. With 0 every drop counts
  // and the rounds go on.
  PositionOptions options;
  HexMesh strict = bent_box(options);
  options.max_inner_iterations = 1;
  HexMesh lenient = strict;
  options.stall_fraction = 1.0;
  const PositionReport rs = position_nodes(strict, options);
  options.stall_fraction = 0.0;
  const PositionReport rl = position_nodes(lenient, options);
  EXPECT_EQ(rs.outer_iterations, static_cast<std::size_t>(options.stall_iterations));
  EXPECT_EQ(rs.stop.rfind("stalled", 0), 0u) << rs.stop;
  EXPECT_GT(rl.outer_iterations, rs.outer_iterations) << rl.stop;
  // Outside [0, 1] it means nothing: refused.
  options.stall_fraction = 1.5;
  EXPECT_THROW(position_nodes(lenient, options), InvalidInput);
  options.stall_fraction = -0.1;
  EXPECT_THROW(position_nodes(lenient, options), InvalidInput);
}

TEST(Position, ARoundWhoseEpsStillFallsIsNotCountedAsAStall) {
  // The 2x2x2 box with the centres of its top and bottom faces pushed past each other (the
  // top one to z = 0.2, the bottom one to z = 1.8): the interior node cannot be above the
  // second and below the first, so corners stay inverted and the rounds stall. Every round before
  // the last either removed 5 % of the inverted corners (below the count at the last such drop) or
  // left a next eps 5 % below its own; the last one ("stalled") did neither. Some round must have
  // gone on for its eps alone, or this checks nothing.
  HexMesh mesh = test::box_hexes(2, 2, 2);
  PositionOptions options;
  options.fixed = test::boundary_nodes(mesh);
  int pushed = 0;
  for (Eigen::Index v = 0; v < mesh.points.rows(); ++v) {
    if (mesh.points(v, 0) != 1.0 || mesh.points(v, 1) != 1.0) continue;
    if (mesh.points(v, 2) == 2.0 || mesh.points(v, 2) == 0.0) {
      mesh.points(v, 2) = mesh.points(v, 2) == 2.0 ? 0.2 : 1.8;
      ++pushed;
    }
  }
  ASSERT_EQ(pushed, 2);
  ASSERT_EQ(options.stall_iterations, 1);
  const double keep = 1.0 - options.stall_fraction;
  std::vector<PositionProgress> rounds;
  options.progress = [&rounds](const PositionProgress& p) {
    if (p.phase == PositionProgress::Phase::Untangle) rounds.push_back(p);
  };
  const PositionReport r = position_nodes(mesh, options);
  ASSERT_TRUE(r.impossible.empty());  // so the rounds count every corner the start counted
  ASSERT_EQ(rounds.size(), r.outer_iterations);
  ASSERT_EQ(r.stop.rfind("stalled", 0), 0u) << r.stop;
  ASSERT_GT(rounds.size(), 1u) << r.stop;
  double best = static_cast<double>(r.corners_inverted_before);
  int for_eps_alone = 0;
  for (std::size_t i = 0; i < rounds.size(); ++i) {
    const PositionProgress& p = rounds[i];
    if (i > 0) EXPECT_DOUBLE_EQ(p.epsilon, rounds[i - 1].next_epsilon) << "round " << i + 1;
    const bool dropped = static_cast<double>(p.inverted) < keep * best;
    const bool eps_fell = p.next_epsilon < keep * p.epsilon;
    if (dropped) best = static_cast<double>(p.inverted);
    if (i + 1 < rounds.size()) {
      EXPECT_TRUE(dropped || eps_fell) << "round " << i + 1 << " was a stall and did not stop";
      for_eps_alone += !dropped && eps_fell ? 1 : 0;
    } else {
      EXPECT_FALSE(dropped || eps_fell) << "the last round was no stall";
      EXPECT_GT(p.inverted, 0u);
    }
  }
  EXPECT_GT(for_eps_alone, 0) << "no round went on for its falling eps alone";
}

TEST(Position, TotalIterationsBoundEveryRound) {
  // The bent box needs more than a dozen iterations to untangle: with a total bound of 12
  // the rounds stop there, the last one cut short, and the report says why; with no bound
  // (0) the same start goes on and untangles. A negative bound is refused.
  PositionOptions options;
  HexMesh bounded = bent_box(options);
  HexMesh free = bounded;
  options.max_total_iterations = 12;
  const PositionReport rb = position_nodes(bounded, options);
  EXPECT_LE(rb.iterations, 12U);
  EXPECT_GT(rb.iterations, 0U);
  EXPECT_EQ(rb.stop.rfind("iteration budget (12 L-BFGS iterations)", 0), 0U) << rb.stop;
  EXPECT_FALSE(rb.converged);
  options.max_total_iterations = 0;
  const PositionReport rf = position_nodes(free, options);
  EXPECT_GT(rf.iterations, 12U) << rf.stop;
  EXPECT_EQ(rf.stop.find("iteration budget"), std::string::npos) << rf.stop;
  // The bound is over every round: rounds of 5 iterations under a total of 12 are 5, 5 and
  // a third cut to 2.
  HexMesh rounds = bent_box(options);
  options.max_inner_iterations = 5;
  options.max_total_iterations = 12;
  const PositionReport rr = position_nodes(rounds, options);
  EXPECT_EQ(rr.iterations, 12U) << rr.stop;
  EXPECT_EQ(rr.outer_iterations, 3U) << rr.stop;
  EXPECT_EQ(rr.stop.rfind("iteration budget", 0), 0U) << rr.stop;
  options.max_total_iterations = -1;
  EXPECT_THROW(position_nodes(free, options), InvalidInput);
}

TEST(Position, HarmonicStartWorksWithAMask) {
  // The harmonic placement of a box's interior is the grid itself.
  HexMesh mesh = test::box_hexes(4, 3, 3);
  const Points grid = mesh.points;
  PositionOptions options;
  options.fixed = test::boundary_nodes(mesh);
  test::collapse(mesh, options.fixed);
  options.start = StartPosition::Harmonic;
  options.max_outer_iterations = 1;
  options.max_inner_iterations = 1;
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_TRUE(r.harmonic_start);
  EXPECT_EQ(r.inverted_before, 0u);
  EXPECT_TRUE(mesh.points.isApprox(grid, 1e-9));
}

TEST(Position, AutoStartKeepsABetterCurrentPlacement) {
  // bent box: the harmonic map is tangled, the bent grid is not, so Auto keeps the grid
  HexMesh mesh = test::box_hexes(6, 6, 6);
  test::bend(mesh, 6.0, 6.0, 1.0, 1.5 * M_PI);
  PositionOptions options;
  options.fixed = test::boundary_nodes(mesh);
  options.start = StartPosition::Auto;
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_FALSE(r.harmonic_start);
  EXPECT_EQ(r.inverted_before, 0u);
  EXPECT_EQ(r.inverted_after, 0u);
}

TEST(Position, MirroredMeshIsRejected) {
  HexMesh mesh = test::box_hexes(3, 3, 3);
  mesh.points.col(0) *= -1.0;
  PositionOptions options;
  options.fixed = test::boundary_nodes(mesh);
  EXPECT_THROW((void)position_nodes(mesh, options), InvalidInput);
}

TEST(Position, MessagesTellAMirroredFromAFlatAndAnOverflowingMesh) {
  const auto message = [](HexMesh mesh) {
    PositionOptions options;
    options.fixed = test::boundary_nodes(mesh);
    try {
      (void)position_nodes(mesh, options);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  HexMesh mirrored = test::box_hexes(3, 3, 3);
  mirrored.points.col(0) *= -1.0;
  EXPECT_THAT(message(mirrored), ::testing::HasSubstr("mirrored"));
  HexMesh flat = test::box_hexes(3, 3, 3);
  flat.points.col(2).setZero();
  EXPECT_THAT(message(flat), ::testing::HasSubstr("enclose no volume"));
  HexMesh thin = test::box_hexes(3, 3, 3);  // mirrored, but its volume is rounding
  thin.points.col(0) *= -1.0;
  thin.points.col(2) *= 1e-14;
  EXPECT_THAT(message(thin), ::testing::HasSubstr("enclose no volume"));
  HexMesh huge = test::box_hexes(3, 3, 3);
  huge.points *= 1e120;  // volumes overflow to infinity
  EXPECT_THAT(message(huge), ::testing::HasSubstr("not a finite number"));
}

TEST(Position, RealOptionsOutsideTheirRangeOrNaNAreRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int which = 0; which < 4; ++which) {
    for (const double value : {nan, -0.5, 3.0}) {
      HexMesh mesh = test::box_hexes(2, 2, 2);
      PositionOptions options;
      options.fixed = test::boundary_nodes(mesh);
      double& field = which == 0   ? options.theta
                      : which == 1 ? options.shape_target
                      : which == 2 ? options.good_start
                                   : options.good_start_mean;
      field = value;
      EXPECT_THROW((void)position_nodes(mesh, options), InvalidInput) << which << " " << value;
    }
  }
}

TEST(Position, WrongMaskSizeIsRejected) {
  HexMesh mesh = test::box_hexes(2, 2, 2);
  PositionOptions options;
  options.fixed.assign(5, true);
  EXPECT_THROW((void)position_nodes(mesh, options), InvalidInput);
}

TEST(Position, NoFreeNodeChangesNothing) {
  HexMesh mesh = test::box_hexes(2, 1, 1);
  const Points before = mesh.points;
  PositionOptions options;
  options.num_fixed = static_cast<std::size_t>(mesh.points.rows());
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_TRUE(mesh.points == before);
  EXPECT_EQ(r.free_nodes, 0u);
  EXPECT_EQ(r.iterations, 0u);
  EXPECT_EQ(r.certified.valid, 2u);
}

TEST(Position, FixedInvertedCornerIsReportedByElementAndTheRestIsUntangled) {
  HexMesh mesh = test::box_hexes(3, 3, 3);
  PositionOptions options;
  options.fixed = test::boundary_nodes(mesh);
  // Node 0 is a corner of the box: its three edge neighbours are boundary nodes, so the
  // corner of hex 0 there has four fixed nodes. Pushing node 0 inside inverts it for good.
  mesh.points.row(0) << 0.9, 0.9, 0.9;
  test::scramble(mesh, options.fixed, 0.5, 11);
  const PositionReport r = position_nodes(mesh, options);
  ASSERT_FALSE(r.impossible.empty());
  EXPECT_EQ(r.impossible.front().hex, HexId(0));
  EXPECT_EQ(r.impossible.front().corner, 0);
  EXPECT_FALSE(r.impossible.front().other.is_valid());
  EXPECT_NE(r.impossible.front().reason.find("h0"), std::string::npos);
  for (const ImpossibleCorner& c : r.impossible) EXPECT_EQ(c.hex, HexId(0));
  ASSERT_EQ(r.inverted.size(), 1u);
  EXPECT_EQ(r.inverted[0], HexId(0));
  ASSERT_EQ(r.validity.size(), mesh.complex.hexes.size());
  EXPECT_EQ(r.validity[0], Validity::Invalid);
  EXPECT_EQ(r.certified.invalid, 1u);
  EXPECT_EQ(r.certified.valid, mesh.complex.hexes.size() - 1);
  EXPECT_EQ(r.inverted_after, 1u);
  EXPECT_NE(r.stop.find("impossible"), std::string::npos) << r.stop;
  EXPECT_FALSE(r.untangled);
}

TEST(Position, HexesSharingTwoFacesAreReportedAsImpossible) {
  // Hex 0 is the unit cube; hex 1 shares its faces x = 0 (0,3,7,4) and y = 0 (0,1,5,4),
  // hence the edge 0-4 and the corners at nodes 0 and 4 with the same three edges, in the
  // opposite orientation: one of the two hexes is inverted there whatever the positions.
  HexMesh mesh;
  mesh.points.resize(10, 3);
  mesh.points << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 0.3, 0.3,
      0, 0.3, 0.3, 1;
  auto hex = [](std::array<int, 8> v) {
    stc::Hex h{};
    for (std::size_t i = 0; i < 8; ++i) h[i] = NodeId(v[i]);
    return h;
  };
  mesh.complex.hexes = {hex({0, 1, 2, 3, 4, 5, 6, 7}), hex({0, 3, 8, 1, 4, 7, 9, 5})};
  mesh.complex.num_nodes = 10;
  // nodes 0 and 4 (the ends of the shared edge) move, so the corners there are not fixed
  const std::vector<bool> fixed = {false, true, true, true, false, true, true, true, false, false};
  const std::vector<ImpossibleCorner> corners = impossible_corners(mesh, fixed);
  ASSERT_FALSE(corners.empty());
  bool pair_named = false;
  for (const ImpossibleCorner& c : corners)
    if (c.hex == HexId(0) && c.other == HexId(1)) pair_named = true;
  EXPECT_TRUE(pair_named);
  PositionOptions options;
  options.fixed = fixed;
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_FALSE(r.impossible.empty());
  EXPECT_FALSE(r.untangled);
  EXPECT_LE(r.outer_iterations, static_cast<std::size_t>(options.max_outer_iterations));
  EXPECT_NE(r.stop.find("impossible"), std::string::npos) << r.stop;
}

TEST(Position, StallRuleStopsEarly) {
  // With one round of one iteration nothing can converge: the report says so.
  HexMesh mesh = test::box_hexes(4, 4, 4);
  PositionOptions options;
  options.fixed = test::boundary_nodes(mesh);
  test::collapse(mesh, options.fixed);
  options.max_outer_iterations = 1;
  options.max_inner_iterations = 1;
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_EQ(r.outer_iterations, 1u);
  EXPECT_LE(r.iterations, 1u);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.stop, "iteration limit");
}

}  // namespace
}  // namespace stcweave::primal

namespace stcweave::primal {
namespace {

TEST(LayerPositions, PutAWovenBoxOnItsGrid) {
  // Every cross completes a parallelepiped, so the layers of a woven box land exactly on the
  // grid (graded spacing included): every hex is a box, scaled Jacobian 1.
  const SurfaceMesh s = test::box_surface(3, 4, 2, 1.0, 0.5, 2.0);
  const weave::WeaveResult woven = weave::weave(s.surface);
  HexMesh mesh = recover_hex_mesh(s.points, woven);
  mesh.points.bottomRows(mesh.points.rows() - s.points.rows()).setZero();
  const std::size_t interior = woven.complex.num_nodes - woven.num_input_nodes;
  EXPECT_EQ(layer_positions(mesh, woven), interior);
  const QualitySummary q = summarize_quality(mesh);
  EXPECT_NEAR(q.min_scaled_jacobian, 1.0, 1e-9);
}

TEST(LayerPositions, RefuseAMeshOfAnotherWeave) {
  const SurfaceMesh s = test::box_surface(2, 2, 2);
  const weave::WeaveResult woven = weave::weave(s.surface);
  HexMesh other = test::box_hexes(3, 3, 3);
  EXPECT_THROW(layer_positions(other, woven), InvalidInput);
}

TEST(Position, NeverReturnsMoreInvertedHexesThanItWasGiven) {
  // The guard at the end of position_nodes: whatever one short round of the optimiser does
  // to a badly scrambled box, at most the hexes inverted before are inverted after.
  for (const std::uint32_t seed : {1U, 2U, 3U, 4U}) {
    HexMesh mesh = test::box_hexes(4, 4, 4);
    const std::vector<bool> fixed = test::boundary_nodes(mesh);
    test::scramble(mesh, fixed, 2.0, seed);
    const QualitySummary before = summarize_quality(mesh);
    PositionOptions o;
    o.fixed = fixed;
    o.max_outer_iterations = 1;
    o.max_inner_iterations = 2;
    const PositionReport r = position_nodes(mesh, o);
    EXPECT_LE(r.inverted_after, before.inverted) << "seed " << seed;
    EXPECT_EQ(summarize_quality(mesh).inverted, r.inverted_after);
  }
}

}  // namespace
}  // namespace stcweave::primal
