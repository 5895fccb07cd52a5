// Harmonic placement (`stcweave/primal/recover.hpp`): the conjugate-gradient solve puts a
// woven box on its grid, agrees with an independent direct solve of the same Laplacian on
// unstructured weaves, keeps a coordinate that is zero on every fixed node exactly zero,
// repeats bit for bit, and refuses a free node that is on no hex edge.
#include "stcweave/primal/recover.hpp"

#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <array>
#include <set>
#include <utility>
#include <vector>

#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/weave.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

/// The harmonic positions of the free nodes (ids >= num_fixed) by a sparse Cholesky
/// factorisation of the uniform graph Laplacian, built here from the hexes' twelve edges
/// without the library's edge list.
Points direct_harmonic(const HexMesh& mesh, std::size_t num_fixed) {
  static constexpr int kEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                        {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  std::set<std::pair<std::int32_t, std::int32_t>> edges;
  for (const stc::Hex& h : mesh.complex.hexes) {
    for (const auto& e : kEdges) {
      std::int32_t a = h[static_cast<std::size_t>(e[0])].value();
      std::int32_t b = h[static_cast<std::size_t>(e[1])].value();
      if (a > b) std::swap(a, b);
      edges.emplace(a, b);
    }
  }
  const auto n = static_cast<Eigen::Index>(mesh.points.rows());
  const auto f = static_cast<Eigen::Index>(num_fixed);
  std::vector<Eigen::Triplet<double>> t;
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(n - f, 3);
  for (const auto& [a, b] : edges) {
    const bool free_a = a >= f;
    const bool free_b = b >= f;
    if (free_a) t.emplace_back(a - f, a - f, 1.0);
    if (free_b) t.emplace_back(b - f, b - f, 1.0);
    if (free_a && free_b) {
      t.emplace_back(a - f, b - f, -1.0);
      t.emplace_back(b - f, a - f, -1.0);
    } else if (free_a) {
      rhs.row(a - f) += mesh.points.row(b);
    } else if (free_b) {
      rhs.row(b - f) += mesh.points.row(a);
    }
  }
  Eigen::SparseMatrix<double> l(n - f, n - f);
  l.setFromTriplets(t.begin(), t.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(l);
  EXPECT_EQ(solver.info(), Eigen::Success);
  Points out = mesh.points;
  out.bottomRows(n - f) = solver.solve(rhs);
  return out;
}

double diagonal(const Points& p) {
  return (p.colwise().maxCoeff() - p.colwise().minCoeff()).norm();
}

TEST(HarmonicPositions, PutAWovenBoxOnItsGrid) {
  // Every interior node of a structured grid is the mean of its six neighbours, so the grid
  // is the harmonic placement: every hex a box, whatever the spacing per axis.
  const SurfaceMesh s = test::box_surface(3, 4, 2, 1.0, 0.5, 2.0);
  const weave::WeaveResult woven = weave::weave(s.surface);
  HarmonicReport r;
  const HexMesh mesh = recover_hex_mesh(s.points, woven, &r);
  EXPECT_EQ(r.free_nodes, woven.complex.num_nodes - woven.num_input_nodes);
  EXPECT_EQ(r.free_nodes, 2u * 3u * 1u);
  EXPECT_GT(r.iterations, 0u);
  EXPECT_LE(r.residual, 1e-10);
  EXPECT_NEAR(summarize_quality(mesh).min_scaled_jacobian, 1.0, 1e-8);
}

/// A 4 x 4 x 3 block of voxels with a 2 x 2 x 2 notch cut from one top corner: a concave
/// edge and corner, and interior nodes around them that are not on a grid line's mean.
std::vector<std::array<int, 3>> notched_block() {
  std::vector<std::array<int, 3>> cells;
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 4; ++i) {
        if (!(i >= 2 && j >= 2 && k >= 1)) cells.push_back({i, j, k});
      }
    }
  }
  return cells;
}

