// Local untangling of the clusters of hexes left inverted (`untangle_clusters`,
// docs/geometry.md "Local untangling"): sub-meshes around each cluster positioned on their
// own, boundary held, the best kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <set>
#include <string>

#include "../../primal/src/position_hinge.hpp"
#include "position_helpers.hpp"
#include "stcweave/primal/position.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

/// A 7x7x7 box, boundary first and fixed, with interior node `moved` pushed by `shift`
/// (in edge lengths) along x: the hexes around it fold over.
HexMesh box_with_a_fold(std::vector<bool>* fixed, std::size_t* moved, double shift) {
  HexMesh mesh = test::box_hexes(7, 7, 7);
  const std::size_t num_fixed = test::boundary_first(mesh);
  fixed->assign(static_cast<std::size_t>(mesh.points.rows()), false);
  for (std::size_t v = 0; v < num_fixed; ++v) (*fixed)[v] = true;
  // The interior node nearest the centre (3.5, 3.5, 3.5) of the box: (3, 3, 3).
  std::size_t best = num_fixed;
  for (std::size_t v = num_fixed; v < fixed->size(); ++v) {
    const Eigen::RowVector3d p = mesh.points.row(static_cast<Eigen::Index>(v));
    if ((p - Eigen::RowVector3d(3, 3, 3)).norm() < 1e-9) best = v;
  }
  mesh.points(static_cast<Eigen::Index>(best), 0) += shift;
  *moved = best;
  return mesh;
}

/// The hexes sharing a node with a hex that has node `v`, `rings` times over.
std::set<std::size_t> rings_around(const HexMesh& mesh, std::size_t v, int rings) {
  std::set<std::size_t> nodes{v};
  std::set<std::size_t> hexes;
  for (int r = 0; r <= rings; ++r) {
    for (std::size_t h = 0; h < mesh.complex.hexes.size(); ++h)
      for (const NodeId n : mesh.complex.hexes[h])
        if (nodes.count(n.index()) != 0) hexes.insert(h);
    for (const std::size_t h : hexes)
      for (const NodeId n : mesh.complex.hexes[h]) nodes.insert(n.index());
  }
  return hexes;
}

TEST(LocalUntangling, UnfoldsAClusterAndMovesNothingOutsideItsSubMeshes) {
  std::vector<bool> fixed;
  std::size_t moved = 0;
  HexMesh mesh = box_with_a_fold(&fixed, &moved, 1.6);
  const QualitySummary before = summarize_quality(mesh, 0);
  ASSERT_GT(before.inverted, 0U) << "the test needs a fold";
  const Points start = mesh.points;
  PositionOptions options;
  std::vector<PositionProgress> told;
  options.progress = [&](const PositionProgress& p) { told.push_back(p); };
  const ClusterReport r = untangle_clusters(mesh, fixed, options);
  EXPECT_TRUE(r.ran);
  // One progress call per cluster of every pass, the last with the count left.
  ASSERT_EQ(told.size(), r.clusters);
  for (const PositionProgress& p : told) {
    EXPECT_EQ(p.phase, PositionProgress::Phase::Clusters);
    EXPECT_GE(p.step, 1U);
    EXPECT_LE(p.step, p.limit);
    EXPECT_GE(p.pass, 1U);
  }
  EXPECT_EQ(told.back().inverted, 0U);
  EXPECT_EQ(r.inverted_before, before.inverted);
  EXPECT_EQ(r.inverted_after, 0U);
  EXPECT_EQ(r.stop, "untangled");
  EXPECT_GE(r.accepted, 1U);
  EXPECT_GE(r.sub_problems, 1U);
  EXPECT_EQ(summarize_quality(mesh, 0).inverted, 0U);
  // Only nodes strictly inside the widest sub-mesh (the inverted hexes and 3 rings) move.
  std::set<std::size_t> inside;
  const std::set<std::size_t> wide = rings_around(mesh, moved, 1 + options.cluster_max_rings);
  for (const std::size_t h : wide)
    for (const NodeId n : mesh.complex.hexes[h]) inside.insert(n.index());
  std::size_t moved_nodes = 0;
  for (std::size_t v = 0; v < fixed.size(); ++v) {
    const bool same =
        mesh.points.row(static_cast<Eigen::Index>(v)) == start.row(static_cast<Eigen::Index>(v));
    if (!same) ++moved_nodes;
    if (fixed[v]) EXPECT_TRUE(same) << "fixed node n" << v << " moved";
    if (inside.count(v) == 0) EXPECT_TRUE(same) << "node n" << v << " far from the fold moved";
  }
  EXPECT_GT(moved_nodes, 0U);
}

