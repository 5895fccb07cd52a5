// A geometric selection's side properties on demand (weave/src/select/candidates.hpp): the
// first candidate of `rank_first` against `rank` over every candidate computed, on fronts of
// shapes with and without non-convex edges, and the weave that uses it against the weave with
// an observer attached (which computes every candidate at every selection).

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "driver.hpp"
#include "select/candidates.hpp"
#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/kernel.hpp"
#include "stcweave/weave/select.hpp"
#include "stcweave/weave/weave.hpp"
#include "support/counting_observer.hpp"
#include "support/same_weave.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

struct Shape {
  std::string name;
  primal::SurfaceMesh mesh;
};

/// The k x k x k box's surface pushed onto its circumscribed sphere: no sharp and no
/// non-convex edge, so that the depth filter decides among candidates no earlier filter read.
primal::SurfaceMesh box_sphere(int k) {
  primal::SurfaceMesh s = test::box_surface(k, k, k);
  const Eigen::RowVector3d centre(0.5 * k, 0.5 * k, 0.5 * k);
  for (Eigen::Index n = 0; n < s.points.rows(); ++n) {
    const Eigen::RowVector3d d = s.points.row(n) - centre;
    s.points.row(n) = centre + d.normalized() * k;
  }
  return s;
}

std::vector<Shape> shapes() {
  std::vector<Shape> out;
  out.push_back({"box 6x5x4", test::box_surface(6, 5, 4)});
  out.push_back({"box 7x2x6", test::box_surface(7, 2, 6)});
  out.push_back({"l-block", test::voxel_surface(test::lblock_cells())});
  out.push_back({"rhombic dodecahedron", test::rhombic_dodecahedron()});
  out.push_back({"sphere 4x4x4", box_sphere(4)});
  out.push_back({"sphere 5x5x5", box_sphere(5)});
  out.push_back({"ogrid cylinder",
                 test::boundary_of(test::extruded_hexes(test::ogrid_disk(), {0.0, 0.5, 1.0}))});
  // U-shaped voxels: non-convex edges on two sides.
  out.push_back({"u-block", test::voxel_surface({{0, 0, 0},
                                                 {1, 0, 0},
                                                 {2, 0, 0},
                                                 {0, 1, 0},
                                                 {2, 1, 0},
                                                 {0, 2, 0},
                                                 {2, 2, 0},
                                                 {0, 0, 1},
                                                 {1, 0, 1},
                                                 {2, 0, 1}})});
  return out;
}

void expect_same_candidate(const TraceCandidate& a, const TraceCandidate& b,
                           const std::string& where) {
  EXPECT_EQ(a.loop, b.loop) << where;
  EXPECT_EQ(a.side, b.side) << where;
  EXPECT_EQ(a.length, b.length) << where;
  EXPECT_EQ(a.strictly_on_side, b.strictly_on_side) << where;
  EXPECT_EQ(a.on_strip, b.on_strip) << where;
  EXPECT_EQ(a.weight, b.weight) << where;
  EXPECT_EQ(a.self_intersecting, b.self_intersecting) << where;
  EXPECT_EQ(a.faces_collapsed, b.faces_collapsed) << where;
  EXPECT_EQ(a.depth, b.depth) << where;
  EXPECT_EQ(a.crossed_sharp, b.crossed_sharp) << where;
  EXPECT_EQ(a.side_sharp, b.side_sharp) << where;
  EXPECT_EQ(a.nonconvex_on_side, b.nonconvex_on_side) << where;
  EXPECT_EQ(a.parallel_to, b.parallel_to) << where;
}

/// The input front of `s` with `extended` rules and parameters `par`, its angles measured.
WeaveState input_front(const Shape& s, const ExtendedParameters& par) {
  WeaveOptions options;
  options.rules = RuleSet::Extended;
  options.extended = par;
  return initial_state(s.mesh.surface, options, primal::dihedral_angles(s.mesh));
}

/// `rank_first` on the front of `state` against `rank` of every candidate; the number of
/// loops left incomplete. `full_out`, when given, receives `rank`'s ranking.
std::size_t compare_on(const WeaveState& state, const Selection& selection,
                       const ExtendedParameters& par, const std::string& where,
                       Ranking* full_out = nullptr) {
  Marks nodes, faces, faces2;
  const FrontLoops loops = front_loops(state.front);
  const FrontComponents components = front_components(state.front, nodes);
  // `rank_first` first: `loop_candidates` floods every loop, and the sides it keeps
  // (SideCache) would then complete every loop cheaply.
  CandidateSet set(state.front, loops, components, par, nodes, faces, faces2, /*check=*/true);
  const Ranking first = rank_first(selection, set);
  const Ranking full = rank(
      selection, loop_candidates(state.front, loops, components, true, par, nodes, faces, faces2));
  if (full_out != nullptr) *full_out = full;
  EXPECT_EQ(first.order.size(), full.order.size()) << where;
  if (first.order.empty() || full.order.empty()) return 0;
  expect_same_candidate(first.order.front(), full.order.front(), where);
  EXPECT_EQ(first.reason, full.reason) << where;
  EXPECT_EQ(first.decided_by, full.decided_by) << where;
  EXPECT_EQ(first.filters, full.filters) << where;
  std::size_t incomplete = 0;
  for (std::size_t l = 0; l < loops.strips.size(); ++l)
    if (set.known(static_cast<std::int32_t>(l)) != side_property::kAll) ++incomplete;
  return incomplete;
}

