#pragma once
/// \file
/// Primal recovery: from the woven STC to a hex mesh with coordinates.

#include <cstddef>

#include "stcweave/primal/mesh.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::primal {

/// Result of a harmonic placement.
struct HarmonicReport {
  std::size_t free_nodes = 0;
  std::size_t iterations = 0;  ///< conjugate-gradient iterations
  double residual = 0.0;       ///< relative residual reached
  std::size_t levels = 1;      ///< multigrid levels of the preconditioner (1: Jacobi)
};

/// Gives nodes `num_fixed ..` of `mesh` the harmonic position of the hex-edge graph with nodes
/// `0 .. num_fixed-1` fixed: every free node at the average of its edge neighbours. A
/// provisional placement so that the output can be looked at; it does not untangle.
/// \pre every free node is linked by hex edges to some fixed node.
/// \throw SolverError when the solve does not converge.
HarmonicReport harmonic_positions(HexMesh& mesh, std::size_t num_fixed);

/// The hex mesh of a weave: input nodes keep their ids and the coordinates
/// `input_points` (rows 0..num_input_nodes-1), interior nodes get harmonic positions.
/// \pre `input_points.rows() == woven.num_input_nodes`.
/// \throw InvalidInput when the point count does not match.
HexMesh recover_hex_mesh(const Points& input_points, const weave::WeaveResult& woven,
                         HarmonicReport* report = nullptr);

/// Layer placement: moves the interior nodes of `mesh` (a recovered weave, same numbering)
/// to where the weave's layers put them, advancing from the boundary in the order the hexes
/// were made. A cross's new node completes the parallelepiped of its corner (w = the three
/// far face corners - the three edge neighbours + the corner node), a blind chord's two new
/// nodes are translated copies of the strip face's far nodes across the common edge;
/// parallel merging makes no node. A node reached several ways (nodes merged by seams) gets
/// the mean of its estimates; nodes no estimate reaches keep their position.
/// \return the number of interior nodes placed.
std::size_t layer_positions(HexMesh& mesh, const weave::WeaveResult& woven);

}  // namespace stcweave::primal
