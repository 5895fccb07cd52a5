// The CAD front end (primal/cad.hpp): solids made with Gmsh's OpenCASCADE kernel in the test
// and the data/ examples, meshed into quad surfaces and on through the whole pipeline; the
// refusals. Tests that need Gmsh skip visibly in a build without it, and the refusal of that
// build is tested there.
#include "stcweave/primal/cad.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "stcweave/primal/pipeline.hpp"
#include "stcweave/stc/errors.hpp"
#include "support/cad.hpp"

namespace stcweave::primal {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using test::cad_surface;
using test::max_boundary_distance;
using test::mesh_cad;

std::string data(const std::string& name) {
  return test::repo_data(name);
}

TEST(Cad, RecipeNamesRoundTripAndUnknownNamesAreRefused) {
  for (const CadRecipe r :
       {CadRecipe::Auto, CadRecipe::Transfinite, CadRecipe::TriangleSplit, CadRecipe::Mixed})
    EXPECT_EQ(cad_recipe_from_name(cad_recipe_name(r)), r);
  try {
    (void)cad_recipe_from_name("paving");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("paving"));
    EXPECT_THAT(e.what(), HasSubstr("triangle-split"));
  }
}

TEST(Cad, CadPathsAreRecognisedByTheirExtension) {
  for (const char* p : {"a.step", "a.STP", "dir/b.brep", "c.iges", "d.IGS"})
    EXPECT_TRUE(is_cad_path(p)) << p;
  for (const char* p : {"a.obj", "a.msh", "step", "a.step.obj", "a"})
    EXPECT_FALSE(is_cad_path(p)) << p;
}

TEST(Cad, TheBuildWithoutGmshMessageSaysWhatWhyAndWhatToDo) {
  const std::string m = cad_unavailable_message("part.step");
  EXPECT_THAT(m, HasSubstr("part.step"));
  EXPECT_THAT(m, HasSubstr("built without"));
  EXPECT_THAT(m, HasSubstr("STCWEAVE_WITH_GMSH"));
  EXPECT_THAT(m, HasSubstr("libgmsh-dev"));
  EXPECT_THAT(m, HasSubstr("quad"));
}

TEST(Cad, ABuildWithoutGmshRefusesCadInputWithThatMessage) {
  if (has_cad_support()) GTEST_SKIP() << "built with Gmsh: the refusal path is not compiled in";
  try {
    (void)mesh_cad_surface(data("plate_slot.step"));
    FAIL() << "expected Unsupported";
  } catch (const Unsupported& e) {
    EXPECT_EQ(std::string(e.what()), cad_unavailable_message(data("plate_slot.step")));
  }
  EXPECT_THROW((void)mesh_cad_surface(CadPrimitive{}), Unsupported);
}

TEST(Cad, BoxIsTransfiniteAndWeavesToItsStructuredHexes) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = cad_surface(CadPrimitive{CadPrimitive::Kind::Box, 1, 1, 1}, 0.25);
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_EQ(cad.record.faces, 6u);
  EXPECT_EQ(cad.record.quads, 96u);  // 4 x 4 per face
  EXPECT_EQ(cad.file.quads.size(), 96u);
  EXPECT_EQ(cad.record.nodes, 98u);
  EXPECT_LT(cad.record.max_cad_distance, 1e-9);
  const MeshResult r = mesh_cad(cad, true);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.mesh.complex.hexes.size(), 64u);
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_NEAR(r.quality.min_scaled_jacobian, 1.0, 1e-9);
  // Every boundary node is on a face of the unit cube.
  const double d = max_boundary_distance(r, [](const Eigen::Vector3d& p) {
    double best = 1e300;
    for (int k = 0; k < 3; ++k) best = std::min({best, std::abs(p[k]), std::abs(p[k] - 1.0)});
    const double outside = (p.array() < -1e-12).any() || (p.array() > 1 + 1e-12).any();
    return best + outside;
  });
  EXPECT_LT(d, 1e-12);
}

