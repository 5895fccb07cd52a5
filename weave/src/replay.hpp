#pragma once
/// \file
/// Hexes made outside the driver put on a weave's front (private to the library): the hexes
/// attached before the weave and by the front moves of a blocked weave (attached.cpp), and the
/// fill of a small blocked front (fill.cpp). Each is built by `make_hex` on the front faces it
/// lies on, as if a rule had built it.

#include <optional>
#include <string>
#include <vector>

#include "stcweave/stc/quad_surface.hpp"
#include "stcweave/weave/kernel.hpp"

namespace stcweave::weave {

/// Puts `hexes` on the front of `state`, in order, each made by `make_hex` under the name
/// `rule`. `node_of` maps their node ids below its size to canonical nodes of the weave; the
/// others become new interior nodes. With `check`, a hex that cannot join the woven complex
/// (two of its front faces belong to one hex; it would share more than one face, or four nodes
/// that are not a face being glued now, with a woven hex; one of its edges between existing
/// nodes is an edge of a woven hex off the front) stops the replay before it is built, and the
/// reason is returned (the hexes before it stay built: the caller rolls back).
/// \throw InvalidInput when a hex repeats a node, uses a node out of range, lies on a front face
///        with the wrong orientation or on none, or leaves the front broken.
std::optional<std::string> replay(WeaveState& state, WeaveContext& ctx,
                                  const stc::HexComplex& hexes, std::vector<NodeId> node_of,
                                  bool check, const char* rule);

/// The live front of `front` as a quad surface with compact node ids; `nodes` gets, per compact
/// id, the canonical front node.
stc::QuadSurface front_surface(const Front& front, std::vector<NodeId>& nodes);

}  // namespace stcweave::weave
