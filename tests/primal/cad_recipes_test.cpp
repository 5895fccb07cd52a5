// The CAD front end on solids with a hole (a plate with a through-hole, a torus), each as
// one solid and as blocks glued face to face, made with Gmsh's OpenCASCADE kernel in the
// test; and the mixed recipe (structured four-cornered faces next to split ones).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "stcweave/primal/cad.hpp"
#include "stcweave/primal/diagnose.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/cad.hpp"

namespace stcweave::primal {
namespace {

using test::cad_surface;
using test::mesh_cad;
using ::testing::HasSubstr;

/// Distance to the surface of the torus of radius 1 and tube radius 0.4 around z.
double torus_distance(const Eigen::Vector3d& p) {
  return std::abs(std::hypot(std::hypot(p.x(), p.y()) - 1.0, p.z()) - 0.4);
}

TEST(CadRecipes, TorusOfBlocksIsTransfiniteAndWeavesThroughItsHandle) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = cad_surface({CadPrimitive::Kind::TorusBlocks, 1.0, 0.4}, 0.35);
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_EQ(cad.record.volumes, 20u);
  EXPECT_EQ(cad.record.faces, 16u);  // the core's and the cuts' faces are inside
  EXPECT_EQ(cad.record.structured_faces, 16u);
  EXPECT_LT(cad.record.max_cad_distance, 1e-7);
  const SurfaceDiagnosis d = diagnose(cad.file);
  EXPECT_EQ(d.genus, 1);
  EXPECT_EQ(d.self_intersecting_loops, 0u);
  const MeshResult r = mesh_cad(cad, true);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_GT(r.quality.min_scaled_jacobian, 0.0);
  EXPECT_LT(test::max_boundary_distance(r, torus_distance), 1e-6);
}

TEST(CadRecipes, PlateWithAHoleOfBlocksIsTransfiniteAndWeaves) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad =
      cad_surface({CadPrimitive::Kind::PlateWithHoleBlocks, 4.0, 2.0, 0.5}, 0.25);
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_EQ(cad.record.volumes, 4u);
  EXPECT_EQ(cad.record.faces, 16u);  // 4 top, 4 bottom, 4 outer sides, 4 arcs of the hole
  EXPECT_EQ(diagnose(cad.file).genus, 1);
  const MeshResult r = mesh_cad(cad, true);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.quality.inverted, 0u);
  // Every boundary node is in the plate's box and outside the hole (radius 0.5).
  const double d = test::max_boundary_distance(r, [](const Eigen::Vector3d& p) {
    const double in_hole = std::max(0.0, 0.5 - 1e-9 - std::hypot(p.x() - 2.0, p.y() - 1.0));
    return std::max({in_hole, -p.x(), p.x() - 4.0, -p.y(), p.y() - 2.0, -p.z(), p.z() - 0.5});
  });
  EXPECT_LT(d, 1e-9);
}

TEST(CadRecipes, OneSolidTorusHasNoFourCorneredFaceSoItIsSplit) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  // Without the split into blocks (which makes it 20 blocks: cad_split_handles_test.cpp).
  const CadSurface cad =
      cad_surface({CadPrimitive::Kind::Torus, 1.0, 0.4}, 0.3, CadRecipe::Auto, /*split=*/false);
  EXPECT_EQ(cad.record.faces, 1u);
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
  EXPECT_THAT(cad.record.reason, HasSubstr("no CAD face has 4 corners"));
  EXPECT_EQ(cad.record.structured_faces, 0u);
  EXPECT_EQ(cad.record.quads, 3 * cad.record.triangles);
  const SurfaceDiagnosis d = diagnose(cad.file);
  EXPECT_EQ(d.genus, 1);
  EXPECT_EQ(d.self_intersecting_loops, 0u);
  EXPECT_LT(cad.record.max_cad_distance, 1e-7);
}

TEST(CadRecipes, LBlockIsMixedAndLoopClean) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad =
      cad_surface({CadPrimitive::Kind::LBlock, 2, 2, 1}, 0.25, CadRecipe::Auto, /*split=*/false);
  EXPECT_EQ(cad.record.recipe, CadRecipe::Mixed);
  EXPECT_EQ(cad.record.faces, 8u);
  EXPECT_EQ(cad.record.structured_faces, 6u);  // all but the two L-shaped faces
  EXPECT_THAT(cad.record.reason, HasSubstr("6 of the 8"));
  EXPECT_THAT(cad.record.reason, HasSubstr("loop-clean"));
  EXPECT_GT(cad.record.triangles, 0u);
  EXPECT_GT(cad.record.quads, 3 * cad.record.triangles);  // the structured faces' quads
  EXPECT_EQ(diagnose(cad.file).self_intersecting_loops, 0u);
  const MeshResult r = mesh_cad(cad, false);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
}

TEST(CadRecipes, EachRecipeCanStillBeAskedFor) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadPrimitive lblock{CadPrimitive::Kind::LBlock, 2, 2, 1};
  const CadSurface split = cad_surface(lblock, 0.5, CadRecipe::TriangleSplit);
  EXPECT_EQ(split.record.recipe, CadRecipe::TriangleSplit);
  EXPECT_EQ(split.record.reason, "asked for");
  EXPECT_EQ(split.record.structured_faces, 0u);
  const CadSurface mixed = cad_surface(lblock, 0.5, CadRecipe::Mixed);
  EXPECT_EQ(mixed.record.recipe, CadRecipe::Mixed);
  // Mixed on a box: every face structured, then split in four (edges of the target size).
  const CadSurface box = cad_surface({CadPrimitive::Kind::Box, 1, 1, 1}, 0.25, CadRecipe::Mixed);
  EXPECT_EQ(box.record.recipe, CadRecipe::Mixed);
  EXPECT_EQ(box.record.quads, 96u);
  EXPECT_EQ(box.record.triangles, 0u);
  EXPECT_EQ(cad_recipe_from_name("mixed"), CadRecipe::Mixed);
}

TEST(CadRecipes, TheTriangleAlgorithmIsAnOptionAndOthersAreRefused) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadPrimitive sphere{CadPrimitive::Kind::Sphere, 0.5};
  CadOptions options = test::cad_options(0.25, CadRecipe::Auto, /*split=*/false);
  for (const int algorithm : {1, 5, 6}) {
    options.triangle_algorithm = algorithm;
    const CadSurface cad = mesh_cad_surface(sphere, options);
    EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
    EXPECT_EQ(diagnose(cad.file).self_intersecting_loops, 0u) << algorithm;
  }
  options.triangle_algorithm = 8;
  try {
    (void)mesh_cad_surface(sphere, options);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("algorithm 8"));
  }
}

TEST(CadRecipes, ATorusNeedsItsTubeInsideItsRadius) {
  EXPECT_THROW((void)mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::Torus, 1.0, 1.0}),
               InvalidInput);
  EXPECT_THROW((void)mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::TorusBlocks, 0.5, 1.0}),
               InvalidInput);
}

}  // namespace
}  // namespace stcweave::primal
