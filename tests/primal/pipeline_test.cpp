#include "stcweave/primal/pipeline.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "stcweave/primal/beside.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/hex_stc.hpp"
#include "stcweave/stc/surface_topology.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

using test::file_of;

TEST(Pipeline, LBlockGivesItsTenStructuredHexes) {
  const MeshResult r = mesh_file(file_of(test::voxel_surface(test::lblock_cells()), "lblock"));
  EXPECT_EQ(r.mesh.complex.hexes.size(), 10u);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_NEAR(r.quality.min_scaled_jacobian, 1.0, 1e-12);
}

TEST(Pipeline, TenCubedBoxIsStructuredWithExactInteriorNodes) {
  const MeshResult r = mesh_file(file_of(test::box_surface(10, 10, 10), "box10"));
  EXPECT_EQ(r.mesh.complex.hexes.size(), 1000u);
  EXPECT_EQ(r.mesh.complex.num_nodes - r.woven.num_input_nodes, 729u);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  // the harmonic position of a uniform grid is the grid itself
  EXPECT_NEAR(r.quality.min_scaled_jacobian, 1.0, 1e-6);
}

TEST(Pipeline, InputNodesKeepTheirIdsAndCoordinates) {
  const SurfaceMesh box = test::box_surface(3, 2, 2);
  const MeshResult r = mesh_file(file_of(box, "box"));
  ASSERT_GE(r.mesh.points.rows(), box.points.rows());
  EXPECT_TRUE(r.mesh.points.topRows(box.points.rows()).isApprox(box.points, 0.0));
}

TEST(Pipeline, InwardSurfaceIsReorientedAndMeshed) {
  const SurfaceMesh inward = test::reversed_surface(test::box_surface(2, 3, 4));
  const MeshResult r = mesh_file(file_of(inward, "inward"));
  EXPECT_EQ(r.orientation.flipped_quads, inward.surface.quads.size());
  EXPECT_EQ(r.mesh.complex.hexes.size(), 24u);
  EXPECT_EQ(r.quality.inverted, 0u);
}

TEST(Pipeline, SeedFigure5BarsAreValid) {
  const std::vector<std::vector<std::array<int, 3>>> bars = {
      {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}},  // straight: 3 hexes
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}},  // bent in a plane (L)
      {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}},  // bent upward
  };
  for (const auto& cells : bars) {
    const SurfaceMesh s = test::voxel_surface(cells);
    ASSERT_EQ(s.surface.quads.size(), 14u);
    const MeshResult r = mesh_file(file_of(s, "bar"));
    EXPECT_TRUE(r.validation.valid) << r.validation.summary();
    EXPECT_EQ(r.mesh.complex.hexes.size(), 3u);
  }
}

TEST(Pipeline, TwoDisjointShellsAreBothMeshed) {
  const SurfaceMesh a = test::box_surface(1, 1, 1);
  SurfaceMesh both = a;
  both.points.conservativeResize(16, 3);
  both.points.bottomRows(8) = a.points.rowwise() + Eigen::RowVector3d(5, 0, 0);
  for (auto q : a.surface.quads) {
    for (auto& n : q) n = NodeId(n.value() + 8);
    both.surface.quads.push_back(q);
  }
  both.surface.num_nodes = 16;
  const MeshResult r = mesh_file(file_of(both, "two cubes"));
  EXPECT_EQ(r.mesh.complex.hexes.size(), 2u);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
}

TEST(Pipeline, SquareRingIsCutAndGluedIntoItsEightHexes) {
  // 3x3x1 block minus the centre column: 32 quads, genus 1; the handle cycle is a 4-edge
  // section, its disc one quad, the cut ball a bent 1x1x8 bar.
  const SurfaceMesh ring = test::voxel_surface(test::ring_cells());
  ASSERT_EQ(ring.surface.quads.size(), 32u);
  const MeshResult r = mesh_file(file_of(ring, "ring.obj"));
  EXPECT_EQ(r.mesh.complex.hexes.size(), 8u);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_TRUE(r.validation.boundary_compared);
  EXPECT_EQ(r.quality.inverted, 0u);
  ASSERT_EQ(r.solids.cuts.size(), 1u);
  EXPECT_EQ(r.solids.cuts[0].cycle.size(), 4u);
  EXPECT_EQ(r.solids.cuts[0].grid_a * r.solids.cuts[0].grid_b, 1);
}

