#pragma once
/// \file
/// Pinched face pairs of a hex complex (internal to primal/src; docs/geometry.md "Repair").

#include <array>
#include <cstdint>
#include <vector>

#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::primal {

/// Two distinct faces (n, a, x, b) and (n, a, y, b) of the complex: they share the edges
/// n-a and n-b. At n both are tangent to the plane of those two edges, so the hexes met
/// going round the edge n-a from one face to the other on one side span a dihedral angle of
/// 0 there: some corner at n is flat (det 0) whatever the positions. Topology, not positions.
struct PinchedFaces {
  NodeId node;
  NodeId a;  ///< the smaller of the two shared neighbours
  NodeId b;
  std::array<std::int32_t, 4> first{};  ///< node cycles of the two faces
  std::array<std::int32_t, 4> second{};
};

/// Every pinched pair of faces, sorted by (node, a, b); O(hexes log hexes).
std::vector<PinchedFaces> pinched_faces(const stc::HexComplex& complex);

}  // namespace stcweave::primal