TEST(LocalUntangling, NeverRaisesTheInvertedCountWhereNothingCanMove) {
  // A fold whose nodes are all fixed: no sub-mesh can move anything, the mesh is unchanged
  // and the pass says it settled.
  std::vector<bool> fixed;
  std::size_t moved = 0;
  HexMesh mesh = box_with_a_fold(&fixed, &moved, 1.6);
  std::fill(fixed.begin(), fixed.end(), true);
  const Points start = mesh.points;
  const std::size_t inverted = summarize_quality(mesh, 0).inverted;
  const ClusterReport r = untangle_clusters(mesh, fixed, {});
  EXPECT_TRUE(r.ran);
  EXPECT_EQ(r.inverted_after, inverted);
  EXPECT_EQ(r.accepted, 0U);
  // The hinge phase after the passes cannot move anything either.
  EXPECT_EQ(r.stop, "settled; hinge phase: " + std::to_string(inverted) + " left");
  EXPECT_EQ(r.hinge_accepted, 0U);
  EXPECT_GE(r.hinge_tries, 1U);
  EXPECT_EQ(r.passes, 1U);
  EXPECT_TRUE(mesh.points == start);
}

TEST(LocalUntangling, StopsAtTheWorkBound) {
  // Nothing can move (all nodes fixed), so every sub-mesh fails; with a bound of one unit of
  // work the first sub-mesh reaches it and no other is started.
  std::vector<bool> fixed;
  std::size_t moved = 0;
  HexMesh mesh = box_with_a_fold(&fixed, &moved, 1.6);
  std::fill(fixed.begin(), fixed.end(), true);
  PositionOptions options;
  options.cluster_max_work = 1;
  const ClusterReport r = untangle_clusters(mesh, fixed, options);
  EXPECT_EQ(r.sub_problems, 1U);
  EXPECT_GE(r.work, 1U);
  EXPECT_EQ(r.stop, "work bound");
  // Unbounded, the same cluster gets its six sub-meshes (1 to 3 rings, two starts each).
  options.cluster_max_work = 0;
  const ClusterReport all = untangle_clusters(mesh, fixed, options);
  EXPECT_EQ(all.sub_problems, 6U);
  EXPECT_EQ(all.hinge_tries, 6U);  // 1 to 3 rings, beta 0.02 and 0.05
  EXPECT_EQ(all.stop.rfind("settled; hinge phase: ", 0), 0U) << all.stop;
}

TEST(LocalUntangling, OffOrNothingInvertedLeavesTheMeshAlone) {
  std::vector<bool> fixed;
  std::size_t moved = 0;
  HexMesh folded = box_with_a_fold(&fixed, &moved, 1.6);
  const Points start = folded.points;
  PositionOptions off;
  off.cluster_passes = 0;
  const ClusterReport r = untangle_clusters(folded, fixed, off);
  EXPECT_FALSE(r.ran);
  EXPECT_EQ(r.stop, "off");
  EXPECT_TRUE(folded.points == start);

  HexMesh valid = box_with_a_fold(&fixed, &moved, 0.2);
  ASSERT_EQ(summarize_quality(valid, 0).inverted, 0U);
  const Points valid_start = valid.points;
  const ClusterReport n = untangle_clusters(valid, fixed, {});
  EXPECT_FALSE(n.ran);
  EXPECT_EQ(n.stop, "nothing inverted");
  EXPECT_TRUE(valid.points == valid_start);
}