TEST(Pipeline, DoubleRingGetsTwoCutsAndAValidComplex) {
  std::vector<std::array<int, 3>> cells;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 3; ++i)
      if (!(i == 1 && (j == 1 || j == 3))) cells.push_back({i, j, 0});
  const MeshResult r = mesh_file(file_of(test::voxel_surface(cells), "double-ring"));
  EXPECT_EQ(r.solids.cuts.size(), 2u);
  EXPECT_EQ(r.mesh.complex.hexes.size(), 13u);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.quality.inverted, 0u);
}

TEST(Pipeline, TorusWithEvenSectionGivesAValidComplex) {
  // 8 quads round the tube, 12 along: the disc is a grid spanning an 8-edge meridian.
  const MeshResult r = mesh_file(file_of(test::torus_surface(8, 12, 3.0, 1.0), "torus"));
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_GT(r.mesh.complex.hexes.size(), 0u);
  EXPECT_EQ(r.quality.inverted, 0u);
  ASSERT_EQ(r.solids.cuts.size(), 1u);
  EXPECT_EQ(r.solids.cuts[0].cycle.size(), 8u);
}

TEST(Pipeline, TriangularTorusIsRefusedAsImpossible) {
  try {
    (void)mesh_file(file_of(test::torus_surface(3, 8, 3.0, 1.0), "tri-torus.obj"));
    FAIL() << "expected TopologyError";
  } catch (const TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("no hex mesh with this boundary exists"),
              std::string::npos)
        << e.what();
  }
}

TEST(Pipeline, DisjointSolidsAreWovenSeparatelyAndCombined) {
  // A ring beside a 2x2x2 box: two solids, one with a handle.
  const SurfaceMesh ring = test::voxel_surface(test::ring_cells());
  const SurfaceMesh box = test::translated(test::box_surface(2, 2, 2), {10.0, 0.0, 0.0});
  const MeshResult r = mesh_file(file_of(test::merged_surfaces({ring, box}), "two solids"));
  EXPECT_EQ(r.solids.solids, 2u);
  EXPECT_EQ(r.mesh.complex.hexes.size(), 16u);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.quality.inverted, 0u);
  // Each shrink keeps its own record: the two solids' shrinks are numbered apart.
  const auto ring_nodes = static_cast<std::size_t>(ring.points.rows());
  std::set<std::int32_t> ring_shrinks, box_shrinks, recorded;
  for (const weave::ShrinkRecord& rec : r.woven.shrinks) recorded.insert(rec.shrink);
  EXPECT_EQ(recorded.size(), r.woven.shrinks.size());
  ASSERT_EQ(r.woven.hex_shrink.size(), r.woven.complex.hexes.size());
  for (std::size_t h = 0; h < r.woven.complex.hexes.size(); ++h) {
    const std::int32_t sh = r.woven.hex_shrink[h];
    if (sh < 0) continue;
    EXPECT_TRUE(recorded.contains(sh)) << "hex " << h << ": shrink " << sh << " has no record";
    const bool in_ring =
        std::any_of(r.woven.complex.hexes[h].begin(), r.woven.complex.hexes[h].end(),
                    [&](NodeId v) { return v.index() < ring_nodes; });
    (in_ring ? ring_shrinks : box_shrinks).insert(sh);
  }
  EXPECT_FALSE(ring_shrinks.empty());
  EXPECT_FALSE(box_shrinks.empty());
  for (std::int32_t sh : box_shrinks) EXPECT_FALSE(ring_shrinks.contains(sh)) << sh;
}

