#pragma once
/// \file
/// Handles of a solid: which cycles of its boundary bound inside it, and whether one of them
/// is odd (then no hex mesh with this boundary exists: Erickson, DCG 2014).
///
/// Method (docs/topology.md): a Z2 homology basis of the boundary (tree-cotree, 2g cycles of
/// edges), each basis cycle pushed slightly into the solid and slightly out of it, and the
/// matrix of linking numbers mod 2 between inward and outward copies, counted as crossings in
/// a generic parallel projection. By Alexander duality a cycle is zero in H1(solid; Z2) iff it
/// links every outward cycle evenly, so the cycles that bound inside are the left kernel of
/// that matrix (dimension g). Short representatives are chosen greedily among the fundamental
/// cycles of breadth-first trees. Cycle length parity is a homomorphism on Z2 homology (quad
/// boundaries are even), so the g chosen cycles decide Erickson's condition.

#include <cstddef>
#include <string>
#include <vector>

#include "stcweave/primal/mesh.hpp"
#include "stcweave/stc/ids.hpp"

namespace stcweave::primal {

/// Settings of `diagnose_handles`.
struct HandleOptions {
  /// Push distance of a cycle node, as a fraction of the shortest surface edge at that node.
  double push_fraction = 0.05;
  /// Projection directions tried before giving up when a projection is degenerate.
  int max_projections = 8;
  /// Breadth-first roots used to look for short handle cycles: every node when the surface
  /// has at most `all_roots_up_to` nodes, else `sampled_roots` nodes evenly spaced by id.
  std::size_t all_roots_up_to = 1500;
  std::size_t sampled_roots = 300;
  /// Other simple cycles kept per handle (same class, distinct node sets, shortest first):
  /// `weave_solids` tries them when no disc spans the first one well.
  std::size_t alternatives = 6;
};

/// A cycle of the surface's edges that bounds inside the solid (zero in H1(solid; Z2)) but
/// not on the surface: the cross-section of a handle.
struct HandleCycle {
  ComponentId component;      ///< the surface component it lies on
  std::vector<NodeId> nodes;  ///< in order along the cycle, each once (simple cycle)
  [[nodiscard]] std::size_t length() const { return nodes.size(); }
  [[nodiscard]] bool is_even() const { return nodes.size() % 2 == 0; }
};

/// What `diagnose_handles` found.
struct HandleDiagnosis {
  /// False when the method could not decide (degenerate projections, a node whose normal
  /// cone is not pointed, a linking matrix of the wrong rank); `undecided_reason` says why.
  bool decided = false;
  std::string undecided_reason;
  int genus = 0;                         ///< sum over the components
  std::vector<int> genus_per_component;  ///< by component id
  /// A basis of the cycles that bound inside, as short simple cycles (g of them when every
  /// basis vector has a single-component representative among the candidates).
  std::vector<HandleCycle> handles;
  /// Per handle, other simple cycles of the same homology class, shortest first.
  std::vector<std::vector<HandleCycle>> alternatives;
  /// Basis vectors without a simple representative (cycles spread over several components,
  /// e.g. the solid between two nested tori): their edge count (its parity is what counts).
  std::vector<std::size_t> combined_lengths;
  int projections_tried = 0;
  /// Index in `handles` of an odd cycle, or -1 (an odd combined cycle is reported as
  /// `odd_combined`).
  int odd_handle = -1;
  bool odd_combined = false;

  /// True when decided and every handle cycle is even (Erickson's condition for genus > 0).
  [[nodiscard]] bool all_even() const { return decided && odd_handle < 0 && !odd_combined; }
};

/// Diagnoses the handles of the solid bounded by `mesh`.
/// \pre `mesh` is closed, manifold, consistently oriented with every normal pointing away from
///      the material (`orient_outward`), finite, without degenerate quads.
/// \throw InvalidInput when the point count does not match the surface.
[[nodiscard]] HandleDiagnosis diagnose_handles(const SurfaceMesh& mesh,
                                               const HandleOptions& options = {});

/// One cycle per handle, no two sharing a node, each the handle's own cycle or one of its
/// `alternatives` (same class, so the set is still a basis of the cycles that bound inside):
/// a depth-first search over the handles in order, each handle's own cycle first, then its
/// alternatives shortest first; at most `max_tries` partial choices. Empty when none is found
/// (or `diagnosis` has no handle). Cutting along the discs of cycles that share nodes is not
/// supported (`weave_solids`), so this is what it cuts.
[[nodiscard]] std::vector<std::vector<NodeId>> disjoint_handle_cycles(
    const HandleDiagnosis& diagnosis, std::size_t num_nodes, std::size_t max_tries = 10000);

/// "n12-n40-n7", with `names[v]` the printed id of surface node v (file ids); empty `names`
/// prints the surface ids.
[[nodiscard]] std::string cycle_name(const HandleCycle& cycle,
                                     const std::vector<NodeId>& names = {});

}  // namespace stcweave::primal
