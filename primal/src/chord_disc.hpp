#pragma once
/// \file
/// Quad-meshed discs with a prescribed chord diagram (internal to primal's handle cuts).
///
/// The dual chords of a quad-meshed disc pair its boundary edges; the disc spanning a handle
/// cycle decides, through that pairing, how the loops crossing the cycle continue across the
/// cut. `chord_disc` builds a disc whose chords realise a given pairing: the pairing drawn as
/// straight chords between points on a circle (a generic arrangement), each crossing of two
/// chords a quad, each face of the arrangement a disc node (docs/topology.md).

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::primal {

/// A quad-meshed disc spanning a cycle of L nodes, over its own node ids.
struct Disc {
  /// Per disc node, its position along the cycle's walk (0 .. L-1) for a boundary node, none
  /// for an interior one. Boundary edge p joins walk positions p and p + 1 (mod L).
  std::vector<std::optional<std::size_t>> walk;
  std::vector<Eigen::RowVector3d> positions;  ///< per disc node
  /// Quads over disc node ids, oriented so that a quad on boundary edge p runs from walk
  /// position p to p + 1.
  std::vector<std::array<std::size_t, 4>> quads;
};

/// A disc whose boundary walk is `cycle_points` (L points, L even) and whose dual chords pair
/// boundary edge p with edge `partner[p]` (an involution without fixed points). Interior
/// nodes are placed by a Tutte (uniform Laplacian) embedding of the boundary.
/// Returns none when the pairing has no such disc: a chord joining two adjacent edges (it
/// would cross no other chord), or an arrangement that stays degenerate.
[[nodiscard]] std::optional<Disc> chord_disc(const std::vector<Eigen::RowVector3d>& cycle_points,
                                             const std::vector<std::size_t>& partner);

/// Whether two arcs of the circle (arc k between the endpoints of edges k and k + 1) lie in
/// one face of the pairing's chord arrangement. Exact and independent of where the endpoints
/// sit: each chord splits the disc in two like a line, a face is the set of points on the
/// same side of every chord, and arc k lies inside chord (a, b), a < b, iff a <= k < b. Such a
/// pairing has no disc (that face would be a boundary node twice); `chord_disc` checks this
/// before building any arrangement. \pre `partner` is an involution without fixed points.
[[nodiscard]] bool arcs_share_a_face(const std::vector<std::size_t>& partner);

/// `chord_disc` without the `arcs_share_a_face` test first: the arrangements alone (same
/// result, slower on the pairings that test refuses). For tests.
[[nodiscard]] std::optional<Disc> arrangement_disc(
    const std::vector<Eigen::RowVector3d>& cycle_points, const std::vector<std::size_t>& partner);

/// Number of chord crossings (disc quads) of the pairing `partner` drawn on a circle: pairs
/// of chords whose endpoints interleave.
[[nodiscard]] std::size_t chord_crossings(const std::vector<std::size_t>& partner);

}  // namespace stcweave::primal