TEST(Pipeline, HollowBoxIsMeshedThroughAnAnnulusCut) {
  const SurfaceMesh outer = test::box_surface(3, 3, 3);
  const SurfaceMesh inner = test::box_surface(1, 1, 1);
  SurfaceMesh both = outer;
  const auto n0 = outer.points.rows();
  both.points.conservativeResize(n0 + 8, 3);
  both.points.bottomRows(8) = inner.points.rowwise() + Eigen::RowVector3d(1, 1, 1);
  for (auto q : inner.surface.quads) {
    q = stc::reversed(q);  // a cavity faces the material
    for (auto& n : q) n = NodeId(n.value() + static_cast<int>(n0));
    both.surface.quads.push_back(q);
  }
  both.surface.num_nodes = static_cast<std::size_t>(n0 + 8);
  const MeshResult r = mesh_file(file_of(both, "hollow"));
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_TRUE(r.validation.boundary_compared);
  EXPECT_EQ(r.solids.solids, 1u);
  EXPECT_EQ(r.solids.cuts.size(), 1u);
  EXPECT_EQ(r.quality.inverted, 0u);
}

TEST(Pipeline, OddQuadCountIsATopologyError) {
  auto cube = test::box_surface(1, 1, 1);
  cube.surface.quads.pop_back();  // open and odd
  EXPECT_THROW((void)mesh_file(file_of(cube, "open")), TopologyError);
}

TEST(Pipeline, CheckModeKeepsTheFrontValidOnTheRhombicDodecahedron) {
  MeshOptions options;
  options.weave.check = true;
  const MeshResult r = mesh_file(file_of(test::rhombic_dodecahedron(), "rd"), options);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.mesh.complex.hexes.size(), 4u);
}
}  // namespace
}  // namespace stcweave::primal