TEST(LocalUntangling, RunsInPositionNodesWhenHexesStayInverted) {
  // Every node of the hexes at the folded node held: no position unfolds them, so hexes stay
  // inverted after the untangling and the repair, and `position_nodes` runs the local pass
  // on the free nodes around them (which cannot raise their count either).
  std::vector<bool> fixed;
  std::size_t moved = 0;
  HexMesh mesh = box_with_a_fold(&fixed, &moved, 1.6);
  for (const stc::Hex& h : mesh.complex.hexes)
    if (std::find(h.begin(), h.end(), NodeId(moved)) != h.end())
      for (const NodeId n : h) fixed[n.index()] = true;
  PositionOptions options;
  options.fixed = fixed;
  const PositionReport r = position_nodes(mesh, options);
  ASSERT_GT(r.inverted_after, 0U) << r.stop;
  EXPECT_TRUE(r.clusters.ran);
  EXPECT_GE(r.clusters.sub_problems, 1U);
  EXPECT_LE(r.clusters.inverted_after, r.clusters.inverted_before);
  EXPECT_EQ(r.clusters.inverted_after, r.inverted_after);
  EXPECT_NE(r.stop.find("; local untangling: "), std::string::npos) << r.stop;
  // The shape phase's hinge pass needs a valid mesh, and says why it did not run.
  EXPECT_FALSE(r.shape.hinge.ran);
  EXPECT_EQ(r.shape.hinge.stop, "inverted hexes: skipped");

  // Off: the report says so and nothing runs.
  HexMesh again = box_with_a_fold(&fixed, &moved, 1.6);
  options.cluster_passes = 0;
  const PositionReport off = position_nodes(again, options);
  EXPECT_FALSE(off.clusters.ran);
  EXPECT_EQ(off.clusters.stop, "off");
  EXPECT_EQ(off.stop.find("local untangling"), std::string::npos) << off.stop;
}

TEST(LocalUntangling, UntanglesInPositionNodesWhatTheRoundsAndTheRepairLeft) {
  // No untangling round and no repair: the fold is left to the local pass, which unfolds it;
  // the shape phase then runs on a valid mesh.
  std::vector<bool> fixed;
  std::size_t moved = 0;
  HexMesh mesh = box_with_a_fold(&fixed, &moved, 1.6);
  PositionOptions options;
  options.fixed = fixed;
  options.start = StartPosition::Keep;
  options.max_outer_iterations = 0;
  options.max_repair_sweeps = 0;
  const PositionReport r = position_nodes(mesh, options);
  EXPECT_GT(r.inverted_before, 0U);
  EXPECT_TRUE(r.clusters.ran);
  EXPECT_EQ(r.clusters.stop, "untangled");
  EXPECT_EQ(r.inverted_after, 0U) << r.stop;
  EXPECT_TRUE(r.untangled) << r.stop;
  EXPECT_NE(r.shape.stop, "inverted hexes: skipped");
  EXPECT_EQ(summarize_quality(mesh, 0).inverted, 0U);
}

TEST(LocalUntangling, RefusesAMaskOfTheWrongSize) {
  HexMesh mesh = test::box_hexes(2, 2, 2);
  EXPECT_THROW((void)untangle_clusters(mesh, std::vector<bool>(3, false), {}), InvalidInput);
}

TEST(LocalUntangling, RefusesAHexNamingANodeOutOfRange) {
  HexMesh mesh = test::box_hexes(2, 2, 2);
  const std::vector<bool> fixed(static_cast<std::size_t>(mesh.points.rows()), false);
  mesh.complex.hexes[1][5] = NodeId(static_cast<std::int32_t>(mesh.points.rows()));
  try {
    (void)untangle_clusters(mesh, fixed, {});
    FAIL() << "no InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("hex h1 names node"), std::string::npos) << e.what();
  }
}

