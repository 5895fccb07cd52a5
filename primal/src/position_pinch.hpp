#pragma once
/// \file
/// Pinched face pairs of a hex complex (internal to primal/src; docs/geometry.md "Repair").

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "stcweave/primal/mesh.hpp"
#include "stcweave/stc/quad_surface.hpp"
#include "stcweave/stc/validate.hpp"

namespace stcweave::primal {

using stc::pinched_faces;
using stc::PinchedFaces;

/// What `unpinch` did.
struct UnpinchReport {
  std::size_t pinched_before = 0;  ///< pinched pairs found
  std::size_t pinched_after = 0;   ///< left (0 unless some pair had no interior 2-hex block)
  std::size_t blocks = 0;          ///< 2-hex blocks pillowed
  std::size_t hexes_added = 0;     ///< 10 per block
  std::size_t nodes_added = 0;     ///< 12 per block
};

/// Removes pinched face pairs (docs/geometry.md "Pinched faces") by pillowing, per pair,
/// the two hexes on one of its faces: every node of those two hexes gets a copy (moved a
/// third of the way to the block's centroid), the two hexes move to the copies and one hex
/// joins each of the block's 10 outer faces to its copy. The pinched node's link then
/// holds each of the two shared edges once. A block is used only when none of its nodes is
/// among the first `num_fixed` (boundary) nodes, the result is a valid
/// hex complex with `boundary` as its faces used once, and the pinched count drops; pairs
/// with no such block are left (counted in `pinched_after`). Nothing changes when there is
/// no pinched pair. New nodes and hexes are appended.
/// `pinched`, when given, must be `pinched_faces(mesh.complex)` (found beforehand, beside
/// another stage).
UnpinchReport unpinch(HexMesh& mesh, std::size_t num_fixed, const stc::QuadSurface& boundary,
                      std::optional<std::vector<PinchedFaces>> pinched = std::nullopt);

}  // namespace stcweave::primal