namespace stcweave::primal {
namespace {

TEST(Pipeline, HandlesAndACavityTogetherAreMeshed) {
  // A torus (tube radius 1) with a small cubic cavity inside its tube: a hex joining the
  // cavity to the outer shell is put on the front of the ball the handle's cut leaves.
  const SurfaceMesh torus = test::torus_surface(8, 12, 3.0, 1.0);
  SurfaceMesh cavity = test::box_surface(1, 1, 1, 0.4, 0.4, 0.4);
  cavity = test::reversed_surface(test::translated(cavity, {2.8, -0.2, -0.2}));
  const SurfaceMesh input = test::merged_surfaces({torus, cavity});
  const MeshResult r = mesh_file(file_of(input, "torus with cavity"));
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_TRUE(r.validation.boundary_compared);
  EXPECT_EQ(r.solids.solids, 1u);
  // One column hex for the cavity, one disc for the handle.
  ASSERT_EQ(r.solids.cuts.size(), 2u);
  EXPECT_EQ(r.solids.cuts[0].disc, "column hex");
  EXPECT_EQ(r.quality.inverted, 0u);
  // The column's fixed corners join the two shells: both are pillowed (with the cavity's
  // alone, 4 hexes stayed inverted).
  EXPECT_EQ(r.pillow.shells_pillowed, 2u) << r.pillow.reason;
  std::cout << "torus with a cavity (" << input.surface.quads.size()
            << " quads): " << r.mesh.complex.hexes.size() << " hexes, min scaled Jacobian "
            << r.quality.min_scaled_jacobian << ", handle disc " << r.solids.cuts[1].disc << "\n";
}

TEST(Pipeline, AVoxelRingWithACavityIsMeshed) {
  // A 7 x 7 x 3 block without its centre column (a handle) and without cell (1, 1, 1) (a
  // cavity): 143 cells.
  std::vector<std::array<int, 3>> cells;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 7; ++i)
        if ((i != 3 || j != 3) && (i != 1 || j != 1 || k != 1)) cells.push_back({i, j, k});
  const SurfaceMesh input = test::voxel_surface(cells);
  const MeshResult r = mesh_file(file_of(input, "ring with cavity"));
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_TRUE(r.validation.boundary_compared);
  ASSERT_EQ(r.solids.cuts.size(), 2u);
  EXPECT_EQ(r.solids.cuts[0].disc, "column hex");
  EXPECT_EQ(r.quality.inverted, 0u);
  std::cout << "voxel ring with a cavity (" << input.surface.quads.size()
            << " quads): " << r.mesh.complex.hexes.size() << " hexes (143 voxels), min scaled "
            << "Jacobian " << r.quality.min_scaled_jacobian << "\n";
}

/// The n x n x n cube of unit cells with an m x m x m cubic cavity whose corner is at
/// (at, at, at).
SurfaceMesh hollow_cube(int n, int m, double at) {
  return test::merged_surfaces(
      {test::box_surface(n, n, n),
       test::reversed_surface(test::translated(test::box_surface(m, m, m), {at, at, at}))});
}

TEST(Pipeline, HollowCubesWhoseCavityIsWiderThanACellAreMeshed) {
  // Cut off along the annulus between a cavity quad and the nearest outer quad, these solids
  // glued back into a face of three hexes: the joined shell's weave filled the column's place
  // with hexes of its own. The column attached to the front of the uncut solid instead (as
  // with handles) gives a valid complex.
  // (Without the untangling: these check the complex; the thin one's positioning takes a
  // minute on its inverted hexes.)
  MeshOptions topology_only;
  topology_only.untangle = false;
  for (const auto& [n, m, at] : {std::tuple{6, 2, 2.0}, std::tuple{4, 2, 1.0}}) {
    const std::string name =
        "hollow cube " + std::to_string(n) + " with cavity " + std::to_string(m);
    const MeshResult r = mesh_file(file_of(hollow_cube(n, m, at), name), topology_only);
    EXPECT_TRUE(r.validation.valid) << name << ": " << r.validation.summary();
    EXPECT_TRUE(r.validation.boundary_compared) << name;
    EXPECT_EQ(r.solids.solids, 1u) << name;
    ASSERT_EQ(r.solids.cuts.size(), 1u) << name;
    EXPECT_EQ(r.solids.cuts[0].disc, "column hex") << name;
    std::cout << name << ": " << r.mesh.complex.hexes.size() << " hexes\n";
  }
  // Positioned: the thick one (a shell two cells thick) has none inverted; the thin one keeps
  // 4 (measured; docs/topology.md "Several shells").
  const MeshResult thick = mesh_file(file_of(hollow_cube(6, 2, 2.0), "thick"));
  EXPECT_EQ(thick.quality.inverted, 0u);
  std::cout << "positioned, the thick one: min scaled Jacobian "
            << thick.quality.min_scaled_jacobian << "\n";
}

TEST(Pipeline, AHollowSolidBothOfWhoseRoutesBlockIsRefusedNamingBoth) {
  // With a rule budget too small for any weave, the cavity cut off and the column attached
  // both block: a WeaveError (exit code 3) naming the two routes, no mesh.
  MeshOptions starved;
  starved.weave.max_rules = 5;
  starved.untangle = false;
  try {
    (void)mesh_file(file_of(hollow_cube(6, 2, 2.0), "starved hollow cube"), starved);
    ADD_FAILURE() << "a weave of 5 rules meshed a hollow cube";
  } catch (const WeaveError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cavities cut off along annuli, their weave blocks"), std::string::npos)
        << what;
    EXPECT_NE(what.find("with the column hexes attached to the front its weave blocks"),
              std::string::npos)
        << what;
  }
}

TEST(Pipeline, ASolidInsideACavityIsMeshedOnItsOwn) {
  // A 6 x 6 x 6 cube with a 4 x 4 x 4 cavity, a unit cube floating in the cavity (nesting
  // depth 2) and a second one: three solids' shells and one cavity, woven as two solids.
  const SurfaceMesh hollow = hollow_cube(6, 4, 1.0);
  const SurfaceMesh input =
      test::merged_surfaces({hollow, test::translated(test::box_surface(1, 1, 1), {1.5, 1.5, 1.5}),
                             test::translated(test::box_surface(1, 1, 1), {3.5, 3.5, 3.5})});
  MeshOptions topology_only;  // (the complex is what counts here)
  topology_only.untangle = false;
  const MeshResult r = mesh_file(file_of(input, "cubes in a hollow cube"), topology_only);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_TRUE(r.validation.boundary_compared);
  EXPECT_EQ(r.orientation.nesting_depth, (std::vector<int>{0, 1, 2, 2}));
  EXPECT_EQ(r.solids.solids, 3u);
  // The two floating cubes are one hex each: two hexes on their 16 nodes alone (merged after
  // the hollow cube's nodes), none elsewhere on them.
  const std::size_t first = hollow.surface.num_nodes;
  const std::size_t last = input.surface.num_nodes;
  std::size_t on_cubes = 0;
  for (const stc::Hex& h : r.mesh.complex.hexes) {
    std::size_t in = 0;
    for (const NodeId v : h) in += v.index() >= first && v.index() < last ? 1 : 0;
    EXPECT_TRUE(in == 0 || in == 8) << "a hex joins a floating cube to something else";
    on_cubes += in == 8 ? 1 : 0;
  }
  EXPECT_EQ(on_cubes, 2u);
}

/// The cells of a 7 x 7 x 3 block without its centre column (a hole through it) and without
/// the ring of 16 cells at distance 2 from that column in the middle layer (a cavity around
/// the hole): a solid with a handle whose cavity has one too, 128 cells.
std::vector<std::array<int, 3>> hollow_ring_cells() {
  std::vector<std::array<int, 3>> cells;
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 7; ++j) {
      for (int i = 0; i < 7; ++i) {
        const int ring = std::max(std::abs(i - 3), std::abs(j - 3));
        if (ring == 0 || (k == 1 && ring == 2)) continue;
        cells.push_back({i, j, k});
      }
    }
  }
  return cells;
}

