#pragma once
/// \file
/// Weaving after hexes were attached to the input by someone else (the front moves of
/// stc/loop_moves.hpp, docs/self-intersecting-loops.md): the attached hexes are replayed on the
/// input's front as if the weaver had built them, so that the weave goes on with everything it
/// knows about its own hexes. The nodes those hexes made are interior nodes of the weave, free
/// to be merged by a seam like any node the weaver made itself; only the input's nodes stay
/// fixed. The weaver also knows which hex stands behind every front face, so its seams and
/// merges respect "two hexes share at most one face" across attached and woven hexes alike.

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "stcweave/stc/loop_moves.hpp"
#include "stcweave/stc/quad_surface.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::weave {

/// Front moves during the weave: when every (loop, side) is blocked and some loop of the
/// weave's front crosses itself (the weave never shrinks such a loop), `stc::untangle_loops`
/// runs on that front and its hexes are attached there, each checked against the woven hexes
/// first (none may share two faces, or four nodes off the front, or an edge off the front with
/// a woven hex; a refused hex undoes the whole round). Then the weave goes on.
struct AttachedWeaveOptions {
  /// Rounds of front moves at most; 0: none (a block is handled as by `weave`).
  std::size_t untangle_rounds = 0;
  /// Bounds of each round's search.
  stc::LoopMoveOptions search;
};

/// What the rounds of front moves did.
struct AttachedWeaveReport {
  std::size_t rounds = 0;  ///< rounds whose hexes were attached
  std::size_t hexes = 0;   ///< hexes they attached
  /// Per refused round, why (a hex in conflict with the woven ones, or a front the search refused).
  std::vector<std::string> refusals;
};

/// Weaves the region bounded by `surface` once the hexes `attached` are on it. `attached`
/// lists hexes in the order they were put on the front: each is built on the front faces it
/// shares with the front at that moment (as its own outward faces: the front face and the hex
/// face have the same nodes in the same cyclic order), and its other faces join the front
/// reversed. Its node ids: the input's 0 .. surface.num_nodes-1, then new nodes (any ids up to
/// `attached.num_nodes`). The result holds the attached hexes first (rule "attached", shrink
/// -1), then the woven ones; input nodes keep their ids, interior nodes are numbered in order of
/// creation (the attached hexes' first, in order of first use). The replayed hexes, and those
/// the rounds of `more` attach (rule "attached" too, among the woven ones), are traced and count
/// against `max_rules` like any rule. The complex is not certified: run
/// `stc::validate_hex_complex` on it.
/// \param report when set, receives what the rounds of front moves did.
/// \param side_angles as for `weave`: the input's; faces of the attached hexes carry angles by
///        the weave's propagation (seed sect. 6), as a woven hex's faces do.
/// \throw InvalidInput when `surface` is not a valid front, when an attached hex has a node id
///        out of range, repeats a node, touches no front face, or lies on a front face with the
///        wrong orientation, or when the front after the replay is not a closed oriented
///        manifold quad surface.
/// \throw WeaveError, InternalError as `weave`.
WeaveResult weave_attached(const stc::QuadSurface& surface, const stc::HexComplex& attached,
                           const WeaveOptions& options = {},
                           const std::vector<std::array<double, 4>>& side_angles = {},
                           const AttachedWeaveOptions& more = {},
                           AttachedWeaveReport* report = nullptr);

}  // namespace stcweave::weave
