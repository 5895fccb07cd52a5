#pragma once
/// \file
/// Small sphere quadrangulations made from the cube by seeded sequences of local moves that
/// keep a valid quad mesh: doublet splits (a quad cut along a diagonal by a new node, one more
/// quad) and edge rotations (two quads sharing an edge re-split along another diagonal of
/// their hexagon). Most come out with loops that cross themselves. Deterministic: the seed
/// drives a 32-bit linear congruential generator of our own (std:: distributions differ
/// between standard libraries).

#include <cstddef>
#include <cstdint>
#include <optional>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::test {

/// A random quadrangulation of the sphere, oriented outward, with `target_quads` quads:
/// doublet splits until it has that many, then `flips` edge rotations, each move drawn at
/// random among the allowed ones. Returned only when the result is a valid quad mesh in the
/// strong sense the weave needs: closed, oriented, every node of valence >= 3, no two quads
/// on the same four nodes, no two quads sharing two edges; otherwise nothing. Node positions:
/// the cube's corners, every new node at the centroid of the quad it split (for files only).
std::optional<primal::SurfaceMesh> random_quadrangulation(std::uint32_t seed, int target_quads,
                                                          int flips);

/// True when `surface` is closed, consistently oriented, every node used has valence >= 3, no
/// two quads have the same four nodes and no two quads share two edges.
bool is_strong_quadrangulation(const stc::QuadSurface& surface);

/// `mesh` with the edge leaving corner `corner` of quad `quad` rotated (the two quads sharing
/// it re-split along the first diagonal of their hexagon, or the second when
/// `other_diagonal`), points unchanged; nothing when the rotation is not allowed (a repeated
/// hexagon node, the diagonal already an edge) or the result is not a strong quadrangulation.
std::optional<primal::SurfaceMesh> rotate_edge(const primal::SurfaceMesh& mesh, std::size_t quad,
                                               std::size_t corner, bool other_diagonal);

}  // namespace stcweave::test