TEST(Pipeline, ACavityWithAHandleIsRefusedAsUnsupported) {
  // Its handle classes would cross the hex joining the cavity to the outer shell twice; no
  // set of disjoint simple cycles spans them (docs/topology.md).
  const SurfaceMesh input = test::voxel_surface(hollow_ring_cells());
  const stc::SurfaceTopology topo = stc::surface_topology(input.surface);
  ASSERT_EQ(topo.components.size(), 2u);
  ASSERT_EQ(topo.components[0].genus.value_or(-1), 1);
  ASSERT_EQ(topo.components[1].genus.value_or(-1), 1);
  try {
    (void)mesh_file(file_of(input, "hollow ring"));
    FAIL() << "expected Unsupported";
  } catch (const Unsupported& e) {
    EXPECT_NE(std::string(e.what()).find("a cavity with handles"), std::string::npos) << e.what();
  }
}

TEST(Pipeline, UndecidedHandlesAreRefused) {
  SurfaceMesh torus = test::torus_surface(4, 6, 3.0, 1.0);
  torus.points.row(0) = Eigen::RowVector3d(3.0 - 1.5, 0.0, 0.0);
  try {
    (void)mesh_file(file_of(torus, "folded"));
    FAIL() << "expected Unsupported";
  } catch (const Unsupported& e) {
    EXPECT_NE(std::string(e.what()).find("cannot tell which cycles bound inside"),
              std::string::npos)
        << e.what();
  }
}

// Per hex, its three sheets and chords (what the cell data and the report read of the STC).
std::vector<std::array<std::int32_t, 6>> stc_of_hexes(const stc::HexStc& stc) {
  std::vector<std::array<std::int32_t, 6>> out;
  for (const stc::StcVertex& v : stc.vertices) {
    out.push_back({v.sheets[0].value(), v.sheets[1].value(), v.sheets[2].value(),
                   v.chords[0].value(), v.chords[1].value(), v.chords[2].value()});
  }
  return out;
}

