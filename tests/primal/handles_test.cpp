#include "stcweave/primal/handles.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "stcweave/primal/cut.hpp"
#include "stcweave/primal/diagnose.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

using test::file_of;

/// The cross-section index j of torus node v (torus_surface numbers nodes j * around + i).
std::set<int> sections(const HandleCycle& c, int around) {
  std::set<int> js;
  for (NodeId v : c.nodes) js.insert(v.value() / around);
  return js;
}

TEST(Handles, TorusMeridianIsFoundEvenWhenTheLongitudeIsShorter) {
  // 10 quads round the tube, 6 along it: the shortest non-trivial cycle is a longitude (6
  // edges), but only the meridian (10 edges) bounds inside the solid.
  const SurfaceMesh torus = test::torus_surface(10, 6, 3.0, 1.0);
  const HandleDiagnosis h = diagnose_handles(torus);
  ASSERT_TRUE(h.decided) << h.undecided_reason;
  EXPECT_EQ(h.genus, 1);
  ASSERT_EQ(h.handles.size(), 1u);
  EXPECT_EQ(h.handles[0].length(), 10u);
  EXPECT_EQ(sections(h.handles[0], 10).size(), 1u);  // one cross-section: a meridian
  EXPECT_TRUE(h.all_even());
}

TEST(Handles, TheAlternativesOfATorusMeridianAreOtherMeridians) {
  // Each root keeps the shortest cycle nearest it, so the alternatives are meridians at other
  // cross-sections (before, every root kept the meridian of the smallest edge ids).
  const SurfaceMesh torus = test::torus_surface(8, 12, 3.0, 1.0);
  const HandleDiagnosis h = diagnose_handles(torus);
  ASSERT_TRUE(h.decided) << h.undecided_reason;
  ASSERT_EQ(h.handles.size(), 1u);
  ASSERT_EQ(h.alternatives.size(), 1u);
  ASSERT_GE(h.alternatives[0].size(), 2u);
  std::set<int> all{*sections(h.handles[0], 8).begin()};
  for (const HandleCycle& alt : h.alternatives[0]) {
    EXPECT_EQ(alt.length(), 8u);
    const std::set<int> js = sections(alt, 8);
    ASSERT_EQ(js.size(), 1u);  // a meridian
    EXPECT_TRUE(all.insert(*js.begin()).second) << "cross-section " << *js.begin() << " twice";
  }
}

TEST(Handles, SquareRingHandleIsTheFourEdgeSection) {
  const HandleDiagnosis h = diagnose_handles(test::voxel_surface(test::ring_cells()));
  ASSERT_TRUE(h.decided) << h.undecided_reason;
  ASSERT_EQ(h.handles.size(), 1u);
  EXPECT_EQ(h.handles[0].length(), 4u);
  EXPECT_TRUE(h.all_even());
}

TEST(Handles, DoubleRingHasTwoFourEdgeHandles) {
  // 3 x 5 x 1 slab minus cells (1,1) and (1,3): genus 2.
  std::vector<std::array<int, 3>> cells;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 3; ++i)
      if (!(i == 1 && (j == 1 || j == 3))) cells.push_back({i, j, 0});
  const HandleDiagnosis h = diagnose_handles(test::voxel_surface(cells));
  ASSERT_TRUE(h.decided) << h.undecided_reason;
  EXPECT_EQ(h.genus, 2);
  ASSERT_EQ(h.handles.size(), 2u);
  EXPECT_EQ(h.handles[0].length(), 4u);
  EXPECT_EQ(h.handles[1].length(), 4u);
}

TEST(Handles, LinkedToriEachGetTheirMeridian) {
  // Two linked tori (each core runs through the other's hole): linking across components
  // matters, and each handle is still the meridian of its own tube.
  const SurfaceMesh a = test::torus_surface(10, 6, 3.0, 1.0);
  SurfaceMesh b = a;
  for (Eigen::Index r = 0; r < b.points.rows(); ++r) {
    const Eigen::RowVector3d p = a.points.row(r);
    b.points.row(r) = Eigen::RowVector3d(p.x() + 3.0, p.z(), p.y());
  }
  // The coordinate swap mirrors b: reverse it back outward.
  b = test::reversed_surface(b);
  const SurfaceMesh both = test::merged_surfaces({a, b});
  const HandleDiagnosis h = diagnose_handles(both);
  ASSERT_TRUE(h.decided) << h.undecided_reason;
  EXPECT_EQ(h.genus, 2);
  ASSERT_EQ(h.handles.size(), 2u);
  std::set<int> components;
  for (const HandleCycle& c : h.handles) {
    EXPECT_EQ(c.length(), 10u);
    components.insert(c.component.value());
  }
  EXPECT_EQ(components.size(), 2u);
}