TEST(Cad, CylinderIsSplitFromTrianglesAndItsBoundaryNodesLieOnIt) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = cad_surface(CadPrimitive{CadPrimitive::Kind::Cylinder, 0.5, 1.0, 1.0},
                                     0.25, CadRecipe::Auto, /*split=*/false);
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
  EXPECT_EQ(cad.record.split, "");
  EXPECT_THAT(cad.record.reason, HasSubstr("not transfinite"));
  EXPECT_EQ(cad.record.faces, 3u);
  EXPECT_GT(cad.record.triangles, 0u);
  EXPECT_EQ(cad.record.quads, 3 * cad.record.triangles);
  EXPECT_LT(cad.record.max_cad_distance, 1e-9);
  // The weave of a triangle-split surface is slow to untangle: the complex is the point here.
  const MeshResult r = mesh_cad(cad, false);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_GT(r.mesh.complex.hexes.size(), 0u);
  const double d = max_boundary_distance(
      r, [](const Eigen::Vector3d& p) { return test::cylinder_distance(p, 0.5, 1.0); });
  EXPECT_LT(d, 1e-9);
}

TEST(Cad, SphereNodesLieOnTheSphere) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad =
      cad_surface(CadPrimitive{CadPrimitive::Kind::Sphere, 0.5}, 0.35, CadRecipe::Auto, false);
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
  const MeshResult r = mesh_cad(cad, true);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  const double d =
      max_boundary_distance(r, [](const Eigen::Vector3d& p) { return std::abs(p.norm() - 0.5); });
  EXPECT_LT(d, 1e-9);
}

TEST(Cad, LBlockSplitFromTrianglesWhenAskedIsAValidComplex) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad =
      cad_surface(CadPrimitive{CadPrimitive::Kind::LBlock, 2, 2, 1}, 0.5, CadRecipe::TriangleSplit);
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
  EXPECT_EQ(cad.record.reason, "asked for");
  EXPECT_EQ(cad.record.faces, 8u);
  const MeshResult r = mesh_cad(cad, false);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
}

TEST(Cad, LBlockBuiltOfThreeBlocksIsTransfiniteAndStructured) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = cad_surface(CadPrimitive{CadPrimitive::Kind::LBlockBlocks, 2, 2, 1}, 0.25);
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_EQ(cad.record.volumes, 3u);
  EXPECT_EQ(cad.record.faces, 14u);  // the boundary of the union: glued faces left out
  const MeshResult r = mesh_cad(cad, true);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.mesh.complex.hexes.size(), 192u);  // 3 blocks of 4 x 4 x 4
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_NEAR(r.quality.min_scaled_jacobian, 1.0, 1e-9);
}

TEST(Cad, TransfiniteOnAnUnsplitCylinderIsRefusedNamingTheFace) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.recipe = CadRecipe::Transfinite;
  options.split = false;
  try {
    (void)mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::Cylinder, 0.5, 1.0}, options);
    FAIL() << "expected Unsupported";
  } catch (const Unsupported& e) {
    EXPECT_THAT(e.what(), HasSubstr("CAD face"));
    EXPECT_THAT(e.what(), HasSubstr("triangle-split"));
  }
}

TEST(Cad, TriangleSplitCanBeAskedForOnABox) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.size = 0.5;
  options.recipe = CadRecipe::TriangleSplit;
  const CadSurface cad = mesh_cad_surface(CadPrimitive{}, options);
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
  EXPECT_EQ(cad.record.quads, 3 * cad.record.triangles);
}

TEST(Cad, SameSolidAndOptionsGiveTheSameSurface) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.size = 0.3;
  const CadPrimitive cylinder{CadPrimitive::Kind::Cylinder, 0.5, 1.0};
  const CadSurface a = mesh_cad_surface(cylinder, options);
  // Another model in between must not leak options or entities into the next one.
  (void)mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::Box, 2, 1, 1}, CadOptions{});
  const CadSurface b = mesh_cad_surface(cylinder, options);
  EXPECT_EQ(a.file.quads, b.file.quads);
  EXPECT_TRUE(a.file.points.isApprox(b.file.points, 0.0));
}

TEST(Cad, DefaultSizeIsATenthOfTheDiagonal) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::Box, 3, 4, 12});
  EXPECT_NEAR(cad.record.size, 1.3, 1e-6);  // OpenCASCADE pads its boxes by ~1e-7
}