// With a second thread the pipeline validates beside the harmonic placement (finding the
// pinched face pairs there too) and builds the STC beside the positioning; nothing but the
// seconds may change. (On a machine with one hardware thread both runs are sequential.)
TEST(Pipeline, StagesSideBySideGiveTheSequentialResult) {
  const std::vector<std::pair<std::string, SurfaceMesh>> inputs = {
      {"lblock", test::voxel_surface(test::lblock_cells())},
      {"box 5x4x3", test::box_surface(5, 4, 3)},
      {"rhombic dodecahedron", test::rhombic_dodecahedron()},
      {"triangle-split box", test::triangle_split_of(test::box_surface(2, 2, 2))},
      {"square ring", test::voxel_surface(test::ring_cells())}};
  for (std::size_t i = 0; i <= inputs.size(); ++i) {
    // Last, the box again with every fixed corner taken as bad (below 1.5) but positive: the
    // pillowed and the woven complexes are compared and the woven one, all cubes, is kept, so
    // the STC built beside the pillowed one's positioning is dropped and built again.
    const bool forced = i == inputs.size();
    const auto& [name, surface] = inputs[forced ? 1 : i];
    SCOPED_TRACE(forced ? "box, pillow compared" : name);
    MeshOptions one;
    one.build_stc = true;
    one.position.threads = 1;
    if (forced) one.pillow.min_fixed_corner = 1.5;
    MeshOptions two = one;
    two.position.threads = 2;
    const MeshResult a = mesh_file(file_of(surface, name), one);
    const MeshResult b = mesh_file(file_of(surface, name), two);
    ASSERT_TRUE(a.validation.valid) << a.validation.summary();
    EXPECT_EQ(a.validation.summary(), b.validation.summary());
    EXPECT_EQ(a.mesh.complex.hexes, b.mesh.complex.hexes);
    ASSERT_EQ(a.mesh.points.rows(), b.mesh.points.rows());
    EXPECT_TRUE((a.mesh.points.array() == b.mesh.points.array()).all());
    EXPECT_EQ(a.pillow.reason, b.pillow.reason);
    EXPECT_EQ(a.pillow.pinched_pairs, b.pillow.pinched_pairs);
    EXPECT_EQ(a.quality.min_scaled_jacobian, b.quality.min_scaled_jacobian);
    // The STC is that of the final complex (after any pillow the comparison dropped).
    ASSERT_TRUE(a.stc && b.stc);
    const stc::HexStc fresh = stc::build_hex_stc(a.mesh.complex);
    EXPECT_EQ(stc_of_hexes(*a.stc), stc_of_hexes(fresh));
    EXPECT_EQ(stc_of_hexes(*b.stc), stc_of_hexes(fresh));
    EXPECT_EQ(a.stc->sheets.size(), fresh.sheets.size());
    EXPECT_EQ(b.stc->chords.size(), fresh.chords.size());
    // One thread: nothing ran at once.
    EXPECT_EQ(a.seconds.overlap, 0.0);
    EXPECT_GE(b.seconds.overlap, 0.0);
    if (forced) {
      EXPECT_TRUE(a.pillow.compared);
      EXPECT_FALSE(a.pillow.applied);
      EXPECT_EQ(a.mesh.complex.hexes.size(), 60u);
    }
  }
}

TEST(Beside, GivesTheTaskResultOrRethrowsItsErrorEitherWay) {
  for (const bool parallel : {false, true}) {
    SCOPED_TRACE(parallel ? "second thread" : "at once");
    Beside<int> sum(parallel, [] {
      int s = 0;
      for (int i = 1; i <= 100; ++i) s += i;
      return s;
    });
    EXPECT_EQ(sum.get(), 5050);
    EXPECT_GE(sum.seconds(), 0.0);
    Beside<int> failing(parallel, []() -> int { throw InvalidInput("the task failed"); });
    EXPECT_THROW((void)failing.get(), InvalidInput);
  }
  // Not waited for: the destructor waits.
  int touched = 0;
  {
    const Beside<int> unused(true, [&touched] { return ++touched; });
  }
  EXPECT_EQ(touched, 1);
}

TEST(Pipeline, NoStcUnlessAskedFor) {
  const MeshResult r = mesh_file(file_of(test::box_surface(2, 2, 2), "box"));
  EXPECT_EQ(r.stc, nullptr);
  EXPECT_EQ(r.seconds.stc, 0.0);
}

}  // namespace
}  // namespace stcweave::primal
