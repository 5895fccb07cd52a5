#include "stcweave/primal/pillow.hpp"

#include <gtest/gtest.h>

#include "stcweave/primal/pipeline.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/validate.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

using test::file_of;

/// A box's hex mesh with its boundary nodes renumbered first (as the pipeline numbers them),
/// and that boundary.
struct Numbered {
  HexMesh mesh;
  SurfaceMesh boundary;
};

Numbered boundary_first(const HexMesh& in) {
  const SurfaceMesh b = test::boundary_of(in);
  // boundary_of compacts nodes in increasing order of their hex-mesh ids: map them back.
  std::vector<NodeId> to_new(static_cast<std::size_t>(in.points.rows()));
  std::vector<bool> on(to_new.size(), false);
  std::size_t next = 0;
  for (std::size_t v = 0; v < to_new.size(); ++v) {
    const Eigen::RowVector3d p = in.points.row(static_cast<Eigen::Index>(v));
    for (Eigen::Index w = 0; w < b.points.rows(); ++w)
      if ((b.points.row(w) - p).norm() < 1e-12) {
        to_new[v] = NodeId(static_cast<std::size_t>(w));
        on[v] = true;
      }
  }
  next = static_cast<std::size_t>(b.points.rows());
  Numbered r;
  r.boundary = b;
  r.mesh.points.resize(in.points.rows(), 3);
  for (std::size_t v = 0; v < to_new.size(); ++v) {
    if (!on[v]) to_new[v] = NodeId(next++);
    r.mesh.points.row(static_cast<Eigen::Index>(to_new[v].index())) =
        in.points.row(static_cast<Eigen::Index>(v));
  }
  r.mesh.complex.num_nodes = to_new.size();
  for (stc::Hex h : in.complex.hexes) {
    for (NodeId& v : h) v = to_new[v.index()];
    r.mesh.complex.hexes.push_back(h);
  }
  return r;
}

TEST(Pillow, CubeAlwaysGivesSevenHexesWithTheCubeAsBoundary) {
  Numbered cube = boundary_first(test::box_hexes(1, 1, 1));
  PillowOptions options;
  options.mode = PillowMode::Always;
  const PillowReport r = pillow(cube.mesh, cube.boundary.surface, options);
  EXPECT_TRUE(r.applied);
  EXPECT_EQ(r.shells, 1u);
  EXPECT_EQ(r.shells_pillowed, 1u);
  EXPECT_EQ(r.nodes_added, 8u);
  EXPECT_EQ(r.hexes_added, 6u);
  EXPECT_EQ(cube.mesh.complex.hexes.size(), 7u);
  EXPECT_EQ(cube.mesh.complex.num_nodes, 16u);
  const auto v = stc::validate_hex_complex(cube.mesh.complex, &cube.boundary.surface);
  EXPECT_TRUE(v.valid) << v.summary();
  // Boundary nodes keep their coordinates; the copies start strictly inside.
  for (Eigen::Index n = 0; n < 8; ++n)
    EXPECT_EQ(cube.mesh.points.row(n), cube.boundary.points.row(n));
  for (Eigen::Index n = 8; n < 16; ++n)
    for (int c = 0; c < 3; ++c) {
      EXPECT_GT(cube.mesh.points(n, c), 0.0);
      EXPECT_LT(cube.mesh.points(n, c), 1.0);
    }
  // Offset along the vertex normal (the cube diagonal) by a quarter of the edge length.
  EXPECT_NEAR((cube.mesh.points.row(8) - cube.mesh.points.row(0)).norm(), 0.25, 1e-12);
  const QualitySummary q = summarize_quality(cube.mesh);
  EXPECT_EQ(q.inverted, 0u);
}

TEST(Pillow, AutoLeavesABoxAlone) {
  Numbered box = boundary_first(test::box_hexes(3, 2, 2));
  const std::size_t hexes = box.mesh.complex.hexes.size();
  const Points before = box.mesh.points;
  const PillowReport r = pillow(box.mesh, box.boundary.surface);
  EXPECT_FALSE(r.applied) << r.reason;
  EXPECT_EQ(r.mode, PillowMode::Auto);
  EXPECT_GT(r.fixed_corners, 0u) << "the box's corner and edge hexes have fixed corners";
  EXPECT_EQ(r.bad_fixed_corners, 0u);
  EXPECT_NEAR(r.worst_fixed_corner, 1.0, 1e-12);
  EXPECT_EQ(box.mesh.complex.hexes.size(), hexes);
  EXPECT_EQ(box.mesh.points, before);
}

TEST(Pillow, AutoPillowsAHexWithTwoFacesOnOneFlatStretch) {
  // A single hex whose side faces 0-1-5-4 and 1-2-6-5 meet at an almost flat edge (about 175
  // degrees): nodes (1,0,z) pulled in to (0.52,0.48,z), near the diagonal from (0,0) to (1,1).
  Numbered cube = boundary_first(test::box_hexes(1, 1, 1));
  for (Eigen::Index n = 0; n < cube.boundary.points.rows(); ++n) {
    const Eigen::RowVector3d p = cube.boundary.points.row(n);
    if (std::abs(p.x() - 1.0) < 1e-12 && std::abs(p.y()) < 1e-12) {
      cube.boundary.points(n, 0) = 0.52;
      cube.boundary.points(n, 1) = 0.48;
      cube.mesh.points.row(n) = cube.boundary.points.row(n);
    }
  }
  const PillowReport assessed = assess_pillow(cube.mesh, 8);
  EXPECT_GT(assessed.bad_fixed_corners, 0u);
  const PillowReport r = pillow(cube.mesh, cube.boundary.surface);
  EXPECT_TRUE(r.applied) << r.reason;
  EXPECT_EQ(cube.mesh.complex.hexes.size(), 7u);
  EXPECT_NE(r.reason.find("auto: pillowed"), std::string::npos) << r.reason;
  const auto v = stc::validate_hex_complex(cube.mesh.complex, &cube.boundary.surface);
  EXPECT_TRUE(v.valid) << v.summary();
}

