#pragma once
/// \file
/// Solids with handles or several shells whose loops cross themselves
/// (docs/self-intersecting-loops.md, "Handles and shells"): the handle cuts of
/// `weave_solids` first, accepting cuts that add no self-crossing quad, then every cut ball
/// whose loops still cross themselves through `weave_self_crossing` (front moves, then the
/// weave), the others through the plain weave; the balls are glued back as `weave_solids`
/// does, and the glued complex certified there.

#include <array>
#include <vector>

#include "stcweave/primal/cut.hpp"
#include "stcweave/primal/mesh.hpp"
#include "stcweave/primal/self_crossing.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::primal {

/// Meshes `mesh` (closed, manifold, oriented outward, every handle cycle even) whose loops
/// may cross themselves, through `weave_solids` with `CutOptions::allow_self_crossing` and a
/// ball weaver that sends each cut ball with self-intersecting loops to
/// `weave_self_crossing`. `report` sums the balls' searches and weaves (including discarded
/// disc choices); its hex counts are those of the returned complex (`hex_rule` "attached",
/// "pillow", the rest woven) and its `moves` the last ball's that went through the moves.
/// \throw what `weave_solids` throws; a ball whose search or weave gives up only discards its
///        disc choice (the next one is tried), and the last failure is in the message.
weave::WeaveResult weave_solids_self_crossing(const SurfaceMesh& mesh,
                                              const weave::WeaveOptions& weave_options,
                                              const CutOptions& cut_options,
                                              const SelfCrossingOptions& options,
                                              SolidsReport* solids, SelfCrossingReport& report);

}  // namespace stcweave::primal