// The same run twice gives the same positions. (These sub-meshes are below the 1,024 hexes
// from which `position_nodes` evaluates with threads; that its results do not depend on the
// thread count is `Position.ResultDoesNotDependOnTheThreadCount`.)
TEST(LocalUntangling, IsDeterministic) {
  std::vector<bool> fixed;
  std::size_t moved = 0;
  HexMesh a = box_with_a_fold(&fixed, &moved, 1.6);
  HexMesh b = a;
  PositionOptions one_thread;
  one_thread.threads = 1;
  (void)untangle_clusters(a, fixed, {});
  (void)untangle_clusters(b, fixed, one_thread);
  EXPECT_TRUE(a.points == b.points);
}

// With a second hardware thread the harmonic start's sub-mesh runs beside the first start's,
// capped by what the work bound left before the pair, and is kept only when the sequential
// order would have given it the same result (run again otherwise). Folds of several depths,
// unbounded and with bounds that cut the sub-meshes, in both modes: the same positions and
// the same report.
/// `untangle_clusters` on `mesh` with the two starts side by side and one after the other
/// (`threads` 1), `bound` its work bound: the same positions and report. True when a harmonic
/// start was tried (more sub-meshes than clusters times rings).
bool same_both_ways(const HexMesh& mesh, const std::vector<bool>& fixed, std::size_t bound,
                    const std::string& where) {
  HexMesh a = mesh;
  HexMesh b = mesh;
  PositionOptions both;
  both.cluster_max_work = bound;
  PositionOptions one_thread = both;
  one_thread.threads = 1;
  const ClusterReport ra = untangle_clusters(a, fixed, both);
  const ClusterReport rb = untangle_clusters(b, fixed, one_thread);
  EXPECT_TRUE(a.points == b.points) << where;
  EXPECT_EQ(ra.work, rb.work) << where;
  EXPECT_EQ(ra.sub_problems, rb.sub_problems) << where;
  EXPECT_EQ(ra.accepted, rb.accepted) << where;
  EXPECT_EQ(ra.inverted_after, rb.inverted_after) << where;
  EXPECT_EQ(ra.stop, rb.stop) << where;
  std::cout << where << ": " << rb.sub_problems << " sub-meshes, " << rb.clusters
            << " clusters, work " << rb.work << ", " << rb.inverted_after << " inverted, "
            << rb.stop << "\n";
  return rb.sub_problems > rb.clusters * 3;
}

TEST(LocalUntangling, TheTwoStartsSideBySideGiveTheSequentialResult) {
  std::size_t compared = 0, harmonic_tried = 0;
  for (const double shift : {1.6, 2.4, 3.4}) {
    for (const std::size_t bound : {std::size_t{0}, std::size_t{150}, std::size_t{600},
                                    std::size_t{4000}, std::size_t{30000}}) {
      std::vector<bool> fixed;
      std::size_t moved = 0;
      const HexMesh mesh = box_with_a_fold(&fixed, &moved, shift);
      if (same_both_ways(mesh, fixed, bound,
                         "shift " + std::to_string(shift) + ", bound " + std::to_string(bound)))
        ++harmonic_tried;
      ++compared;
    }
  }
  // A fixed corner pushed through its hex: no position of the free nodes unfolds it, so every
  // sub-mesh is tried, both starts, and the tight bounds cut them (with 300 the harmonic
  // start run beside the first is run again under the smaller cap the first one leaves).
  for (const std::size_t bound :
       {std::size_t{0}, std::size_t{300}, std::size_t{1200}, std::size_t{5000}}) {
    std::vector<bool> fixed;
    std::size_t moved = 0;
    HexMesh mesh = box_with_a_fold(&fixed, &moved, 0.0);
    for (Eigen::Index v = 0; v < mesh.points.rows(); ++v) {
      if (mesh.points.row(v).norm() < 1e-9) mesh.points.row(v) = Eigen::RowVector3d(1.6, 1.4, 1.5);
    }
    if (same_both_ways(mesh, fixed, bound, "pushed corner, bound " + std::to_string(bound)))
      ++harmonic_tried;
    ++compared;
  }
  EXPECT_EQ(compared, 19U);
  EXPECT_GT(harmonic_tried, 0U) << "no harmonic start was tried: the test shows nothing";
}