TEST(Pillow, NeverChangesNothing) {
  Numbered cube = boundary_first(test::box_hexes(1, 1, 1));
  PillowOptions options;
  options.mode = PillowMode::Never;
  options.min_fixed_corner = 2.0;  // every corner would be "bad"
  const PillowReport r = pillow(cube.mesh, cube.boundary.surface, options);
  EXPECT_FALSE(r.applied);
  EXPECT_EQ(r.bad_fixed_corners, 8u);
  EXPECT_EQ(cube.mesh.complex.hexes.size(), 1u);
}

TEST(Pillow, OnlyTheShellThatNeedsItIsPillowed) {
  // Two separate one-hex cubes, each its own shell.
  Numbered a = boundary_first(test::box_hexes(1, 1, 1));
  HexMesh two;
  two.points.resize(16, 3);
  two.points.topRows(8) = a.mesh.points;
  two.points.bottomRows(8) = a.mesh.points;
  two.points.bottomRows(8).col(0).array() += 3.0;
  SurfaceMesh boundary;
  boundary.surface.num_nodes = 16;
  boundary.surface.quads = a.boundary.surface.quads;
  for (stc::Quad q : a.boundary.surface.quads) {
    for (NodeId& v : q) v = NodeId(v.index() + 8);
    boundary.surface.quads.push_back(q);
  }
  // Remap: shell 1's nodes are 8..15 in the boundary; hexes use them directly.
  two.complex.num_nodes = 16;
  two.complex.hexes.push_back(a.mesh.complex.hexes[0]);
  stc::Hex h = a.mesh.complex.hexes[0];
  for (NodeId& v : h) v = NodeId(v.index() + 8);
  two.complex.hexes.push_back(h);
  // The second cube gets the almost flat edge of the test above.
  for (Eigen::Index n = 8; n < 16; ++n)
    if (std::abs(two.points(n, 0) - 4.0) < 1e-12 && std::abs(two.points(n, 1)) < 1e-12) {
      two.points(n, 0) = 3.52;
      two.points(n, 1) = 0.48;
    }
  const PillowReport r = pillow(two, boundary.surface);
  EXPECT_EQ(r.shells, 2u);
  EXPECT_EQ(r.shells_pillowed, 1u) << r.reason;
  EXPECT_EQ(r.nodes_added, 8u);
  EXPECT_EQ(two.complex.hexes.size(), 8u);
  const auto v = stc::validate_hex_complex(two.complex, &boundary.surface);
  EXPECT_TRUE(v.valid) << v.summary();
  EXPECT_EQ(two.complex.hexes[0], a.mesh.complex.hexes[0]) << "the good cube is untouched";
}

TEST(Pillow, RefusesABadOffsetAndMismatchedPoints) {
  Numbered cube = boundary_first(test::box_hexes(1, 1, 1));
  PillowOptions options;
  options.offset = 1.5;
  EXPECT_THROW((void)pillow(cube.mesh, cube.boundary.surface, options), InvalidInput);
  cube.mesh.points.conservativeResize(7, 3);
  EXPECT_THROW((void)pillow(cube.mesh, cube.boundary.surface), InvalidInput);
}

TEST(Pillow, ModeNamesRoundTrip) {
  for (const PillowMode m : {PillowMode::Auto, PillowMode::Always, PillowMode::Never})
    EXPECT_EQ(pillow_mode_from_name(to_string(m)), m);
  EXPECT_THROW((void)pillow_mode_from_name("sometimes"), InvalidInput);
}

TEST(PillowPipeline, CubeAlwaysGivesSevenValidUntangledHexes) {
  MeshOptions options;
  options.pillow.mode = PillowMode::Always;
  const MeshResult r = mesh_file(file_of(test::box_surface(1, 1, 1), "cube"), options);
  EXPECT_TRUE(r.pillow.applied);
  EXPECT_EQ(r.mesh.complex.hexes.size(), 7u);
  EXPECT_EQ(r.woven.complex.hexes.size(), 1u) << "the weave's own result is kept";
  EXPECT_TRUE(r.validation.valid) << r.validation.summary();
  EXPECT_EQ(r.validation.hexes, 7u) << "the validation is that of the pillowed complex";
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_GT(r.quality.min_scaled_jacobian, 0.3);
}

TEST(PillowPipeline, AutoLeavesBoxesStructured) {
  for (const auto& [a, b, c] : std::vector<std::array<int, 3>>{{1, 1, 1}, {3, 3, 3}, {4, 2, 1}}) {
    SCOPED_TRACE(std::to_string(a) + "x" + std::to_string(b) + "x" + std::to_string(c));
    const MeshResult r = mesh_file(file_of(test::box_surface(a, b, c), "box"));
    EXPECT_FALSE(r.pillow.applied) << r.pillow.reason;
    EXPECT_EQ(r.mesh.complex.hexes.size(), static_cast<std::size_t>(a * b * c));
    EXPECT_NEAR(r.quality.min_scaled_jacobian, 1.0, 1e-6);
  }
}

}  // namespace
}  // namespace stcweave::primal
