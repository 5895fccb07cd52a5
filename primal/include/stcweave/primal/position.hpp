#pragma once
/// \file
/// Node positioning with a fixed boundary: untangling and shape optimisation of a hex mesh
/// by a foldover-free energy on the corner Jacobians.
///
/// Algorithm (what it guarantees and why). Every hex corner k is the tet spanned by the
/// corner node and its three edge neighbours; its matrix J = [e1 e2 e3] / h (h = the edge
/// length of a cube of the mean hex volume, fixed by the boundary) has det J = the corner
/// Jacobian. The energy is Garanzha et al.'s regularised Winslow energy (ACM TOG 40(4),
/// 2021) summed over the 8 corners of every hex:
///
///     E = sum (1 - theta) |J|^2 / chi(eps, d)^(2/3) + theta (1 + d^2) / chi(eps, d),
///     chi(eps, d) = (d + sqrt(eps^2 + d^2)) / 2,  d = det J,
///
/// finite and smooth for every position (so defined while corners are inverted) and, as
/// eps -> 0, a barrier that grows without bound when a corner flattens. A sequence of
/// L-BFGS minimisations with decreasing eps (Gmsh's rule eps = sqrt(1e-12 + 0.04
/// min(d_min, 0)^2), measured in research/geometry.md to untangle where the paper's rule
/// stalls) pushes the smallest corner determinant up; once every corner is positive, the
/// barrier keeps it so and the shape term evens the corners out. Only the nodes that are
/// not fixed move; fixed nodes keep their coordinates bit for bit.
///
/// No method can untangle every mesh: corners whose four nodes are all fixed keep their
/// determinant, and two hexes with the same corner (same node and same three edges, as
/// in a doublet: two hexes sharing two faces) have opposite determinants there. Such
/// corners are found first, left out of the energy and reported by element, so that the
/// optimiser does not chase an impossible goal; the outer loop also stops when the count
/// of inverted corners has not dropped for `stall_iterations` rounds.
///
/// Deterministic: no randomness, and the energy is summed in a fixed order whatever the
/// number of threads, so the same input gives the same output bit for bit.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/SparseCore>

#include "stcweave/primal/mesh.hpp"
#include "stcweave/primal/quality.hpp"

