#pragma once
/// \file
/// What the CAD tests share: skipping visibly in a build without Gmsh, the repository's
/// data/ examples, a CAD surface at a size and recipe in one call, the whole pipeline on it,
/// and the distance of the result's boundary nodes to a surface known in closed form.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <set>
#include <string>

#include "stcweave/primal/cad.hpp"
#include "stcweave/primal/pipeline.hpp"

/// Skips the test (visibly) in a build without Gmsh (`STCWEAVE_WITH_GMSH=OFF`).
#define STCWEAVE_SKIP_WITHOUT_GMSH()          \
  if (!::stcweave::primal::has_cad_support()) \
  GTEST_SKIP() << "built without Gmsh (STCWEAVE_WITH_GMSH=OFF)"

namespace stcweave::test {

/// The path of `name` in the repository's data/ folder.
inline std::string repo_data(const std::string& name) {
  return std::string(STCWEAVE_SOURCE_DIR) + "/data/" + name;
}

/// The CAD options of a test: target size `size`, recipe `recipe`, splitting into blocks
/// (`CadOptions::split`) on or off, the rest defaults.
inline primal::CadOptions cad_options(double size,
                                      primal::CadRecipe recipe = primal::CadRecipe::Auto,
                                      bool split = true) {
  primal::CadOptions options;
  options.size = size;
  options.recipe = recipe;
  options.split = split;
  return options;
}

/// A primitive's quad surface at `size` with `recipe`.
inline primal::CadSurface cad_surface(const primal::CadPrimitive& primitive, double size,
                                      primal::CadRecipe recipe = primal::CadRecipe::Auto,
                                      bool split = true) {
  return primal::mesh_cad_surface(primitive, cad_options(size, recipe, split));
}

/// Distance from `p` to the boundary of the cylinder of radius `r` and height `h` along z
/// from the origin.
inline double cylinder_distance(const Eigen::Vector3d& p, double r, double h) {
  const double radial = std::hypot(p.x(), p.y());
  const double to_side = std::abs(radial - r) + std::max(0.0, -p.z()) + std::max(0.0, p.z() - h);
  const double to_caps = std::min(std::abs(p.z()), std::abs(p.z() - h)) + std::max(0.0, radial - r);
  return std::min(to_side, to_caps);
}

/// The whole pipeline on a CAD surface (untangling on or off: it is slow on the hexes of
/// triangle-split surfaces, and some tests only need the complex).
inline primal::MeshResult mesh_cad(const primal::CadSurface& cad, bool untangle) {
  primal::MeshOptions options;
  options.untangle = untangle;
  return primal::mesh_file(cad.file, options);
}

/// Largest value of `distance` over the boundary nodes of the hex mesh (the nodes of the
/// woven surface's quads, looked up in the hex mesh's points).
template <typename Distance>
double max_boundary_distance(const primal::MeshResult& r, Distance distance) {
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

}  // namespace stcweave::test