TEST(Cad, PlateWithASlotFromDataIsMeshedToAValidComplex) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = mesh_cad_surface(data("plate_slot.step"), test::cad_options(0.5));
  EXPECT_EQ(cad.record.format, "step");
  EXPECT_EQ(cad.record.volumes, 1u);
  EXPECT_EQ(cad.record.faces, 10u);
  // Its flat sides have four corners, its top and bottom (round slot end) do not.
  EXPECT_EQ(cad.record.recipe, CadRecipe::Mixed);
  EXPECT_GT(cad.record.structured_faces, 0u);
  EXPECT_LT(cad.record.structured_faces, 10u);
  EXPECT_GT(cad.record.quads, 3 * cad.record.triangles);
  EXPECT_LT(cad.record.max_cad_distance, 1e-7);
  const MeshResult r = mesh_cad(cad, false);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.diagnosis.genus, 0);
  // Its boundary nodes stay in the plate's box, on its top, bottom or sides where flat.
  const double d = max_boundary_distance(r, [](const Eigen::Vector3d& p) {
    return std::max({0.0, -p.x(), p.x() - 4.0, -p.y(), p.y() - 2.0, -p.z(), p.z() - 0.5});
  });
  EXPECT_LT(d, 1e-9);
}

TEST(Cad, AFaceGmshCannotMeshIsAnErrorNotACrash) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  // At the default size Gmsh 4.8 fails on the hollow torus's periodic faces, inside its
  // OpenMP region, where the exception it used to throw ended the process.
  try {
    (void)mesh_cad_surface(data("hollow_torus.step"));
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("Gmsh could not mesh the surface"));
    EXPECT_THAT(e.what(), HasSubstr("try another --size"));
  }
}

TEST(Cad, ACavityWithAHandleIsMeshedThroughTheTetInterior) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  // Two shells of genus 1, one solid: the weave's cuts refuse a cavity with handles, the tet
  // interior of the triangle-split surface meshes it.
  const CadSurface cad = mesh_cad_surface(data("hollow_torus.step"), test::cad_options(0.15));
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
  const MeshResult r = mesh_cad(cad, true);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.diagnosis.genus, 2);
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_GT(r.quality.min_scaled_jacobian, 0.2);
}

TEST(Cad, AnOpenShellIsNotAClosedSolid) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  try {
    (void)mesh_cad_surface(data("open_shell.step"));
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("not a closed solid"));
    EXPECT_THAT(e.what(), HasSubstr("5 faces"));
  }
}

TEST(Cad, AClosedShellWithoutAVolumeIsSewnIntoASolid) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = mesh_cad_surface(data("closed_shell.step"), test::cad_options(0.5));
  EXPECT_EQ(cad.record.volumes, 1u);
  ASSERT_FALSE(cad.record.warnings.empty());
  EXPECT_THAT(cad.record.warnings.front(), HasSubstr("sewn into 1 solid"));
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  const MeshResult r = mesh_cad(cad, true);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.mesh.complex.hexes.size(), 8u);
}

TEST(Cad, GarbageIsRefusedWithTheReadersReason) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const fs::path path = fs::temp_directory_path() / "stcweave_cad_garbage.step";
  {
    std::ofstream out(path);
    out << "ISO-10303-21;\nthis is not a STEP file\n";
  }
  try {
    (void)mesh_cad_surface(path);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot read it as step"));
    EXPECT_THAT(e.what(), HasSubstr(path.string()));
  }
  fs::remove(path);
}

TEST(Cad, MissingFilesAndOtherExtensionsAreRefused) {
  if (has_cad_support()) {
    EXPECT_THROW((void)mesh_cad_surface("/nonexistent/part.step"), IoError);
    EXPECT_THROW((void)mesh_cad_surface(data("lblock.obj")), InvalidInput);
  } else {
    EXPECT_THROW((void)mesh_cad_surface("/nonexistent/part.step"), Unsupported);
  }
  // Unsupported (no Gmsh) is an InvalidInput too.
  EXPECT_THROW((void)mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::Box, 1, -1, 1}),
               InvalidInput);
}

}  // namespace
}  // namespace stcweave::primal