TEST(HarmonicPositions, AgreeWithADirectSolve) {
  const std::vector<SurfaceMesh> surfaces = {test::rhombic_dodecahedron(),
                                             test::voxel_surface(notched_block()),
                                             test::box_surface(6, 5, 4, 1.0, 2.0, 0.7)};
  for (const SurfaceMesh& s : surfaces) {
    const weave::WeaveResult woven = weave::weave(s.surface);
    ASSERT_GT(woven.complex.num_nodes, woven.num_input_nodes);
    HarmonicReport r;
    const HexMesh mesh = recover_hex_mesh(s.points, woven, &r);
    const Points direct = direct_harmonic(mesh, woven.num_input_nodes);
    const double worst = (mesh.points - direct).cwiseAbs().maxCoeff();
    EXPECT_LE(worst, 1e-8 * diagonal(direct))
        << woven.complex.hexes.size() << " hexes, " << r.iterations << " iterations";
    // The input nodes keep their coordinates exactly.
    EXPECT_EQ(mesh.points.topRows(s.points.rows()), s.points);
  }
}

TEST(HarmonicPositions, KeepAZeroCoordinateZero) {
  // A coordinate that is 0 on every fixed node has the zero right-hand side: its column is
  // solved as exactly 0 while the other two are iterated.
  SurfaceMesh s = test::box_surface(3, 3, 3);
  const weave::WeaveResult woven = weave::weave(s.surface);
  HexMesh mesh = recover_hex_mesh(s.points, woven);
  mesh.points.col(2).setZero();
  mesh.points.bottomRows(mesh.points.rows() - s.points.rows()).setConstant(7.0);
  const HarmonicReport r = harmonic_positions(mesh, woven.num_input_nodes);
  EXPECT_GT(r.iterations, 0u);
  for (Eigen::Index v = 0; v < mesh.points.rows(); ++v) EXPECT_EQ(mesh.points(v, 2), 0.0);
  EXPECT_LE((mesh.points.leftCols(2) - direct_harmonic(mesh, woven.num_input_nodes).leftCols(2))
                .cwiseAbs()
                .maxCoeff(),
            1e-8 * 3.0);
}

TEST(HarmonicPositions, RepeatBitForBit) {
  const SurfaceMesh s = test::voxel_surface(notched_block());
  const weave::WeaveResult woven = weave::weave(s.surface);
  const HexMesh first = recover_hex_mesh(s.points, woven);
  HexMesh second = recover_hex_mesh(s.points, woven);
  EXPECT_EQ(first.points, second.points);
  // Starting again from the answer does not move it further than the tolerance allows.
  harmonic_positions(second, woven.num_input_nodes);
  EXPECT_LE((first.points - second.points).cwiseAbs().maxCoeff(), 1e-8 * diagonal(first.points));
}

TEST(HarmonicPositions, RefuseAFreeNodeOnNoHexEdge) {
  HexMesh mesh = test::box_hexes(1, 1, 1);
  mesh.points.conservativeResize(9, 3);
  mesh.points.row(8) << 0.5, 0.5, 0.5;
  mesh.complex.num_nodes = 9;
  try {
    harmonic_positions(mesh, 8);
    FAIL() << "a free node on no hex edge was placed";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("n8 is on no hex edge"), std::string::npos) << e.what();
  }
}

TEST(HarmonicPositions, LeaveAMeshWithoutFreeNodesAlone) {
  HexMesh mesh = test::box_hexes(2, 1, 1);
  const Points before = mesh.points;
  const HarmonicReport r = harmonic_positions(mesh, static_cast<std::size_t>(mesh.points.rows()));
  EXPECT_EQ(r.free_nodes, 0u);
  EXPECT_EQ(r.iterations, 0u);
  EXPECT_EQ(mesh.points, before);
}

}  // namespace
}  // namespace stcweave::primal
