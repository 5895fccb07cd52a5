#pragma once
/// \file
/// Pillows of the front: the recovery of a blocked weave (ours; issue 11), opt-in
/// (`WeaveOptions::recovery_pillows`).
///
/// A pillow of a set of front faces puts one hex on each, between the face and a copy whose
/// nodes are new interior nodes; the copies, and the side faces along the set's rim, join
/// the front. On the whole front (a blind sheet parallel to it) the new front is the same
/// quadrangulation and, measured, blocks the same way one layer in. On one face at a
/// valence-2 node whose seam is refused (`pillow_blocked_node`, what the driver uses) the
/// node gets valence 3 and the front's combinatorics change: measured on the blocked sphere
/// quadrangulations of tests/weave/recovery_test.cpp, up to 16 such pillows let `reliable`
/// complete all of them and `extended` 9 of 16 (docs/weave-recovery.md).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "stcweave/weave/kernel.hpp"

namespace stcweave::weave {

/// Puts one hex on every face of the front (rule "pillow"): face [a, b, c, d] becomes the
/// hex (a, d, c, b, a', d', c', b'), a' the copy of a (one new node per front node), and the
/// side faces of neighbouring hexes are glued as they meet. Returns the hexes made.
std::size_t pillow_front(WeaveState& state, WeaveContext& ctx);

/// The same on the front faces `faces` only (a disc, or the whole front): their nodes are
/// copied, and the side faces along the region's rim join the front.
std::size_t pillow_faces(WeaveState& state, WeaveContext& ctx, const std::vector<FaceIndex>& faces);

/// Why a pillow of `faces` would break the complex, if it would: a woven hex other than its
/// owner holds the four nodes of one of them (`WeaveState::contact_conflict`), two of them
/// share two nodes that are not an edge of both (their pillow hexes would share those nodes
/// and their copies: four nodes that are not a face), or three or more nodes (two edges: the
/// hexes would share two faces). `pillow_faces` does not check it.
[[nodiscard]] std::optional<std::string> pillow_conflict(const WeaveState& state,
                                                         const std::vector<FaceIndex>& faces);

/// A pillow of one face at the lowest valence-2 node of the front (its lowest face slot
/// whose pillow has no `pillow_conflict`), which raises that node's valence to 3; the whole
/// front when there is no such node. Returns 0 (and changes nothing) when every such pillow
/// has a conflict.
std::size_t pillow_blocked_node(WeaveState& state, WeaveContext& ctx);

}  // namespace stcweave::weave