namespace stcweave::primal {

/// Where the free nodes start from.
enum class StartPosition {
  Keep,      ///< their current coordinates (e.g. the harmonic placement of recover.hpp)
  Harmonic,  ///< the harmonic placement of the hex-edge graph (every free node at the
             ///< mean of its edge neighbours, fixed nodes as given), one sparse Cholesky
  Auto       ///< the harmonic placement when it has fewer inverted corners than the
             ///< current coordinates (e.g. nodes collapsed or scattered), else Keep
};

/// What `PositionOptions::progress` is told after every untangling round and every sweep of
/// the repair and shape phases, so that a long run can show where it is. Reading it changes
/// nothing: the positions do not depend on whether a callback is set.
struct PositionProgress {
  enum class Phase {
    Untangle,  ///< a round of (L-BFGS minimisation, lower eps) on every free node
    Repair,    ///< a sweep of local max-min moves around the hexes still inverted
    Shape,     ///< a sweep of local moves raising the worst hexes (`improve_shape`)
    Clusters   ///< a cluster of inverted hexes positioned on its own (`untangle_clusters`)
  };
  Phase phase = Phase::Untangle;
  std::size_t step = 0;   ///< this phase's round or sweep (clusters: cluster of the pass), from 1
  std::size_t limit = 0;  ///< the phase's bound on rounds or sweeps (clusters: of the pass)
  /// Untangle: corners with a non-positive Jacobian after the round; repair, shape and
  /// clusters: hexes with a non-positive scaled Jacobian after the sweep or cluster.
  std::size_t inverted = 0;
  /// Untangle: L-BFGS iterations so far, over every round.
  std::size_t iterations = 0;
  /// Repair and shape: the worst hex's scaled Jacobian after the sweep (untangle and
  /// clusters: 0).
  double min_scaled_jacobian = 0.0;
  /// Clusters: the pass, from 1.
  std::size_t pass = 0;
  /// Untangle: the eps the round minimised with, and the one the next round will use (the
  /// stall rule counts a round only when the second is not below the first by more than
  /// `stall_fraction`; docs/geometry.md "Stopping rules"). Other phases: 0.
  double epsilon = 0.0;
  double next_epsilon = 0.0;
};

/// The phase's name as progress lines and reports write it ("untangle", "repair", "shape",
/// "clusters").
[[nodiscard]] const char* phase_name(PositionProgress::Phase phase);

/// Options of `position_nodes`. Defaults are the settings measured to work in
/// research/geometry.md §3.3 / §4.3.
struct PositionOptions {
  /// Nodes 0 .. num_fixed-1 never move (the input surface's nodes, as in recover.hpp).
  std::size_t num_fixed = 0;
  /// Optional extra mask: when non-empty (one entry per node) node n is fixed also when
  /// fixed[n] is true.
  std::vector<bool> fixed;
  StartPosition start = StartPosition::Keep;
  /// Weight of the volume term (theta) against the shape term (1 - theta).
  double theta = 0.5;
  /// Rounds of (minimise, lower eps).
  int max_outer_iterations = 100;
  /// L-BFGS iterations per round.
  int max_inner_iterations = 3000;
  /// L-BFGS iterations over every round at most (0: no bound): the untangling's total work
  /// bound. A round that would pass it is cut short and the rounds stop there ("iteration
  /// budget" in `PositionReport::stop`; the repair of the hexes still inverted runs as after
  /// a stall). Default: ten rounds' worth, above the longest positionings of the bench that
  /// end by themselves (about 22,000; docs/geometry.md, "Stopping rules").
  int max_total_iterations = 30000;
  /// L-BFGS stops when the gradient norm (energy in units of h) is below this.
  double gradient_tolerance = 1e-4;
  /// Stop when every corner is positive and the energy changed by less than this
  /// (relative) over a round.
  double energy_tolerance = 1e-5;
  /// Give up after this many rounds that count toward a stall: rounds after which corners
  /// are still inverted, their number has not dropped (see `stall_fraction`) and eps has not
  /// fallen (the next round's eps is not below (1 - `stall_fraction`) times this one's).
  /// Rounds whose eps still falls do not count, nor do they undo the ones that did. Until
  /// 2026-12-08: 3 rounds, with no exception for a falling eps.
  int stall_iterations = 1;
  /// A round counts as a drop only when the inverted corners fall below (1 - this) times
  /// their count at the last drop (0: any drop counts, the rule before 2026-12-05); and eps
  /// falls when the next round's is below (1 - this) times the round's own.
  double stall_fraction = 0.05;
  /// L-BFGS memory.
  int memory = 6;
  /// When L-BFGS has used this many iterations in a round (or its line search failed), the
  /// round goes on with projected Newton steps (0: never, the default), and back to L-BFGS
  /// if Newton finds no step. Each step assembles the Hessian of every corner projected to
  /// positive semi-definite and solves with Eigen's sparse Cholesky (SimplicialLLT, shifted
  /// until definite). Off by default because it was measured
  /// slower than L-BFGS alone on every mesh tried (docs/geometry.md): a factorisation of a
  /// volume mesh costs far more than the L-BFGS iterations one step saves.
  int newton_after = 0;
  /// Untangling rounds minimise with L-BFGS whose initial inverse Hessian is one multigrid
  /// V-cycle of the hex edges' graph Laplacian over the free nodes (docs/geometry.md,
  /// "Preconditioned L-BFGS"); false: LBFGS++'s plain L-BFGS (a scaled identity).
  bool precondition = true;
  /// Projected Newton steps per round at most.
  int max_newton_steps = 50;
  /// Subdivision depth of the Bézier validity certification (0: no subdivision).
  int certify_depth = 4;
  /// Threads evaluating the energy of meshes of 1024 hexes or more (0: one per hardware
  /// thread), and running the two starts of a local untangling sub-mesh side by side (1: one
  /// after the other). The result does not depend on it.
  int threads = 0;
  /// Early stop: a start with no inverted corner or hex, a minimum scaled Jacobian of at
  /// least this and a mean of at least `good_start_mean` is kept as it is (no untangling
  /// rounds; the shape phase, whose barrier pass works on the worst hexes, still runs). The
  /// default 0 asks only for validity and the mean: measured on the transfinite cylinders,
  /// the untangling energy evens out the average and barely moves the worst hex, which the
  /// shape phase raises anyway (docs/geometry.md). Above 1: never stop early. In [0, 2].
  double good_start = 0.0;
  /// Early stop: the mean scaled Jacobian a good start needs as well (0.95: within a few
  /// percent of the ideal on average, where the energy has little left to even out). In
  /// [0, 2].
  double good_start_mean = 0.95;
  /// Shape phase after untangling (see `improve_shape`): off with 0 sweeps.
  int max_shape_sweeps = 30;
  /// Shape phase: hexes below this scaled Jacobian are worked on.
  double shape_target = 0.6;
  /// Shape phase: stop when a sweep raised the minimum scaled Jacobian by less than this and
  /// reduced the shortfall, sum over hexes of max(0, shape_target - scaled Jacobian), by
  /// less than this fraction of it.
  double shape_tolerance = 1e-2;
  /// Shape phase, barrier pass (see `raise_worst_corners`): at most this many rounds; 0
  /// switches the pass off and leaves the local moves alone.
  int barrier_rounds = 8;
  /// Barrier pass: L-BFGS iterations per round.
  int barrier_iterations = 100;
  /// Barrier pass: the level t of a round is the smallest corner scaled Jacobian q_min of the
  /// worked-on corners times (1 - margin), so the worst corner starts at q_min - t =
  /// margin q_min above the barrier (0 < margin < 1).
  double barrier_margin = 0.5;
  /// Barrier pass: softness tau of the soft minimum exp((q_min - q) / tau) summed over the
  /// corners (smaller: closer to the true minimum; 0.005 measured best of 0.002-0.05 on
  /// Gmsh's tet-split boundaries, docs/geometry.md).
  double barrier_softness = 0.005;
  /// Barrier pass: weight of the mean term (1 - q)^2 per corner, which keeps the corners
  /// well above the worst from degrading (0.01: measured, docs/geometry.md).
  double barrier_mean_weight = 0.01;
  /// Barrier pass: the nodes moved are those of the hexes whose scaled Jacobian is below
  /// min(shape_target, mesh minimum + barrier_window): the worst hexes first.
  double barrier_window = 0.2;
  /// Repair after untangling (see `repair_inverted`): at most this many sweeps of local
  /// max-min moves around the hexes still inverted; 0 switches the repair off. 1000 (was
  /// 100): the repair of the start positions of `real/medial-hexmeshing/fertility` and
  /// `real/pmp/fandisk_quads` was still gaining at 100 sweeps and settles before 1000
  /// (docs/geometry.md "Repair").
  int max_repair_sweeps = 1000;
  /// Repair: the nodes moved are the free nodes within this many hex rings of an inverted
  /// hex (0: the inverted hexes' own nodes).
  int repair_rings = 2;
  /// Local untangling after the repair (see `untangle_clusters`): at most this many passes
  /// over the clusters of hexes still inverted; 0 switches it off.
  int cluster_passes = 3;
  /// Local untangling: each cluster's sub-meshes are the cluster grown by 1 .. this many
  /// rings of hexes sharing a node, each positioned from the current and from the harmonic
  /// positions.
  int cluster_max_rings = 3;
  /// Local untangling: sub-meshes with more hexes than this are not positioned.
  std::size_t cluster_max_hexes = 20000;
  /// Local untangling: no sub-mesh is started once the sub-meshes' work (their hexes times
  /// their L-BFGS iterations, summed) has reached this, and none is given more L-BFGS
  /// iterations than what is left of it allows (0: no bound). Per call of `position_nodes`
  /// (the pipeline calls it twice when it compares a mesh with and without its pillow); the
  /// repair sweeps inside the sub-meshes come on top. The default, about
  /// 100 s on the 2-core development machine, is 2.4 times what `gmsh-quad/cylinder2_c3`
  /// spends (4.2e7) and above `pmp/fandisk_quads` (3.1e7 and 3.9e7; docs/geometry.md "Local
  /// untangling").
  std::size_t cluster_max_work = 100000000;
  /// Local untangling: when the passes leave hexes inverted, a last phase minimises a sum of
  /// hinges on a mean-ratio measure over each cluster's sub-meshes (see `untangle_clusters`;
  /// docs/geometry.md "Local untangling", the hinge phase); under the same work bound.
  bool cluster_hinge = true;
  /// Shape phase, last pass (`raise_worst_by_hinges`): while a hex with a free node is below
  /// this scaled Jacobian after the local moves and the barrier pass, the worst is raised by
  /// hinges over a small sub-mesh around it; 0 switches the pass off.
  double hinge_shape_below = 0.05;
  /// That pass: no sub-mesh is started once its sub-meshes' hexes times their L-BFGS
  /// iterations, summed, reach this (0: no bound).
  std::size_t hinge_shape_max_work = 100000000;
  /// That pass: at most this many L-BFGS iterations per sub-mesh.
  std::size_t hinge_shape_iterations = 1000;
  /// Called after every untangling round, every repair or shape sweep and every cluster of
  /// the local untangling when set (see `PositionProgress`); the CLI's `--progress` prints it.
  std::function<void(const PositionProgress&)> progress;
};

/// What `raise_worst_corners` did.
struct BarrierReport {
  bool ran = false;        ///< at least one round was kept (the mesh changed)
  std::size_t rounds = 0;  ///< rounds run (the last one may have been undone)
  std::size_t iterations = 0;
  /// Smallest corner scaled Jacobian of the worked-on corners at the first round's start and
  /// after the last kept round.
  double min_corner_before = 0.0;
  double min_corner_after = 0.0;
  /// Mesh minimum of Verdict's scaled Jacobian (centre included) before and after.
  double min_scaled_jacobian_before = 0.0;
  double min_scaled_jacobian_after = 0.0;
  /// "target reached", "settled" (a round gained less than a tenth of `shape_tolerance`),
  /// "settled (a round lowered the worst hex: undone)", "round limit", "off",
  /// "inverted hexes: skipped", "no free node below the target".
  std::string stop;
};

/// Barrier pass of the shape phase: raises the worst corner scaled Jacobians of a valid mesh.
/// Each round takes the free nodes of the hexes below min(`shape_target`, mesh minimum +
/// `barrier_window`) and minimises, by L-BFGS over those nodes, the sum over every corner
/// that depends on them of exp((q_min - q) / `barrier_softness`) + `barrier_mean_weight`
/// (1 - q)^2, q being the corner's scaled Jacobian (unit edge vectors) and q_min the
/// smallest at the round's start: a soft minimum, dominated by the worst corners, plus a
/// small term for the others. The objective is +infinity once a corner reaches the level
/// t = q_min (1 - `barrier_margin`) (a hard barrier: no corner can fall far or invert). A
/// round is kept only if the smallest scaled Jacobian (Verdict's, centre included) of the
/// hexes it touched did not drop and it gained at least a tenth of `shape_tolerance` in that
/// or in q_min; otherwise it is undone and the pass stops. At most `barrier_rounds` rounds of
/// `barrier_iterations` iterations. Nodes `fixed` never move; corners with four fixed nodes
/// are left out (they cannot change). Deterministic (fixed order, one thread). Runs nothing
/// on a mesh with an inverted hex.
/// \throw InvalidInput when the mask or a hex disagrees with the points.
BarrierReport raise_worst_corners(HexMesh& mesh, const std::vector<bool>& fixed,
                                  const PositionOptions& options);

/// What `improve_shape` did.
/// What `raise_worst_by_hinges` did.
struct HingeShapeReport {
  bool ran = false;          ///< some hex with a free node was below `hinge_shape_below`
  std::size_t seeds = 0;     ///< worst hexes worked on (one may come back after a kept try)
  std::size_t tries = 0;     ///< sub-meshes whose hinges were minimised
  std::size_t accepted = 0;  ///< clusters whose best try was kept
  std::size_t work = 0;      ///< the tries' hexes times their L-BFGS iterations, summed
  double min_scaled_jacobian_before = 0.0;
  double min_scaled_jacobian_after = 0.0;
  /// "done", "work bound" (`hinge_shape_max_work`), "nothing below" (no hex below
  /// `hinge_shape_below`), "inverted hexes: skipped", "off".
  std::string stop;
};

struct ShapeReport {
  /// false when the mesh had inverted hexes, no free node, or (`position_nodes`) no hex below
  /// `shape_target` at the start
  bool ran = false;
  std::size_t sweeps = 0;
  std::size_t moves = 0;  ///< accepted node moves
  double min_scaled_jacobian_before = 0.0;
  double min_scaled_jacobian_after = 0.0;
  double mean_scaled_jacobian_before = 0.0;
  double mean_scaled_jacobian_after = 0.0;
  BarrierReport barrier;   ///< the barrier pass of the order kept
  HingeShapeReport hinge;  ///< the last pass, by hinges (`raise_worst_by_hinges`)
  /// Which order was kept: "barrier first" (barrier pass, local sweeps) or "local first"
  /// (local sweeps, barrier pass, local sweeps); empty when the barrier pass is off or when
  /// `position_nodes` found no hex below `shape_target` (nothing ran).
  std::string order;
  /// "target reached" (no hex below `shape_target`), "settled" (a sweep gained less than
  /// `shape_tolerance` in the minimum and in the shortfall below the target), "sweep limit",
  /// "inverted hexes: skipped", "no free node", "off".
  std::string stop;
};

/// Shape improvement of an untangled mesh: raises the worst scaled Jacobian (Verdict's, the
/// 9-point one the quality report uses), nodes `fixed` never move. Two orders of the barrier
/// pass (`raise_worst_corners`, a soft max-min of the corner scaled Jacobians over the worst
/// hexes' nodes) and the local max-min moves below are run from the same start, "barrier
/// first" (barrier, local) and "local first" (local, barrier, local); the result with the
/// larger minimum (then mean) is kept, "barrier first" on a tie (`ShapeReport::order`).
/// With `barrier_rounds` = 0 only the local moves run. The local moves: Each sweep visits, worst
/// first (ties in node order), every free node of a hex whose scaled Jacobian is below
/// `shape_target`, and moves it only when that raises the smallest scaled Jacobian of the hexes
/// around it: first to the mean of its edge neighbours (smart Laplacian), then along the
/// finite-difference gradient of that local minimum with halving steps from a fifth of its mean
/// edge length. A move is accepted only if the local minimum grows, so no hex gets worse than the
/// worst one around it was and none can invert: the mesh's minimum never drops (a barrier on the
/// worst element). Stops when no hex is below the target, when a sweep raised the minimum by less
/// than `shape_tolerance` and reduced the shortfall sum max(0, target - SJ) by less than
/// `shape_tolerance` of it, or after `max_shape_sweeps`. Deterministic (fixed order, no threads).
/// Runs nothing when a hex is inverted. \pre `fixed.size() == mesh.points.rows()`.
ShapeReport improve_shape(HexMesh& mesh, const std::vector<bool>& fixed,
                          const PositionOptions& options);

/// What `repair_inverted` did.
struct RepairReport {
  bool ran = false;  ///< some hex was inverted and a free node could move
  std::size_t sweeps = 0;
  std::size_t moves = 0;  ///< accepted node moves
  std::size_t inverted_before = 0;
  std::size_t inverted_after = 0;
  double min_scaled_jacobian_before = 0.0;
  double min_scaled_jacobian_after = 0.0;
  /// "repaired" (no hex inverted), "settled" (a sweep raised neither the minimum nor lowered
  /// the inverted count), "sweep limit", "nothing inverted", "no free node", "off".
  std::string stop;
};

/// Repair of the hexes the untangling left inverted (Verdict's scaled Jacobian, centre
/// included, <= 0) when none of them is fixed by the boundary: the local max-min moves of
/// `improve_shape` (smart Laplacian, then steps along the finite-difference gradients of the
/// local minimum and sum, halving down to 1e-6 of the node's mean edge length), run on the
/// free nodes within `repair_rings` hex rings of an inverted hex, worst first. A move is kept
/// only when the smallest scaled Jacobian of the hexes around the node rises (or stays and
/// their sum rises), so the mesh minimum never drops. The energy of `position_nodes` acts on
/// the corner determinants only and stalls where a corner's barrier and its neighbours' pull
/// balance (`real/mesquite/pave2.e`, extended: 2 hexes with one corner at -0.003, no fixed
/// node); the max-min moves act on the scaled Jacobian itself. Stops when no hex is inverted,
/// when a sweep gains nothing, or after `max_repair_sweeps`. Deterministic.
/// \pre `fixed.size() == mesh.points.rows()`.
RepairReport repair_inverted(HexMesh& mesh, const std::vector<bool>& fixed,
                             const PositionOptions& options);

/// What `untangle_clusters` did.
struct ClusterReport {
  bool ran = false;          ///< some hex was inverted and the pass was on
  std::size_t passes = 0;    ///< passes over the clusters
  std::size_t clusters = 0;  ///< clusters worked on (still inverted), over every pass
  /// Sub-meshes handed to `position_nodes` (those it refused, e.g. with a negative total
  /// volume, included).
  std::size_t sub_problems = 0;
  std::size_t accepted = 0;  ///< clusters whose best sub-mesh was kept
  /// The sub-meshes' hexes times their L-BFGS iterations, summed (`cluster_max_work`).
  std::size_t work = 0;
  std::size_t inverted_before = 0;
  std::size_t inverted_after = 0;
  std::size_t hinge_clusters = 0;  ///< clusters the hinge phase worked on
  std::size_t hinge_tries = 0;     ///< its sub-meshes (at most 2 per ring count)
  std::size_t hinge_accepted = 0;  ///< its clusters whose best try was kept (in `accepted` too)
  /// "untangled" (no hex inverted), "settled" (a pass lowered nothing), "pass limit",
  /// "work bound" (`cluster_max_work`), "nothing inverted", "no free node" (in
  /// `position_nodes`'s report), "off"; after the hinge phase, "untangled by the hinge
  /// phase", "work bound (hinge phase)" or the passes' stop followed by "; hinge phase: N
  /// left".
  std::string stop;
};
/// The shape phase's last pass, for the hexes the local moves and the barrier left below
/// `hinge_shape_below` (slivers where moving one node, or a soft minimum, stalls). Repeatedly
/// the worst hex with a free node (ties: smallest id) is the seed: the free nodes of the hexes
/// within 1, then 2, ... `cluster_max_rings` rings of it are moved by `hinge_untangle` with
/// beta = 1.5 times the worst scaled Jacobian around it (at least 0.0075), the smoothing
/// starting at beta, then at 0.1, at most `hinge_shape_iterations` L-BFGS iterations each,
/// until a try is better; the sub-mesh of one ring more is weighed, its outer nodes held. A try
/// is better when the sorted scaled Jacobians of the widest sub-mesh (`cluster_max_rings` + 1
/// rings) are larger at their first difference, by at least 1e-4 (leximin): the worst hex
/// there never drops, none inverts, and a hex next to a worse one that cannot move may still
/// rise. The best try is kept; a seed with none is not tried again. Ends when no hex with a
/// free node is below the threshold or at `hinge_shape_max_work`. Runs nothing when a hex is
/// inverted. Deterministic. docs/geometry.md "Hinge pass".
/// \pre `fixed.size() == mesh.points.rows()` (checked: InvalidInput).
HingeShapeReport raise_worst_by_hinges(HexMesh& mesh, const std::vector<bool>& fixed,
                                       const PositionOptions& options);

/// Local untangling of the hexes the untangling and the repair left inverted: the inverted
/// hexes are grouped in clusters (hexes sharing a node), and each cluster grown by 1 ..
/// `cluster_max_rings` rings is positioned on its own by `position_nodes`, its boundary nodes
/// held, from the current positions and from the harmonic ones (without the shape phase).
/// The best of those (fewest inverted hexes, then the largest worst scaled Jacobian, judged
/// over the widest sub-mesh) is kept when it beats the current positions, so the inverted
/// count never rises and, at an equal count, the worst hex there never drops. `options` as
/// `position_nodes` takes them (it checks them; an invalid one makes every sub-mesh fail).
/// Up to `cluster_passes` passes, while a pass lowers the count. Then, with `cluster_hinge`
/// and hexes still inverted (and the work bound not reached), the hinge phase: each cluster
/// left, grown by 1 .. `cluster_max_rings` rings, has the free nodes of those hexes moved by
/// `hinge_untangle` (beta 0.02, then 0.05; every hex they touch weighed), kept on the same
/// terms. Deterministic.
/// docs/geometry.md "Local untangling" has the measurements.
/// \pre `fixed.size() == mesh.points.rows()` (checked: InvalidInput).
ClusterReport untangle_clusters(HexMesh& mesh, const std::vector<bool>& fixed,
                                const PositionOptions& options);
/// A hex corner that no position of the free nodes can make positive.
struct ImpossibleCorner {
  HexId hex;
  int corner = -1;     ///< 0..7 (= the hex's local node)
  HexId other;         ///< the hex with the same corner, or invalid for a fixed corner
  std::string reason;  ///< one line naming the elements
};

/// What `position_nodes` did.
struct PositionReport {
  std::size_t free_nodes = 0;
  bool harmonic_start = false;       ///< the harmonic placement was used as the start
  std::size_t outer_iterations = 0;  ///< rounds of (minimise, lower eps)
  std::size_t iterations = 0;        ///< L-BFGS iterations over all rounds
  std::size_t newton_steps = 0;      ///< projected Newton steps over all rounds
  /// Energy of the starting positions and of the final ones, both with the last round's eps
  /// (so the two are comparable; a tangled start gives a large `energy_before`).
  double energy_before = 0.0;
  double energy_after = 0.0;
  double epsilon = 0.0;             ///< last eps
  std::size_t inverted_before = 0;  ///< hexes with scaled Jacobian <= 0 (9 points)
  std::size_t inverted_after = 0;
  std::size_t corners_inverted_before = 0;  ///< corners with det <= 0
  std::size_t corners_inverted_after = 0;
  double min_scaled_jacobian_before = 0.0;
  double min_scaled_jacobian_after = 0.0;
  double mean_scaled_jacobian_before = 0.0;
  double mean_scaled_jacobian_after = 0.0;
  /// Bézier test after positioning: hexes certified valid / invalid / undecided.
  ValidityCounts certified;
  /// The Bézier test of every hex after positioning, indexed by hex.
  std::vector<Validity> validity;
  std::vector<ImpossibleCorner> impossible;  ///< corners excluded as impossible
  std::vector<HexId> inverted;               ///< hexes still inverted (scaled Jacobian <= 0)
  /// The optimisation settled: every corner it could act on is positive and the energy
  /// changed by less than `energy_tolerance` over the last round.
  bool converged = false;
  /// No hex inverted after positioning: every corner determinant > 0 and every scaled
  /// Jacobian (9 points) > 0. False whenever `impossible` is not empty.
  bool untangled = false;
  /// Why it stopped: "converged", "stalled: N corners still inverted", "iteration limit",
  /// "no free node", "good start: ..." (kept, see `PositionOptions::good_start`); followed by
  /// "; N impossible corners left out" (listed in `impossible`) when some corners could not
  /// be fixed by any position, and "; kept the ..." when the start was kept (`kept_start`).
  std::string stop;
  double seconds = 0.0;
  /// The optimised positions had more inverted hexes than the start, or a valid start had a
  /// better worst hex (min scaled Jacobian) than them, or the start repaired better than
  /// them (`repaired_from`): the start was kept.
  bool kept_start = false;
  /// The start was valid and good (`PositionOptions::good_start`): no untangling rounds ran.
  bool good_start = false;
  /// Quality after untangling, before the shape phase.
  double min_scaled_jacobian_untangled = 0.0;
  double mean_scaled_jacobian_untangled = 0.0;
  RepairReport repair;  ///< the repair of hexes left inverted by the untangling
  /// The positions `repair` started from: "untangled" (the rounds' result), "start" (kept
  /// over them), or empty when nothing was left inverted.
  std::string repaired_from;
  /// When the untangled positions were repaired and hexes were left inverted, the start is
  /// repaired too and the better result kept (fewer inverted hexes, then the larger
  /// minimum): this is the repair of the positions not kept (`ran` false when it did not
  /// run, e.g. when the start had been kept over the untangled positions already).
  RepairReport other_repair;
  /// The local untangling of the clusters still inverted after the repair
  /// (`untangle_clusters`).
  ClusterReport clusters;
  ShapeReport shape;  ///< the shape phase after untangling
};

/// The energy of one corner (see the file comment) for the edge matrix `edges` (columns
/// e1 e2 e3, in units of h), with its gradient (9 entries, column after column) and the
/// Hessian (9 x 9, same order, not projected) when asked. The kernel of `position_nodes`,
/// exposed for tests and for users who build their own solvers.
double winslow_corner_energy(const Eigen::Matrix3d& edges, double eps, double theta,
                             Eigen::Matrix<double, 9, 1>* gradient = nullptr,
                             Eigen::Matrix<double, 9, 9>* hessian = nullptr);

/// What `position_energy` computes besides the energy.
enum class EnergyDerivatives {
  Gradient,          ///< the gradient only
  Hessian,           ///< and the exact Hessian
  ProjectedHessian,  ///< and the Hessian with every corner's part projected to PSD, as the
                     ///< projected Newton step uses it
};

/// The energy `position_nodes` minimises, at the current positions of `mesh`, as a function
/// of the coordinates of the free nodes (those not `fixed` that some hex uses), for one eps.
struct PositionEnergy {
  double energy = 0.0;  ///< summed over every hex corner (none is left out)
  /// The free nodes, in node order; variable 3 i + c is coordinate c of free_nodes[i].
  std::vector<NodeId> free_nodes;
  Eigen::VectorXd gradient;             ///< with respect to the coordinates, in model units
  Eigen::SparseMatrix<double> hessian;  ///< symmetric, when asked (else empty)
};

/// The untangling energy with its derivatives, for inspection and tests (`position_nodes`
/// works with the same energy on scaled coordinates). `threads` as in PositionOptions.
/// 	hrow InvalidInput when `fixed` does not have one entry per node or a hex names a node
///        out of range.
[[nodiscard]] PositionEnergy position_energy(
    const HexMesh& mesh, const std::vector<bool>& fixed, double eps, double theta,
    EnergyDerivatives derivatives = EnergyDerivatives::Gradient, int threads = 0);

/// The corners of `mesh` that cannot become positive whatever the free nodes do: corners
/// whose four nodes are fixed and whose determinant is <= 0, and pairs of hexes with the
/// same corner node and the same three edges in opposite orientation.
/// \pre `fixed.size() == mesh.points.rows()`.
[[nodiscard]] std::vector<ImpossibleCorner> impossible_corners(const HexMesh& mesh,
                                                               const std::vector<bool>& fixed);

/// Moves the free nodes of `mesh` to untangle it and improve its shape (see the file
/// comment). Fixed nodes keep their coordinates exactly.
/// \pre the hexes are positively oriented overall (their total signed volume is > 0).
/// \throw InvalidInput when a hex names a node out of range, the fixed mask has the wrong
///        size, a real option lies outside its range or is NaN (theta and shape_target in
///        [0, 1], good_start and good_start_mean in [0, 2], stall_fraction in [0, 1],
///        max_total_iterations >= 0), or the total volume is not > 0 (not finite: coordinates
///        too large; 0 to rounding: a flat or collapsed boundary; negative: hexes mirrored).
/// \throw SolverError when the harmonic start fails (StartPosition::Harmonic or Auto): a
///        free node not connected by hex edges to any fixed node.
PositionReport position_nodes(HexMesh& mesh, const PositionOptions& options);

}  // namespace stcweave::primal
