// Splitting a CAD solid into blocks whose faces have four corners before its surface is
// meshed (CadOptions::split, primal/src/cad_split.cpp): a cylinder as an O-grid, a sphere as a
// cubed sphere, an L-block cut by the planes through its corners; the surface stays on the
// solid, the weave gives a structured or near-structured mesh; solids that are not
// recognised, and the split turned off, keep the recipes they had.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "stcweave/primal/cad.hpp"
#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/pipeline.hpp"
#include "support/cad.hpp"

namespace stcweave::primal {
namespace {

using test::cad_surface;
using test::max_boundary_distance;
using test::mesh_cad;
using ::testing::HasSubstr;

TEST(CadSplit, CylinderBecomesAnOGridOfFiveBlocksOnTheSameSurface) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = cad_surface({CadPrimitive::Kind::Cylinder, 0.5, 1.0}, 0.25);
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_THAT(cad.record.split, HasSubstr("O-grid of 5 blocks"));
  EXPECT_THAT(cad.record.reason, HasSubstr("O-grid"));
  EXPECT_EQ(cad.record.volumes, 1u);  // the file's solids, before the split
  EXPECT_EQ(cad.record.faces, 14u);   // 5 on each cap, 4 on the side
  EXPECT_EQ(cad.record.structured_faces, 14u);
  EXPECT_EQ(cad.record.triangles, 0u);
  EXPECT_LT(cad.record.max_cad_distance, 1e-9);
  const MeshResult r = mesh_cad(cad, true);
  ASSERT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_GT(r.quality.min_scaled_jacobian, 0.5);
  const double d = max_boundary_distance(
      r, [](const Eigen::Vector3d& p) { return test::cylinder_distance(p, 0.5, 1.0); });
  EXPECT_LT(d, 1e-9);
}

TEST(CadSplit, SphereBecomesACubedSphereOfSevenBlocksOnTheSameSurface) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = cad_surface({CadPrimitive::Kind::Sphere, 0.5}, 0.125);
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_THAT(cad.record.split, HasSubstr("cubed sphere of 7 blocks"));
  EXPECT_EQ(cad.record.faces, 6u);
  EXPECT_EQ(diagnose(cad.file).self_intersecting_loops, 0u);
  const MeshResult r = mesh_cad(cad, true);
  ASSERT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_GT(r.quality.min_scaled_jacobian, 0.5);
  const double d =
      max_boundary_distance(r, [](const Eigen::Vector3d& p) { return std::abs(p.norm() - 0.5); });
  EXPECT_LT(d, 1e-9);
}

TEST(CadSplit, LBlockIsCutByThePlanesThroughItsCornersIntoStructuredBlocks) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = cad_surface({CadPrimitive::Kind::LBlock, 2, 2, 1}, 0.25);
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_THAT(cad.record.split, HasSubstr("2 axis planes"));
  EXPECT_THAT(cad.record.split, HasSubstr("3 blocks"));
  EXPECT_EQ(cad.record.faces, 14u);  // as the L-block built of three boxes
  const MeshResult r = mesh_cad(cad, true);
  ASSERT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.mesh.complex.hexes.size(), 192u);  // 3 blocks of 4 x 4 x 4
  EXPECT_NEAR(r.quality.min_scaled_jacobian, 1.0, 1e-9);
}

TEST(CadSplit, OffOrWithTriangleSplitTheSolidIsMeshedAsItIs) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadPrimitive cylinder{CadPrimitive::Kind::Cylinder, 0.5, 1.0};
  const CadSurface off = cad_surface(cylinder, 0.25, CadRecipe::Auto, /*split=*/false);
  EXPECT_EQ(off.record.split, "");
  EXPECT_EQ(off.record.faces, 3u);
  EXPECT_EQ(off.record.recipe, CadRecipe::TriangleSplit);
  const CadSurface asked = cad_surface(cylinder, 0.25, CadRecipe::TriangleSplit);
  EXPECT_EQ(asked.record.split, "");
  EXPECT_EQ(asked.record.faces, 3u);
  EXPECT_EQ(asked.file.quads, off.file.quads);
  // Mixed on the L-block: split too, then every face structured.
  const CadSurface mixed =
      cad_surface({CadPrimitive::Kind::LBlock, 2, 2, 1}, 0.25, CadRecipe::Mixed);
  EXPECT_EQ(mixed.record.recipe, CadRecipe::Mixed);
  EXPECT_EQ(mixed.record.structured_faces, mixed.record.faces);
}

TEST(CadSplit, SolidsNotRecognisedAreLeftWhole) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  // A plate with a slot (a half cylinder): no case applies (a torus and a plate with a
  // through-hole are split: cad_split_handles_test.cpp).
  const CadSurface slot =
      mesh_cad_surface(test::repo_data("plate_slot.step"), test::cad_options(0.5));
  EXPECT_EQ(slot.record.split, "");
  EXPECT_EQ(slot.record.recipe, CadRecipe::Mixed);
  // A box has nothing to split.
  const CadSurface box = cad_surface({CadPrimitive::Kind::Box, 1, 1, 1}, 0.5);
  EXPECT_EQ(box.record.split, "");
  EXPECT_EQ(box.record.faces, 6u);
}

}  // namespace
}  // namespace stcweave::primal
