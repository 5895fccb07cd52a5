// Where a quad surface passes through itself (`crossing_quads`): the geometric check behind
// `SurfaceDiagnosis::crossing_quad_pairs` (docs/topology.md, "A surface that passes through
// itself").
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "stcweave/primal/mesh.hpp"
#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::primal {

/// The pairs of quads (lower index first, sorted) that share no node and cross: whichever of
/// its two diagonals splits each quad into triangles, an edge of a triangle of one goes from
/// one side of a triangle of the other to the other side, through it (its edges included).
/// An edge that only reaches the other's plane, and coplanar overlaps, within a tolerance of
/// 1e-9 of the pair's size, are not crossings: a surface whose solids only touch passes.
/// Quads sharing a node are not compared (a fold between neighbours is not found). Every
/// node a quad names must have finite coordinates. Linear in the quads for a surface whose
/// quads have sizes of one order (a uniform grid of cells about twice the mean quad size).
[[nodiscard]] std::vector<std::array<QuadId, 2>> crossing_quads(const Points& points,
                                                                const stc::QuadSurface& surface);

}  // namespace stcweave::primal
