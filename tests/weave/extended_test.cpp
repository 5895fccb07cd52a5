// The rule set `extended` (seed sect. 4-7) on shapes whose answer is known: structured boxes
// with graded spacing and the L-block give their structured meshes, and the seed's Fig. 5 bars
// give valid complexes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <tuple>
#include <vector>

#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/primal/pipeline.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/validate.hpp"
#include "stcweave/weave/weave.hpp"
#include "support/compare.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

WeaveOptions extended_options() {
  WeaveOptions o;
  o.rules = RuleSet::Extended;
  o.trace = true;
  o.check = true;
  return o;
}

WeaveResult weave_extended(const primal::SurfaceMesh& s, const WeaveOptions& options) {
  return weave(s.surface, options, primal::dihedral_angles(s));
}

/// The woven complex with the input coordinates (interior nodes at the origin: the comparison
/// reads only boundary coordinates).
primal::HexMesh hex_mesh_of(const primal::SurfaceMesh& s, const WeaveResult& r) {
  primal::HexMesh m;
  m.complex = r.complex;
  m.points = primal::Points::Zero(static_cast<Eigen::Index>(r.complex.num_nodes), 3);
  m.points.topRows(s.points.rows()) = s.points;
  return m;
}

void expect_valid(const primal::SurfaceMesh& s, const WeaveResult& r) {
  const auto report = stc::validate_hex_complex(r.complex, &s.surface);
  EXPECT_TRUE(report.valid) << report.summary();
}

// ---------------------------------------------------------------------------------------
// the comparison helper itself

TEST(SameConnectivity, AcceptsARenumberedCopy) {
  primal::HexMesh ref = test::box_hexes(3, 2, 2);
  primal::HexMesh copy = ref;
  // interior nodes of a 3x2x2 box: (1,1,1) and (2,1,1), ids 17 and 18; swap them, reverse
  // the hex order and rotate each hex to another of its orderings (top and bottom swapped)
  for (auto& h : copy.complex.hexes) {
    for (auto& n : h)
      if (n.value() == 17 || n.value() == 18) n = NodeId(35 - n.value());
    h = {h[4], h[7], h[6], h[5], h[0], h[3], h[2], h[1]};
  }
  copy.points.row(17).swap(copy.points.row(18));
  std::reverse(copy.complex.hexes.begin(), copy.complex.hexes.end());
  std::string why;
  EXPECT_TRUE(test::same_connectivity(copy, ref, &why)) << why;
}

TEST(SameConnectivity, RejectsAnotherComplexOnTheSameBoundary) {
  // Two boundary nodes of the 2x1x1 box exchange their places: the same set of boundary
  // coordinates, but the nodes play different roles. And a different hex count.
  const primal::HexMesh ref = test::box_hexes(2, 1, 1);
  primal::HexMesh moved = ref;
  moved.points.row(0).swap(moved.points.row(2));  // two boundary nodes exchanged
  std::string why;
  EXPECT_FALSE(test::same_connectivity(moved, ref, &why));
  EXPECT_FALSE(why.empty());
  EXPECT_FALSE(test::same_connectivity(test::box_hexes(2, 2, 1), test::box_hexes(2, 1, 1)));
}

// ---------------------------------------------------------------------------------------
// structured answers

/// The a x b x c box with coordinates graded geometrically (ratios 1.5, 0.7, 1.3 along x,
/// y, z), so that no two cells have the same size along an axis.
primal::HexMesh graded_box(int a, int b, int c) {
  primal::HexMesh m = test::box_hexes(a, b, c);
  const auto graded = [](double i, double ratio) { return (std::pow(ratio, i) - 1) / (ratio - 1); };
  for (Eigen::Index n = 0; n < m.points.rows(); ++n)
    m.points.row(n) << graded(m.points(n, 0), 1.5), graded(m.points(n, 1), 0.7),
        graded(m.points(n, 2), 1.3);
  return m;
}

class GradedBox : public ::testing::TestWithParam<std::tuple<int, int, int>> {};

TEST_P(GradedBox, GivesTheStructuredMesh) {
  const auto [a, b, c] = GetParam();
  const primal::HexMesh reference = graded_box(a, b, c);
  const primal::SurfaceMesh surface = test::boundary_of(reference);
  WeaveOptions options = extended_options();
  options.check = a * b * c <= 27;
  const WeaveResult r = weave_extended(surface, options);
  EXPECT_EQ(r.complex.hexes.size(), static_cast<std::size_t>(a * b * c));
  expect_valid(surface, r);
  std::string why;
  EXPECT_TRUE(test::same_connectivity(hex_mesh_of(surface, r), reference, &why)) << why;
}

INSTANTIATE_TEST_SUITE_P(UpTo4x3x5, GradedBox,
                         ::testing::Values(std::make_tuple(1, 1, 2), std::make_tuple(2, 2, 2),
                                           std::make_tuple(3, 2, 1), std::make_tuple(1, 3, 4),
                                           std::make_tuple(3, 3, 3), std::make_tuple(4, 3, 5)));

