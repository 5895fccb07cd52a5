#pragma once
/// \file
/// Basic queries on a hex complex: its faces and its boundary.

#include <cstdint>
#include <utility>
#include <vector>

#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::stc {

/// Where a face of the complex comes from: face `face` (0..5, see kHexFaces) of hex `hex`.
struct HexFaceRef {
  HexId hex;
  int face = -1;
};

/// The boundary of a hex complex: the faces used by exactly one hex, oriented outward when
/// the hexes are positively oriented, in a deterministic order (increasing hex id, then
/// face index). Node ids are those of the complex (not compacted): `num_nodes` is the
/// complex's. Faces used by three or more hexes are not boundary faces; `nonmanifold`
/// receives them (one entry per such face) when given.
/// \param origin when given, receives for each boundary quad the hex face it comes from.
QuadSurface boundary_surface(const HexComplex& complex, std::vector<HexFaceRef>* origin = nullptr,
                             std::vector<HexFaceRef>* nonmanifold = nullptr);

/// The distinct edges of the hexes as node-value pairs (smaller value first), sorted.
std::vector<std::pair<std::int32_t, std::int32_t>> unique_edges(const HexComplex& complex);

}  // namespace stcweave::stc
