#pragma once
/// \file
/// Helpers shared by the positioning tests, the corpus positioning test and the benchmark:
/// the boundary-node mask of a hex mesh, seeded scrambling of the interior nodes, and a
/// bent box whose harmonic placement is tangled.

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::test {

/// true for the nodes of the faces used by one hex (the boundary of the mesh).
inline std::vector<bool> boundary_nodes(const primal::HexMesh& mesh) {
  std::map<std::array<std::int32_t, 4>, int> count;
  for (const stc::Hex& h : mesh.complex.hexes)
    for (const auto& f : stc::kHexFaces) {
      std::array<std::int32_t, 4> key{};
      for (std::size_t k = 0; k < 4; ++k) key[k] = h[static_cast<std::size_t>(f[k])].value();
      std::sort(key.begin(), key.end());
      ++count[key];
    }
  std::vector<bool> on(static_cast<std::size_t>(mesh.points.rows()), false);
  for (const auto& [key, c] : count)
    if (c == 1)
      for (std::int32_t v : key) on[static_cast<std::size_t>(v)] = true;
  return on;
}

/// `mesh` with its nodes renumbered so that the boundary nodes come first (in their old
/// order), as the pipeline numbers them; returns the number of boundary nodes.
inline std::size_t boundary_first(primal::HexMesh& mesh) {
  const std::vector<bool> on = boundary_nodes(mesh);
  std::vector<std::int32_t> to(on.size());
  std::int32_t next = 0;
  for (std::size_t v = 0; v < on.size(); ++v)
    if (on[v]) to[v] = next++;
  const auto num_boundary = static_cast<std::size_t>(next);
  for (std::size_t v = 0; v < on.size(); ++v)
    if (!on[v]) to[v] = next++;
  primal::Points points(mesh.points.rows(), 3);
  for (std::size_t v = 0; v < on.size(); ++v)
    points.row(to[v]) = mesh.points.row(static_cast<Eigen::Index>(v));
  mesh.points = points;
  for (stc::Hex& h : mesh.complex.hexes)
    for (NodeId& v : h) v = NodeId(to[v.index()]);
  return num_boundary;
}

/// Moves every node with `fixed[v] == false` that some hex uses by a random vector of
/// length up to `fraction` times its shortest incident hex edge (uniform in the ball),
/// with a seeded generator (deterministic across platforms: no std distributions).
inline void scramble(primal::HexMesh& mesh, const std::vector<bool>& fixed, double fraction,
                     std::uint64_t seed) {
  const auto n = static_cast<std::size_t>(mesh.points.rows());
  std::vector<double> shortest(n, std::numeric_limits<double>::infinity());
  for (const stc::Hex& h : mesh.complex.hexes)
    for (const auto& e : stc::kHexEdges) {
      const auto a = h[static_cast<std::size_t>(e[0])].index();
      const auto b = h[static_cast<std::size_t>(e[1])].index();
      const double l = (mesh.points.row(static_cast<Eigen::Index>(a)) -
                        mesh.points.row(static_cast<Eigen::Index>(b)))
                           .norm();
      shortest[a] = std::min(shortest[a], l);
      shortest[b] = std::min(shortest[b], l);
    }
  std::mt19937_64 random(seed);
  const auto uniform = [&random] {  // in [-1, 1)
    return static_cast<double>(random() >> 11) * (2.0 / 9007199254740992.0) - 1.0;
  };
  const primal::Points original = mesh.points;
  for (std::size_t v = 0; v < n; ++v) {
    if (fixed[v] || !std::isfinite(shortest[v])) continue;
    Eigen::RowVector3d d;
    do {
      d << uniform(), uniform(), uniform();
    } while (d.squaredNorm() > 1.0);
    mesh.points.row(static_cast<Eigen::Index>(v)) =
        original.row(static_cast<Eigen::Index>(v)) + fraction * shortest[v] * d;
  }
}

/// Puts every node with `fixed[v] == false` at the centroid of the fixed nodes.
inline void collapse(primal::HexMesh& mesh, const std::vector<bool>& fixed) {
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
  double count = 0.0;
  for (std::size_t v = 0; v < fixed.size(); ++v)
    if (fixed[v]) centre += mesh.points.row(static_cast<Eigen::Index>(v)), count += 1.0;
  if (count > 0.0) centre /= count;
  for (std::size_t v = 0; v < fixed.size(); ++v)
    if (!fixed[v]) mesh.points.row(static_cast<Eigen::Index>(v)) = centre;
}

/// Bends every point of `mesh` (a box [0,a] x [0,b] x [0,c]) about the z axis: x becomes an
/// angle of `sweep` radians over the box's length a, y a radius from inner + b (y = 0) down
/// to `inner` (y = b), which keeps the hexes positively oriented.
inline void bend(primal::HexMesh& mesh, double a, double b, double inner, double sweep) {
  for (Eigen::Index v = 0; v < mesh.points.rows(); ++v) {
    const double angle = sweep * mesh.points(v, 0) / a;
    const double r = inner + b - mesh.points(v, 1);
    mesh.points(v, 0) = r * std::cos(angle);
    mesh.points(v, 1) = r * std::sin(angle);
  }
}

}  // namespace stcweave::test
