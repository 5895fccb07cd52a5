// The rule set `extended` on Gmsh's transfinite surfaces of the shared corpus, compared hex by
// hex with Gmsh's own structured hex meshes (`*_tf_coarse.reference_hex.msh`), label `corpus`.
// The weave of every loop-clean genus-0 file with `extended` is checked by
// corpus_weave_test.cpp (the pipeline's default rule set is `extended`), not repeated here.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <string>

#include "stcweave/primal/io.hpp"
#include "stcweave/primal/pipeline.hpp"
#include "support/compare.hpp"

namespace stcweave {
namespace {

namespace fs = std::filesystem;

const fs::path kGmsh = fs::path(STCWEAVE_SHARED_DATA) / "gmsh";

/// The pipeline with `extended` (checked, no node positioning: only the topology matters).
primal::MeshResult mesh_extended(const fs::path& obj) {
  primal::MeshOptions options;
  options.weave.rules = weave::RuleSet::Extended;
  options.weave.check = true;
  options.untangle = false;
  return primal::mesh_file(primal::read_mesh(obj), options);
}

primal::HexMesh reference_of(const fs::path& msh) {
  const primal::MeshFile file = primal::read_mesh(msh);
  primal::HexMesh m;
  m.points = file.points;
  m.complex.hexes = file.hexes;
  m.complex.num_nodes = static_cast<std::size_t>(file.points.rows());
  return m;
}

class CorpusExtended : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kGmsh)) GTEST_SKIP() << "shared data not found at " << STCWEAVE_SHARED_DATA;
  }
};

/// Weaves `name`_tf_coarse.obj and compares with its reference hex mesh.
void expect_reference_mesh(const std::string& name, std::size_t hexes) {
  const primal::MeshResult r = mesh_extended(kGmsh / (name + "_tf_coarse.obj"));
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.mesh.complex.hexes.size(), hexes);
  const primal::HexMesh reference = reference_of(kGmsh / (name + "_tf_coarse.reference_hex.msh"));
  ASSERT_EQ(reference.complex.hexes.size(), hexes) << "the reference itself";
  std::string why;
  EXPECT_TRUE(test::same_connectivity(r.mesh, reference, &why)) << why;
}

TEST_F(CorpusExtended, CubeGivesTheReferenceMesh) {
  expect_reference_mesh("cube", 125);
}

TEST_F(CorpusExtended, LBlockGivesTheReferenceMesh) {
  expect_reference_mesh("lblock", 81);
}

TEST_F(CorpusExtended, CylinderGivesTheOGrid) {
  // The 105-hex O-grid: parallel crossings build four layers, parallel merging closes the
  // fifth (seed sect. 4.5 and 5.1, docs/extended-rules.md).
  expect_reference_mesh("cylinder", 105);
}

// Disabled: a weaver defect. Without backtracking, extended on cylinder_a6_trisubdiv_coarse
// (168 quads) does not finish. From rule 2476 on, (almost) every shrink fails ("every node on
// the shrinking side is blocked": seams refused because the merge would make two hexes share
// more than one face, blind chords refused) after one or two rules; backtracking off, the
// partial work is kept, the front grows by about two faces per such hex and the cycle select,
// fail, keep never ends: by rule 4000, 1900 failed shrinks and 2990 front faces (82 at rule
// 2470), each selection slower than the last (5000 rules take 26 s; the default limit, about
// 37,400 rules, is out of reach in practice). With backtracking (the default) the same file
// gives 1300 hexes in 3758 rules; reliable without backtracking gives 56.
// The limit below (1.3 times what the backtracking weave needs; raise it if a fix needs more)
// makes the failure quick (WeaveError) instead of a hang.
TEST_F(CorpusExtended, DISABLED_CylinderTrisubdivCompletesWithoutBacktracking) {
  primal::MeshOptions options;
  options.weave.rules = weave::RuleSet::Extended;
  options.weave.backtrack = false;
  options.weave.max_rules = 5000;
  options.untangle = false;
  primal::MeshResult r;
  ASSERT_NO_THROW(r = primal::mesh_file(
                      primal::read_mesh(kGmsh / "cylinder_a6_trisubdiv_coarse.obj"), options));
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
}

// An uncut genus-0 shell is woven without the depth filter unless that weave blocks
// (MeshOptions::depth_filter_after_block, docs/extended-rules.md "The depth filter in an
// uncut shell"). On srf2012_ellipsoid-A the filter's peeling made `extended` weave 140 hexes
// more than `reliable` (1,230 against 1,090 woven, before pillowing); without it the two agree.
TEST_F(CorpusExtended, EllipsoidIsWovenWithoutTheDepthFilterAndNoWorseThanReliable) {
  const fs::path file =
      fs::path(STCWEAVE_SHARED_DATA) / "real/hexalab/srf2012_ellipsoid-A.boundary.obj";
  const primal::MeshResult extended = mesh_extended(file);
  EXPECT_TRUE(extended.validation.valid) << extended.validation.summary();
  EXPECT_TRUE(extended.depth_filter_retry.empty()) << extended.depth_filter_retry;
  primal::MeshOptions seed_order;
  seed_order.weave.rules = weave::RuleSet::Extended;
  seed_order.untangle = false;
  seed_order.depth_filter_after_block = false;
  const primal::MeshResult filtered = primal::mesh_file(primal::read_mesh(file), seed_order);
  primal::MeshOptions reliable = seed_order;
  reliable.weave.rules = weave::RuleSet::Reliable;
  const primal::MeshResult rel = primal::mesh_file(primal::read_mesh(file), reliable);
  std::cout << "woven hexes: extended " << extended.woven.complex.hexes.size()
            << ", with the depth filter from the start " << filtered.woven.complex.hexes.size()
            << ", reliable " << rel.woven.complex.hexes.size() << "\n";
  EXPECT_LE(extended.woven.complex.hexes.size(), rel.woven.complex.hexes.size());
  EXPECT_GT(filtered.woven.complex.hexes.size(), rel.woven.complex.hexes.size());
}

}  // namespace
}  // namespace stcweave