TEST(Handles, TriangularTorusIsRefusedNamingItsOddCycle) {
  // 3 quads round, 8 along: 24 quads (even), no self-intersecting loop, but the meridian
  // has 3 edges and bounds a disc inside: no hex mesh exists.
  const MeshFile file = file_of(test::torus_surface(3, 8, 3.0, 1.0), "tri-torus.obj");
  const SurfaceDiagnosis d = diagnose(file);
  EXPECT_EQ(d.quads, 24u);
  EXPECT_EQ(d.self_intersecting_loops, 0u);
  ASSERT_TRUE(d.handles);
  ASSERT_TRUE(d.handles->decided) << d.handles->undecided_reason;
  ASSERT_EQ(d.handles->odd_handle, 0);
  EXPECT_EQ(d.handles->handles[0].length(), 3u);
  try {
    require_weavable(d);
    FAIL() << "expected TopologyError";
  } catch (const TopologyError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no hex mesh with this boundary exists"), std::string::npos) << what;
    EXPECT_NE(what.find("has 3 edges"), std::string::npos) << what;
    EXPECT_NE(what.find(cycle_name(d.handles->handles[0])), std::string::npos) << what;
    EXPECT_NE(what.find("tri-torus.obj"), std::string::npos) << what;
  }
  EXPECT_EQ(to_json(d)["handles"]["all_even"], false);
}

TEST(Handles, TheCutRefusesAnOddHandleCycleNamingIt) {
  // The pipeline refuses it in the diagnosis first; called alone, the handle route must too.
  const SurfaceMesh torus = test::torus_surface(3, 8, 3.0, 1.0);
  try {
    (void)weave_solids(torus, weave::WeaveOptions{});
    FAIL() << "expected TopologyError";
  } catch (const TopologyError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("the cycle n"), std::string::npos) << what;
    EXPECT_NE(what.find("(3 edges)"), std::string::npos) << what;
    EXPECT_NE(what.find("no hex mesh with this boundary exists"), std::string::npos) << what;
  }
}

TEST(Handles, InwardInputIsOrientedBeforeTheDiagnosis) {
  const SurfaceMesh inward = test::reversed_surface(test::torus_surface(10, 6, 3.0, 1.0));
  const SurfaceDiagnosis d = diagnose(file_of(inward, "inward"));
  ASSERT_TRUE(d.handles);
  ASSERT_EQ(d.handles->handles.size(), 1u);
  EXPECT_EQ(d.handles->handles[0].length(), 10u);
  EXPECT_NO_THROW(require_weavable(d));
}

TEST(Handles, GenusZeroHasNoHandleDiagnosis) {
  const SurfaceDiagnosis d = diagnose(file_of(test::box_surface(2, 2, 2), "box"));
  EXPECT_FALSE(d.handles);
  const HandleDiagnosis h = diagnose_handles(test::box_surface(2, 2, 2));
  EXPECT_TRUE(h.decided);
  EXPECT_TRUE(h.handles.empty());
}

}  // namespace
}  // namespace stcweave::primal

namespace stcweave::primal {
namespace {

TEST(Handles, FoldedFanAtTheTreeRootIsUndecided) {
  // Node 0 (the root of the homology basis' tree, so on its cycles) pulled through the tube
  // to the far side: its quads face opposite ways and no push-off direction exists there.
  SurfaceMesh torus = test::torus_surface(4, 6, 3.0, 1.0);
  torus.points.row(0) = Eigen::RowVector3d(3.0 - 1.5, 0.0, 0.0);
  const HandleDiagnosis h = diagnose_handles(torus);
  EXPECT_FALSE(h.decided);
  EXPECT_NE(h.undecided_reason.find("face too many ways"), std::string::npos) << h.undecided_reason;
  EXPECT_FALSE(h.all_even());
}

HandleCycle cycle_of(std::initializer_list<int> ids) {
  HandleCycle c;
  for (const int v : ids) c.nodes.emplace_back(v);
  return c;
}

// Handle cycles that touch (two handles meeting at a junction, as skel2016_fertility's): the
// later one is replaced by the first of its alternatives that touches none chosen before;
// disjoint cycles are kept as they are; no disjoint choice gives an empty set.
TEST(DisjointHandleCycles, TouchingCyclesTakeAnAlternativeOfTheirClass) {
  HandleDiagnosis d;
  d.decided = true;
  d.handles = {cycle_of({0, 1, 2, 3}), cycle_of({3, 4, 5, 6})};
  d.alternatives = {{cycle_of({20, 21, 22, 23})},
                    {cycle_of({2, 7, 8, 9}), cycle_of({10, 11, 12, 13})}};
  const std::vector<std::vector<NodeId>> chosen = disjoint_handle_cycles(d, 30);
  ASSERT_EQ(chosen.size(), 2u);
  EXPECT_EQ(chosen[0], d.handles[0].nodes);
  EXPECT_EQ(chosen[1], d.alternatives[1][1].nodes);

  d.handles[1] = cycle_of({14, 15, 16, 17});
  const std::vector<std::vector<NodeId>> kept = disjoint_handle_cycles(d, 30);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[0], d.handles[0].nodes);
  EXPECT_EQ(kept[1], d.handles[1].nodes);

  // The first handle's alternative frees the second one's own cycle (backtracking).
  d.handles[1] = cycle_of({3, 4, 5, 6});
  d.alternatives[1] = {cycle_of({1, 7, 8, 9})};
  const std::vector<std::vector<NodeId>> back = disjoint_handle_cycles(d, 30);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0], d.alternatives[0][0].nodes);
  EXPECT_EQ(back[1], d.handles[1].nodes);

  d.alternatives[0].clear();
  EXPECT_TRUE(disjoint_handle_cycles(d, 30).empty());
}

}  // namespace
}  // namespace stcweave::primal
