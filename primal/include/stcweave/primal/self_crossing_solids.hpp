#pragma once
/// \file
/// Solids with handles or several shells whose loops cross themselves
/// (docs/self-intersecting-loops.md, "Handles and shells"): the handle cuts of
/// `weave_solids` first, accepting cuts that add no self-crossing quad, then every cut ball
/// whose loops still cross themselves through `weave_self_crossing` (front moves, then the
/// weave), the others through the plain weave; the balls are glued back as `weave_solids`
/// does, and the glued complex certified there.

#include <array>
#include <cstddef>
#include <vector>

#include "stcweave/primal/cut.hpp"
#include "stcweave/primal/mesh.hpp"
#include "stcweave/primal/self_crossing.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::primal {

/// The search bound shared by every ball one call sends through the front moves: the disc
/// search of `weave_solids` weaves a new ball per disc choice, and without a shared bound each
/// reran a whole search of up to `stc::LoopMoveOptions::max_work` on each,
/// so a solid whose searches give up took minutes. Each ball's search gets what is left (and
/// at most its own `SelfCrossingOptions::search` bounds); a ball is charged its evaluations
/// times its face count (the work `stc::untangle_loops` counts per evaluation, the front's
/// faces), or all that was left when the search stopped at that bound. Counted, not timed, so
/// the outcome does not depend on the machine.
struct SharedSearchBudget {
  /// Face evaluations over every ball (the `max_work` unit). Set to about the wall time the
  /// old bound of 4e7 took before the search updated its scores from the changed loops alone
  /// (15 s): the medial fertility's balls (about 2,260 faces) ran 3.9e8 of them in 4.5 s,
  /// and with this budget the solid is meshed (the old one ran out on its first ball).
  std::size_t work = 1000000000;
  /// Candidate moves evaluated over every ball (the `max_evaluations` unit), by every search
  /// of a ball: the untangling, and also the fills and the rounds during the weaves of its
  /// ways (one `stc::LoopMoveOptions::shared_evaluations` pool). Until 2026-12-07 only the
  /// untangling was counted, with 1e6: the square ring with a rotated edge, whose balls all
  /// block since hex contacts are checked, then searched for 20 minutes (60 balls, most of it
  /// in the fills' deepenings) before its refusal; with 1e6 counted this way it is refused in
  /// 23 s, but the 3 x 3 x 2 ring with a rotated edge, which meshes with the old count, is
  /// refused too. At 1e7 that ring meshes (106 hexes, about 2 minutes) and the square ring's
  /// refusal takes 4.5 minutes of CPU time (some 27 microseconds per evaluation on such
  /// small balls).
  std::size_t evaluations = 10000000;
};

/// Meshes `mesh` (closed, manifold, oriented outward, every handle cycle even) whose loops
/// may cross themselves, through `weave_solids` with `CutOptions::allow_self_crossing` and a
/// ball weaver that sends each cut ball with self-intersecting loops to
/// `weave_self_crossing`. `report` sums the balls' searches and weaves (including discarded
/// disc choices); its hex counts are those of the returned complex (`hex_rule` "attached",
/// "pillow", the rest woven) and its `moves` the last ball's that went through the moves.
/// \throw WeaveError when the shared budget ran out (every later ball is refused at once, so
///        the disc search ends without weaving), or when no disc choice could be woven and
///        glued and the search for front moves of some ball gave up: the message says which
///        bound, how many balls went through the moves, and `weave_solids`'s refusal.
/// \throw what `weave_solids` throws otherwise; a ball whose search or weave gives up only
///        discards its disc choice (the next one is tried), and the last failure is in the
///        message.
weave::WeaveResult weave_solids_self_crossing(const SurfaceMesh& mesh,
                                              const weave::WeaveOptions& weave_options,
                                              const CutOptions& cut_options,
                                              const SelfCrossingOptions& options,
                                              SolidsReport* solids, SelfCrossingReport& report,
                                              const SharedSearchBudget& budget = {});

}  // namespace stcweave::primal