// The hinge untangling (position_hinge.hpp) alone: the fold of the 7x7x7 box, every interior
// node free, boundary held.
TEST(HingeUntangle, UnfoldsAFoldWithTheBoundaryHeld) {
  std::vector<bool> fixed;
  std::size_t moved = 0;
  HexMesh mesh = box_with_a_fold(&fixed, &moved, 1.6);
  ASSERT_GT(summarize_quality(mesh, 0).inverted, 0U) << "the test needs a fold";
  const Points start = mesh.points;
  HexMesh again = mesh;
  const HingeOutcome r = hinge_untangle(mesh, fixed, 0.05, 100000);
  EXPECT_EQ(summarize_quality(mesh, 0).inverted, 0U);
  EXPECT_GT(summarize_quality(mesh, 0).min_scaled_jacobian, 0.05);
  EXPECT_GE(r.iterations, 1U);
  EXPECT_EQ(r.stages, 10U);  // delta 0.1, 0.03, ... down to 2e-6
  for (std::size_t v = 0; v < fixed.size(); ++v) {
    if (fixed[v]) {
      EXPECT_TRUE(mesh.points.row(static_cast<Eigen::Index>(v)) ==
                  start.row(static_cast<Eigen::Index>(v)))
          << "fixed node n" << v << " moved";
    }
  }
  // Deterministic.
  (void)hinge_untangle(again, fixed, 0.05, 100000);
  EXPECT_TRUE(again.points == mesh.points);
}

TEST(HingeUntangle, KeepsToItsIterationBoundAndMovesNothingWithoutFreeNodes) {
  std::vector<bool> fixed;
  std::size_t moved = 0;
  HexMesh mesh = box_with_a_fold(&fixed, &moved, 1.6);
  HexMesh bounded = mesh;
  const HingeOutcome r = hinge_untangle(bounded, fixed, 0.05, 3);
  EXPECT_LE(r.iterations, 3U);
  EXPECT_GE(r.stages, 1U);
  std::fill(fixed.begin(), fixed.end(), true);
  const Points start = mesh.points;
  const HingeOutcome none = hinge_untangle(mesh, fixed, 0.05, 1000);
  EXPECT_EQ(none.iterations, 0U);
  EXPECT_TRUE(mesh.points == start);
}

// The hinge phase runs only where the passes leave hexes inverted: on the fold, which the
// passes untangle, it never runs, and the result is the one without it (the corpus test on
// `pmp/fandisk_quads` has a mesh the passes leave inverted and the phase untangles).
TEST(LocalUntangling, TheHingePhaseRunsOnlyWhereThePassesLeftHexesInverted) {
  std::vector<bool> fixed;
  std::size_t moved = 0;
  HexMesh mesh = box_with_a_fold(&fixed, &moved, 1.6);
  HexMesh without_hinge = mesh;
  PositionOptions options;
  const ClusterReport on = untangle_clusters(mesh, fixed, options);
  options.cluster_hinge = false;
  const ClusterReport off = untangle_clusters(without_hinge, fixed, options);
  EXPECT_EQ(on.stop, "untangled");
  EXPECT_EQ(on.hinge_tries, 0U);
  EXPECT_EQ(on.hinge_clusters, 0U);
  EXPECT_TRUE(mesh.points == without_hinge.points);
  EXPECT_EQ(off.stop, on.stop);
}

}  // namespace
}  // namespace stcweave::primal
