// The slab route of the handle cuts (primal/src/cut.cpp, docs/topology.md "Slabs"): each
// handle's band of quads closed by a disc on each of its two boundary cycles, woven on its
// own, and the rest of the solid closed by the same discs; glued by node ids alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <vector>

#include "../../primal/src/slab_band.hpp"
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

TEST(Slab, SquareRingIsCutAlongSlabsIntoACertifiedComplex) {
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

// far_bands on a torus of 4 x 12 quads: the partner of the first band is a section of the
// torus, the band's quads on the minus side of the cycle, and the split is as even as the
// sections allow (24 of 48 quads), where the band beside the cycle has 8.
TEST(Slab, FarBandOfATorusSplitsItIntoTwoHalves) {
  const SurfaceMesh torus = test::torus_surface(4, 12, 3.0, 1.0);
  const HandleDiagnosis h = diagnose_handles(torus);
  ASSERT_EQ(h.handles.size(), 1u);
  const std::vector<NodeId>& cycle = h.handles[0].nodes;
  const std::vector<SlabBand> bands = far_bands(torus.surface, cycle, 3);
  ASSERT_FALSE(bands.empty());
  EXPECT_EQ(bands[0].quads.size(), 24u);
  EXPECT_EQ(bands[0].outer.size(), cycle.size());
  for (NodeId v : bands[0].outer)
    EXPECT_EQ(std::count(cycle.begin(), cycle.end(), v), 0) << v.str();
  // The same partner, given directly, gives the same band; the cycle itself is no partner.
  const std::optional<SlabBand> again = band_between(torus.surface, cycle, bands[0].outer);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->quads, bands[0].quads);
  EXPECT_FALSE(band_between(torus.surface, cycle, cycle).has_value());
}

}  // namespace
}  // namespace stcweave::primal
