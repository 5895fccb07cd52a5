#pragma once
/// \file
/// Dihedral angles of a quad surface's edges, the geometric input of the `extended` rule
/// set (seed sect. 4.2 and 4.4). `weave` receives them as numbers: it knows no coordinates.

#include <array>
#include <vector>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::primal {

/// Per quad and side, the dihedral angle in degrees of that side's edge, measured through the
/// solid: 180 on a flat patch, below 180 on a convex edge (90 on a box edge), above 180 on a
/// non-convex one. A quad's normal is the cross product of its diagonals, so non-planar quads
/// are handled; the angle is signed by the turn of the normals about the edge.
/// \pre `mesh` is closed, manifold and oriented outward (sides without a neighbour get 180).
[[nodiscard]] std::vector<std::array<double, 4>> dihedral_angles(const SurfaceMesh& mesh);

}  // namespace stcweave::primal
