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
#include <set>
#include <string>

#include "stcweave/primal/pipeline.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::primal {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

#define SKIP_WITHOUT_GMSH() \
  if (!has_cad_support()) GTEST_SKIP() << "built without Gmsh (STCWEAVE_WITH_GMSH=OFF)"

std::string data(const std::string& name) {
  return std::string(STCWEAVE_SOURCE_DIR) + "/data/" + name;
}

MeshResult mesh_cad(const CadSurface& cad, bool untangle) {
  MeshOptions options;
  options.untangle = untangle;
  return mesh_file(cad.file, options);
}

/// Largest distance of a boundary node of the hex mesh to an analytic surface; the boundary
/// nodes are the nodes of the woven surface's quads, looked up in the hex mesh's points.
template <typename Distance>
double max_boundary_distance(const MeshResult& r, Distance distance) {
  std::set<std::size_t> nodes;
  for (const auto& q : r.surface.surface.quads)
    for (const NodeId n : q) nodes.insert(n.index());
  double worst = 0.0;
  for (const std::size_t n : nodes) {
    const Eigen::Vector3d p = r.mesh.points.row(static_cast<Eigen::Index>(n)).transpose();
    worst = std::max(worst, distance(p));
  }
  return worst;
}

TEST(Cad, RecipeNamesRoundTripAndUnknownNamesAreRefused) {
  for (const CadRecipe r : {CadRecipe::Auto, CadRecipe::Transfinite, CadRecipe::TriangleSplit})
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
  SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.size = 0.25;
  const CadSurface cad = mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::Box, 1, 1, 1}, options);
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
  SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.size = 0.25;
  const CadSurface cad =
      mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::Cylinder, 0.5, 1.0, 1.0}, options);
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
  EXPECT_THAT(cad.record.reason, HasSubstr("not transfinite"));
  EXPECT_EQ(cad.record.faces, 3u);
  EXPECT_GT(cad.record.triangles, 0u);
  EXPECT_EQ(cad.record.quads, 3 * cad.record.triangles);
  EXPECT_LT(cad.record.max_cad_distance, 1e-9);
  // The weave of a triangle-split surface is slow to untangle: the complex is the point here.
  const MeshResult r = mesh_cad(cad, false);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_GT(r.mesh.complex.hexes.size(), 0u);
  const double d = max_boundary_distance(r, [](const Eigen::Vector3d& p) {
    const double radial = std::hypot(p.x(), p.y());
    const double to_side =
        std::abs(radial - 0.5) + std::max(0.0, -p.z()) + std::max(0.0, p.z() - 1.0);
    const double to_caps =
        std::min(std::abs(p.z()), std::abs(p.z() - 1.0)) + std::max(0.0, radial - 0.5);
    return std::min(to_side, to_caps);
  });
  EXPECT_LT(d, 1e-9);
}

TEST(Cad, SphereNodesLieOnTheSphere) {
  SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.size = 0.35;
  const CadSurface cad = mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::Sphere, 0.5}, options);
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
  const MeshResult r = mesh_cad(cad, true);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  const double d =
      max_boundary_distance(r, [](const Eigen::Vector3d& p) { return std::abs(p.norm() - 0.5); });
  EXPECT_LT(d, 1e-9);
}

TEST(Cad, LBlockHasANonQuadrilateralFaceSoItIsSplit) {
  SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.size = 0.5;
  const CadSurface cad =
      mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::LBlock, 2, 2, 1}, options);
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
  EXPECT_THAT(cad.record.reason, HasSubstr("6 curve uses"));
  EXPECT_EQ(cad.record.faces, 8u);
  const MeshResult r = mesh_cad(cad, false);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
}

TEST(Cad, LBlockBuiltOfThreeBlocksIsTransfiniteAndStructured) {
  SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.size = 0.25;
  const CadSurface cad =
      mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::LBlockBlocks, 2, 2, 1}, options);
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_EQ(cad.record.volumes, 3u);
  EXPECT_EQ(cad.record.faces, 14u);  // the boundary of the union: glued faces left out
  const MeshResult r = mesh_cad(cad, true);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.mesh.complex.hexes.size(), 192u);  // 3 blocks of 4 x 4 x 4
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_NEAR(r.quality.min_scaled_jacobian, 1.0, 1e-9);
}

TEST(Cad, TransfiniteOnACylinderIsRefusedNamingTheFace) {
  SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.recipe = CadRecipe::Transfinite;
  try {
    (void)mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::Cylinder, 0.5, 1.0}, options);
    FAIL() << "expected Unsupported";
  } catch (const Unsupported& e) {
    EXPECT_THAT(e.what(), HasSubstr("CAD face"));
    EXPECT_THAT(e.what(), HasSubstr("triangle-split"));
  }
}

TEST(Cad, TriangleSplitCanBeAskedForOnABox) {
  SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.size = 0.5;
  options.recipe = CadRecipe::TriangleSplit;
  const CadSurface cad = mesh_cad_surface(CadPrimitive{}, options);
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
  EXPECT_EQ(cad.record.quads, 3 * cad.record.triangles);
}

TEST(Cad, SameSolidAndOptionsGiveTheSameSurface) {
  SKIP_WITHOUT_GMSH();
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
  SKIP_WITHOUT_GMSH();
  const CadSurface cad = mesh_cad_surface(CadPrimitive{CadPrimitive::Kind::Box, 3, 4, 12});
  EXPECT_NEAR(cad.record.size, 1.3, 1e-6);  // OpenCASCADE pads its boxes by ~1e-7
}

TEST(Cad, PlateWithASlotFromDataIsMeshedToAValidComplex) {
  SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.size = 0.5;
  const CadSurface cad = mesh_cad_surface(data("plate_slot.step"), options);
  EXPECT_EQ(cad.record.format, "step");
  EXPECT_EQ(cad.record.volumes, 1u);
  EXPECT_EQ(cad.record.faces, 10u);
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
  EXPECT_EQ(cad.record.quads, 3 * cad.record.triangles);
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

TEST(Cad, AnOpenShellIsNotAClosedSolid) {
  SKIP_WITHOUT_GMSH();
  try {
    (void)mesh_cad_surface(data("open_shell.step"));
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("not a closed solid"));
    EXPECT_THAT(e.what(), HasSubstr("5 faces"));
  }
}

TEST(Cad, AClosedShellWithoutAVolumeIsSewnIntoASolid) {
  SKIP_WITHOUT_GMSH();
  CadOptions options;
  options.size = 0.5;
  const CadSurface cad = mesh_cad_surface(data("closed_shell.step"), options);
  EXPECT_EQ(cad.record.volumes, 1u);
  ASSERT_FALSE(cad.record.warnings.empty());
  EXPECT_THAT(cad.record.warnings.front(), HasSubstr("sewn into 1 solid"));
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  const MeshResult r = mesh_cad(cad, true);
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.mesh.complex.hexes.size(), 8u);
}

TEST(Cad, GarbageIsRefusedWithTheReadersReason) {
  SKIP_WITHOUT_GMSH();
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
