#pragma once
/// \file
/// Comparison of two hex meshes up to renumbering, for tests that know the structured answer.

#include <string>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::test {

/// True when `ours` and `reference` are the same hex complex up to a renumbering of the hexes
/// and of the interior nodes: boundary nodes (nodes of faces used by one hex) are matched by
/// their coordinates (within 1e-9 of the bounding box diagonal), interior nodes are matched
/// through the hexes. The match is grown from every boundary quad: the hex on a quad fixes
/// the nodes of its opposite face through its four edges leaving the quad, and the match
/// crosses every shared face to the neighbouring hex. Any inconsistency (a node or a hex
/// matched twice, a face shared on one side and not on the other) is a difference. Only the
/// coordinates of boundary nodes are read. Both orientations of a hex are accepted.
/// \param why when not null, receives the first difference found (empty when the same).
bool same_connectivity(const primal::HexMesh& ours, const primal::HexMesh& reference,
                       std::string* why = nullptr);

}  // namespace stcweave::test
