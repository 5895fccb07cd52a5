// The slab route of the handle cuts (primal/src/cut.cpp, docs/topology.md "Slabs"): each
// handle's band of quads closed by a disc on each of its two boundary cycles, woven on its
// own, and the rest of the solid closed by the same discs; glued by node ids alone.
#include <gtest/gtest.h>

#include <vector>

#include "stcweave/primal/cut.hpp"
#include "stcweave/primal/handles.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

struct Slabbed {
  weave::WeaveResult woven;
  SolidsReport report;
};

Slabbed slabbed(const SurfaceMesh& surface) {
  CutOptions cut;
  cut.slab_first = true;
  Slabbed s;
  s.woven = weave_solids(surface, weave::WeaveOptions{}, cut, &s.report);
  return s;
}

void expect_slab_cuts(const Slabbed& s, const SurfaceMesh& surface, std::size_t handles) {
  const stc::ValidationReport v = stc::validate_hex_complex(s.woven.complex, &surface.surface);
  EXPECT_TRUE(v.valid) << v.summary();
  ASSERT_EQ(s.report.cuts.size(), handles);
  for (const HandleCut& c : s.report.cuts) EXPECT_EQ(c.disc.rfind("slab: ", 0), 0u) << c.disc;
  EXPECT_EQ(s.woven.hex_rule.size(), s.woven.complex.hexes.size());
  EXPECT_EQ(s.woven.hex_shrink.size(), s.woven.complex.hexes.size());
}

TEST(Slab, SquareRingIsCutAlongTheBandBesideItsSection) {
  const SurfaceMesh ring = test::voxel_surface(test::ring_cells());
  const Slabbed s = slabbed(ring);
  expect_slab_cuts(s, ring, 1);
}

TEST(Slab, TorusOfSquareSectionGivesAValidComplexTheSameTwice) {
  const SurfaceMesh torus = test::torus_surface(4, 12, 3.0, 1.0);
  const Slabbed a = slabbed(torus);
  expect_slab_cuts(a, torus, 1);
  const Slabbed b = slabbed(torus);
  EXPECT_EQ(a.woven.complex.hexes, b.woven.complex.hexes);  // deterministic
}

}  // namespace
}  // namespace stcweave::primal