TEST(Extended, LBlockGivesTheStructuredMesh) {
  const primal::HexMesh reference = test::voxel_hexes(test::lblock_cells());
  const primal::SurfaceMesh surface = test::boundary_of(reference);
  const WeaveResult r = weave_extended(surface, extended_options());
  EXPECT_EQ(r.complex.hexes.size(), 10u);
  expect_valid(surface, r);
  std::string why;
  EXPECT_TRUE(test::same_connectivity(hex_mesh_of(surface, r), reference, &why)) << why;
}

// ---------------------------------------------------------------------------------------
// the seed's Fig. 5: one 14-quad surface (the 1 x 1 x 3 bar), five solids

using Section = std::array<Eigen::RowVector3d, 4>;

/// A cross-section of unit depth (y from 0 to 1) spanning p = (x, z) to q = (x, z): its first
/// corner is p at y = 0, its second q at y = 0.
Section section(double px, double pz, double qx, double qz) {
  return {Eigen::RowVector3d(px, 0, pz), Eigen::RowVector3d(qx, 0, qz),
          Eigen::RowVector3d(qx, 1, qz), Eigen::RowVector3d(px, 1, pz)};
}

/// The five embeddings. Each bend is mitred: the section between two arms joins the outer
/// corner to the inner one, so every hex of the column is convex and the arms are unit wide.
std::vector<std::pair<std::string, primal::SurfaceMesh>> figure5_bars() {
  std::vector<std::pair<std::string, primal::SurfaceMesh>> bars;
  bars.emplace_back("straight", test::bar_surface({section(0, 0, 1, 0), section(0, 1, 1, 1),
                                                   section(0, 2, 1, 2), section(0, 3, 1, 3)}));
  // up x in [0,1] to z = 3, then right along z in [2,3] to x = 3
  bars.emplace_back("L", test::bar_surface({section(0, 0, 1, 0), section(0, 3, 1, 2),
                                            section(2, 3, 2, 2), section(3, 3, 3, 2)}));
  // up, right, down: arms x in [0,1] and [2,3], bridge z in [2,3]
  bars.emplace_back("U", test::bar_surface({section(0, 0, 1, 0), section(0, 3, 1, 2),
                                            section(3, 3, 2, 2), section(3, 0, 2, 0)}));
  // up, right, up again: x in [0,1] to z = 3, z in [2,3] to x = 3, x in [2,3] to z = 5
  bars.emplace_back("Z", test::bar_surface({section(0, 0, 1, 0), section(0, 3, 1, 2),
                                            section(2, 3, 3, 2), section(2, 5, 3, 5)}));
  // straight, but the last cell folded in along its length: its two sections are darts (the
  // fourth corner pushed inside the square), so the end face is a non-convex quad and the
  // edge joining the two reflex corners is a non-convex edge of the solid
  Section dart2 = section(0, 2, 1, 2), dart3 = section(0, 3, 1, 3);
  dart2[3] << 0.75, 0.25, 2;
  dart3[3] << 0.75, 0.25, 3;
  bars.emplace_back("folded",
                    test::bar_surface({section(0, 0, 1, 0), section(0, 1, 1, 1), dart2, dart3}));
  return bars;
}

primal::MeshFile file_of(const primal::SurfaceMesh& s, const std::string& name) {
  primal::MeshFile f;
  f.path = name;
  f.format = "memory";
  f.points = s.points;
  f.quads = s.surface.quads;
  return f;
}

TEST(Extended, SeedFigure5BarsGiveValidComplexes) {
  const stc::QuadSurface topology = test::box_surface(1, 1, 3).surface;
  for (const auto& [name, bar] : figure5_bars()) {
    SCOPED_TRACE(name);
    ASSERT_EQ(bar.surface.quads, topology.quads) << "one topology, five embeddings";
    primal::MeshOptions options;
    options.untangle = false;
    options.weave.check = true;
    const primal::MeshResult r = primal::mesh_file(file_of(bar, name), options);
    EXPECT_EQ(r.orientation.flipped_quads, 0u) << "the embedding must be outward";
    EXPECT_TRUE(r.validation.valid) << r.validation.summary();
    RecordProperty("hexes_" + name, static_cast<int>(r.mesh.complex.hexes.size()));
    if (name == "straight") EXPECT_EQ(r.mesh.complex.hexes.size(), 3u);
  }
}

TEST(Extended, SeedFigure5EmbeddingsDifferInGeometry) {
  // The five solids must really differ where the rules look: the L, U and Z have non-convex
  // edges (their inner corners), the folded bar one (along its folded cell), the straight
  // bar none.
  for (const auto& [name, bar] : figure5_bars()) {
    SCOPED_TRACE(name);
    const auto angles = primal::dihedral_angles(bar);
    double widest = 0.0;
    for (const auto& quad : angles)
      for (double a : quad) widest = std::max(widest, a);
    if (name == "straight")
      EXPECT_LT(widest, 181.0);
    else
      EXPECT_GT(widest, 190.0);
  }
}

}  // namespace
}  // namespace stcweave::weave
