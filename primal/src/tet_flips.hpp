#pragma once
/// \file
/// Fewer tetrahedra for the tet interior (docs/tet-interior.md, "Fewer tets"): 3-2 flips.
///
/// Every tetrahedron becomes four hexes, so each tet saved is four hexes saved. An interior
/// edge with exactly three tets around it (a triangular bipyramid cut along its axis) can be
/// re-cut across its equator into two tets: one tet fewer, the bipyramid's six faces unchanged,
/// so the boundary triangles and the rest of the mesh are untouched. A flip is made only when
/// both new tets are positive and the worse of them is no worse than `floor` or than the worst
/// of the three it replaces, whichever is lower: the mesh's worst tet never gets worse than it
/// was or than `floor`.

#include <cstddef>
#include <vector>

#include "stcweave/primal/mesh.hpp"
#include "stcweave/stc/tet_split.hpp"

namespace stcweave::primal {

/// Six times the signed volume of `tet`: (b - a) . ((c - a) x (d - a)), positive for a
/// positively oriented tet.
[[nodiscard]] double tet_volume6(const Points& points, const stc::Tet& tet);

/// The worst corner of a tet as a hex corner: the least, over its four vertices, of the
/// triple product of the three edges leaving the vertex divided by their lengths (1 for the
/// corner of a cube, sqrt(2) / 2 for a regular tet; negative when inverted). It is the scaled
/// Jacobian the split's hex gets at that vertex while the added nodes sit at edge midpoints,
/// face and tet centres.
[[nodiscard]] double tet_corner_quality(const Points& points, const stc::Tet& tet);

/// What `flip_tets` did.
struct TetFlips {
  std::size_t flips = 0;   ///< 3-2 flips made (tets removed)
  std::size_t passes = 0;  ///< passes over the interior edges
};

/// Makes 3-2 flips until none is allowed (see the file comment), in a deterministic order:
/// passes over the edges with three tets, sorted by their end nodes. Tets keep positive
/// orientation (`tet_corner_quality` > 0 for each new one). `tets` is rewritten: surviving
/// tets in their old order, then the new ones.
/// \pre every tet is positively oriented; `tets` is a valid tetrahedral mesh of a solid whose
///      boundary faces are faces of exactly one tet.
TetFlips flip_tets(const Points& points, std::vector<stc::Tet>& tets, double floor);

}  // namespace stcweave::primal
