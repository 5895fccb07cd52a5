// Splitting one-solid CAD parts with a handle into blocks of four-cornered faces
// (primal/src/cad_split.cpp): a torus into the 20 blocks of a revolved O-grid, a plate with a
// through-hole cut by half-planes through the hole's axis; both then take the transfinite
// recipe, weave through the disc cut of their handle and stay on the solid's surface. A plate
// with a blind hole (genus 0) is left whole and still meshed.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
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

/// Distance to the torus of radius 1 and tube radius 0.4 around the axis `axis` (unit)
/// through `centre`.
double torus_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& centre,
                      const Eigen::Vector3d& axis) {
  const Eigen::Vector3d d = p - centre;
  const double along = d.dot(axis);
  const double across = (d - along * axis).norm();
  return std::abs(std::hypot(across - 1.0, along) - 0.4);
}

/// Largest distance of the surface's nodes to `distance`'s surface.
template <typename Distance>
double max_node_distance(const MeshFile& surface, Distance distance) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < surface.points.rows(); ++i)
    worst = std::max(worst, distance(Eigen::Vector3d(surface.points.row(i).transpose())));
  return worst;
}

TEST(CadSplitHandles, OneSolidTorusBecomesTwentyBlocksOfARevolvedOGrid) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = cad_surface({CadPrimitive::Kind::Torus, 1.0, 0.4}, 0.35);
  EXPECT_THAT(cad.record.split, HasSubstr("a torus, split as 20 blocks"));
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_EQ(cad.record.volumes, 1u);  // the file's solids, before the split
  EXPECT_EQ(cad.record.faces, 16u);   // 4 ring pieces in each of 4 quarter turns
  EXPECT_EQ(cad.record.structured_faces, 16u);
  EXPECT_TRUE(cad.record.warnings.empty());
  const SurfaceDiagnosis d = diagnose(cad.file);
  EXPECT_EQ(d.genus, 1);
  EXPECT_EQ(d.self_intersecting_loops, 0u);
  const MeshResult r = mesh_cad(cad, true);
  ASSERT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_GT(r.quality.min_scaled_jacobian, 0.3);
  const Eigen::Vector3d z(0, 0, 1);
  EXPECT_LT(max_boundary_distance(r,
                                  [&](const Eigen::Vector3d& p) {
                                    return torus_distance(p, {0, 0, 0}, z);
                                  }),
            1e-6);
}

TEST(CadSplitHandles, ATiltedTorusIsSplitAroundItsOwnAxisAndCentre) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  // data/torus_tilted.step: axis (2, -1, 2) / 3 through (0.3, -0.2, 0.5), found from the
  // solid's centre of mass and matrix of inertia.
  const CadSurface cad =
      mesh_cad_surface(test::repo_data("torus_tilted.step"), test::cad_options(0.25));
  EXPECT_THAT(cad.record.split, HasSubstr("a torus"));
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_EQ(diagnose(cad.file).genus, 1);
  const Eigen::Vector3d centre(0.3, -0.2, 0.5);
  const Eigen::Vector3d axis = Eigen::Vector3d(2, -1, 2) / 3.0;
  EXPECT_GT(cad.file.points.rows(), 0);
  EXPECT_LT(
      max_node_distance(cad.file,
                        [&](const Eigen::Vector3d& p) { return torus_distance(p, centre, axis); }),
      1e-6);
}

TEST(CadSplitHandles, PlateWithAHoleIsCutByHalfPlanesThroughTheHolesAxis) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = cad_surface({CadPrimitive::Kind::PlateWithHole, 4.0, 2.0, 0.5}, 0.25);
  // Four half-planes through the plate's corners and one through the hole's seam.
  EXPECT_THAT(cad.record.split, HasSubstr("cut by 5 half-planes through the hole's axis into 5"));
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_EQ(cad.record.volumes, 1u);
  EXPECT_EQ(cad.record.faces, 20u);  // per block: a top, a bottom, a side, a piece of the hole
  EXPECT_EQ(cad.record.structured_faces, 20u);
  const SurfaceDiagnosis d = diagnose(cad.file);
  EXPECT_EQ(d.genus, 1);
  EXPECT_EQ(d.self_intersecting_loops, 0u);
  const MeshResult r = mesh_cad(cad, true);
  ASSERT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_GT(r.quality.min_scaled_jacobian, 0.3);
  // Every boundary node is on the plate's box or on the hole's cylinder.
  const double worst = max_boundary_distance(r, [](const Eigen::Vector3d& p) {
    const double radial = std::hypot(p.x() - 2.0, p.y() - 1.0);
    const double outside =
        std::max({-p.x(), p.x() - 4.0, -p.y(), p.y() - 2.0, -p.z(), p.z() - 0.5, 0.5 - radial});
    const double on_box = std::min({std::abs(p.x()), std::abs(p.x() - 4.0), std::abs(p.y()),
                                    std::abs(p.y() - 2.0), std::abs(p.z()), std::abs(p.z() - 0.5)});
    return std::max(std::max(0.0, outside), std::min(on_box, std::abs(radial - 0.5)));
  });
  EXPECT_LT(worst, 1e-9);
}

TEST(CadSplitHandles, ATiltedPlateWithAnOffCentreHoleIsCutAroundTheHole) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  // data/plate_hole_tilted.step: hole of radius 0.4 at (1.3, 0.8) of a 4 x 2 x 0.5 plate,
  // turned so that its normal is (1, 2, 2) / 3.
  const CadSurface cad =
      mesh_cad_surface(test::repo_data("plate_hole_tilted.step"), test::cad_options(0.25));
  EXPECT_THAT(cad.record.split, HasSubstr("half-planes through the hole's axis"));
  EXPECT_EQ(cad.record.recipe, CadRecipe::Transfinite);
  EXPECT_EQ(cad.record.structured_faces, cad.record.faces);
  EXPECT_EQ(diagnose(cad.file).genus, 1);
  EXPECT_LT(cad.record.max_cad_distance, 1e-7);
  const MeshResult r = mesh_cad(cad, true);
  ASSERT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.quality.inverted, 0u);
}

TEST(CadSplitHandles, ABlindHoleIsLeftWholeAndStillMeshed) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  // data/plate_blind_hole.step: the hole has a bottom (genus 0); half-planes would leave
  // three-cornered sectors of it, so the split leaves the solid whole, without a warning.
  const CadSurface cad =
      mesh_cad_surface(test::repo_data("plate_blind_hole.step"), test::cad_options(0.25));
  EXPECT_EQ(cad.record.split, "");
  for (const std::string& w : cad.record.warnings)
    EXPECT_THAT(w, ::testing::Not(HasSubstr("not split")));
  EXPECT_EQ(diagnose(cad.file).genus, 0);
  const MeshResult r = mesh_cad(cad, true);
  ASSERT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.quality.inverted, 0u);
}

TEST(CadSplitHandles, WithoutTheSplitTheOneSolidTorusStaysOneFace) {
  STCWEAVE_SKIP_WITHOUT_GMSH();
  const CadSurface cad = cad_surface({CadPrimitive::Kind::Torus, 1.0, 0.4}, 0.3, CadRecipe::Auto,
                                     /*split=*/false);
  EXPECT_EQ(cad.record.split, "");
  EXPECT_EQ(cad.record.faces, 1u);
  EXPECT_EQ(cad.record.recipe, CadRecipe::TriangleSplit);
}

}  // namespace
}  // namespace stcweave::primal
