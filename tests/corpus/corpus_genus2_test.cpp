// Genus > 0 cases of the shared corpus that the first handle cut refused (label `corpus`):
// the handle diagnosis of a surface with a node of unpointed normal cone (pipe_helix), and
// the loop-following chord discs on a triangle-split-like surface whose loops crossing the
// handle cycles cross each other (HexaLab's Fertility, genus 4).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "stcweave/primal/cut.hpp"
#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/handles.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/primal/pipeline.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/corpus.hpp"

namespace stcweave {
namespace {

TEST(CorpusGenus2, PipeHelixIsUndecidedBecauseItsSurfaceIsNotEmbedded) {
  // Its generators meet a node of unpointed normal cone (n174); going round it is refused
  // because an edge pierces a quad there: the undecided reason says so.
  STCWEAVE_SKIP_WITHOUT_SHARED_DATA();
  const auto path = test::shared_data() / "real/polycube-nightmares-quad/pipe_helix.msh";
  const primal::SurfaceDiagnosis d = primal::diagnose(primal::read_mesh(path));
  ASSERT_TRUE(d.handles);
  EXPECT_FALSE(d.handles->decided);
  EXPECT_NE(d.handles->undecided_reason.find("not embedded there"), std::string::npos)
      << d.handles->undecided_reason;
  EXPECT_EQ(d.handles->genus, 1);
  // The same defect, found by the check of crossing quads (measured: 4 pairs).
  ASSERT_TRUE(d.crossing_quad_pairs.has_value());
  EXPECT_GT(*d.crossing_quad_pairs, 0u);
  EXPECT_NE(primal::crossing_warning(d).find("the surface passes through itself"),
            std::string::npos);
}

TEST(CorpusGenus2, FertilityIsCutAlongLoopFollowingDiscsIntoAValidComplex) {
  STCWEAVE_SKIP_WITHOUT_SHARED_DATA();
  const auto path = test::shared_data() / "real/hexalab/evpc2016_Fertility_hex-small.vtk";
  const auto file = primal::read_mesh(path);
  primal::SurfaceMesh surface = primal::surface_of(file);
  primal::orient_outward(surface);
  // Block recovery and the retry undoing the shrinks that leave a seam blocked off: then no
  // grid disc gives a cut ball that weaves, and the second pass's loop-following discs are what
  // this test exercises. (With either, the grids' weaves complete and the first pass already
  // succeeds.)
  primal::MeshOptions options;
  options.weave.block_recovery = weave::BlockRecovery::Off;
  options.weave.undo_seam_blocking_on_block = false;
  primal::SolidsReport report;
  weave::WeaveResult woven;
  ASSERT_NO_THROW(woven = primal::weave_solids(surface, options.weave, options.cut, &report));
  const stc::ValidationReport v = stc::validate_hex_complex(woven.complex, &surface.surface);
  EXPECT_TRUE(v.valid) << v.summary();
  ASSERT_EQ(report.cuts.size(), 4u);
  for (const primal::HandleCut& cut : report.cuts) {
    SCOPED_TRACE(cut.disc);
    EXPECT_EQ(cut.disc.rfind("loop-following", 0), 0u);
    EXPECT_EQ(cut.grid_a, 0);
  }
  EXPECT_GT(woven.complex.hexes.size(), surface.surface.num_quads() / 2);
}

}  // namespace
}  // namespace stcweave
