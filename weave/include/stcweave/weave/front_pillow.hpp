#pragma once
/// \file
/// A pillow of the front: a recovery tried for blocked weaves (ours; issue 11), opt-in.
///
/// One hex per front face, between the face and a copy of it whose nodes are new interior
/// nodes; the copies form the new front (a blind sheet parallel to the front), with the same
/// faces, loops and carried angles. It removes the refusals that come from the nodes
/// themselves (a seam that would merge two input nodes). Measured on the blocked sphere
/// quadrangulations of tests/weave/recovery_test.cpp it recovers none: the pillowed front is
/// the same quadrangulation and blocks the same way one layer in (docs/weave-recovery.md).

#include <cstddef>

#include "stcweave/weave/kernel.hpp"

namespace stcweave::weave {

/// Puts one hex on every face of the front (rule "pillow"): face [a, b, c, d] becomes the
/// hex (a, d, c, b, a', d', c', b'), a' the copy of a (one new node per front node), and the
/// side faces of neighbouring hexes are glued as they meet. Returns the hexes made.
std::size_t pillow_front(WeaveState& state, WeaveContext& ctx);

}  // namespace stcweave::weave