TEST(Candidates, FirstOfRankFirstIsFirstOfRankOnInputFronts) {
  ExtendedParameters par;
  const Selection selection = extended_selection(par);
  std::size_t incomplete = 0;
  for (const Shape& s : shapes()) {
    WeaveOptions options;
    options.rules = RuleSet::Extended;
    const WeaveState state =
        initial_state(s.mesh.surface, options, primal::dihedral_angles(s.mesh));
    incomplete += compare_on(state, selection, par, s.name);
  }
  // The point of it: on these fronts most loops are decided by their strips alone.
  EXPECT_GT(incomplete, 0U) << "every loop was flooded: nothing was saved";
}

TEST(Candidates, TheNonConvexRelaxationComparesExactCountsOnInputFronts) {
  // Every edge non-convex (flat below 90 degrees): no side is free of them, and the
  // non-convex filter keeps the sides with the fewest. The side parities only know "at least
  // one", so rank_first must flood those sides before it compares; `compare_on` checks that
  // its choice, reason and filters are rank's.
  ExtendedParameters par;
  par.sharp = 20;
  par.little_sharp = 40;
  par.flat = 60;
  par.little_sharp_nonconvex = 80;
  const Selection selection = extended_selection(par);
  std::size_t relaxed_to_least = 0;
  for (const Shape& s : shapes()) {
    Ranking full;
    (void)compare_on(input_front(s, par), selection, par, s.name, &full);
    for (const std::string& f : full.filters)
      if (f.rfind("nonconvex:", 0) == 0 && f.find("->least:") != std::string::npos)
        ++relaxed_to_least;
  }
  EXPECT_GT(relaxed_to_least, 0U) << "the relaxation never ran: the test shows nothing";
}

TEST(Candidates, TheFewestFacesOrderFloodsOnlyUpToTheBest) {
  // No depth filter (the weave's first pass) and fronts with no sharp edge (box-spheres):
  // most candidates reach the order by fewest faces collapsed. With
  // `order_fewest_faces_first` the sides are flooded only up to the best found, so loops
  // are left incomplete; without it every candidate left is completed; the first is rank's
  // either way (compare_on).
  ExtendedParameters par;
  par.depth_filter = false;
  const Selection bounded = extended_selection(par);
  ASSERT_TRUE(bounded.order_fewest_faces_first);
  Selection complete = bounded;
  complete.order_fewest_faces_first = false;
  // (Small spheres would show nothing: every loop of a 5x5x5 one has a side within the best.)
  std::size_t checked = 0;
  for (const Shape& s :
       {Shape{"sphere 8x8x8", box_sphere(8)}, Shape{"sphere 10x10x10", box_sphere(10)}}) {
    const WeaveState state = input_front(s, par);
    Ranking full;
    const std::size_t left = compare_on(state, bounded, par, s.name + " (bounded)", &full);
    const std::size_t none = compare_on(state, complete, par, s.name + " (complete)");
    if (full.filters.back().rfind("topological:", 0) == 0) {
      ++checked;
      EXPECT_GT(left, none) << s.name << ": the bounded order flooded every loop the other did";
    }
  }
  EXPECT_GT(checked, 0U) << "no front reached the order by fewest faces";
}

TEST(Candidates, AFilterThatDeclaresNothingSeesEveryCandidateComplete) {
  // A user's filter without `reads` may read anything: every candidate it sees is completed
  // first, and the choice is rank's.
  ExtendedParameters par;
  Selection selection = extended_selection(par);
  Filter weight;
  weight.name = "lightest";
  weight.kind = Filter::Kind::Least;
  weight.cost = [](const TraceCandidate& c) { return static_cast<double>(c.weight); };
  selection.filters.insert(selection.filters.begin(), weight);
  const Shape box{"box 6x5x4", test::box_surface(6, 5, 4)};
  WeaveOptions options;
  options.rules = RuleSet::Extended;
  const WeaveState state =
      initial_state(box.mesh.surface, options, primal::dihedral_angles(box.mesh));
  EXPECT_EQ(compare_on(state, selection, par, "lightest first"), 0U)
      << "a filter that declares nothing read an incomplete candidate";
}

TEST(Candidates, TheWeaveChoosesAsWithEveryCandidateComputed) {
  for (const Shape& s : shapes()) {
    for (const bool merging : {true, false}) {
      const std::string where = s.name + (merging ? "" : " (no parallel merging)");
      const auto angles = primal::dihedral_angles(s.mesh);
      WeaveOptions lazy;
      lazy.rules = RuleSet::Extended;
      lazy.extended.parallel_merging = merging;
      lazy.check = true;  // the driver compares with the full ranking at every selection
      WeaveResult a;
      ASSERT_NO_THROW(a = weave(s.mesh.surface, lazy, angles)) << where;
      test::CountingObserver counting;
      WeaveOptions full = lazy;
      full.observer = &counting;
      const WeaveResult b = weave(s.mesh.surface, full, angles);
      test::expect_same_weave(a, b, where);
      EXPECT_GT(counting.selections, 1U) << where << ": more than one selection to compare";
    }
  }
}

}  // namespace
}  // namespace stcweave::weave
