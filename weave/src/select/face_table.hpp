#pragma once
/// Per-selection tables of the front: the face across every face side and the angle of every
/// front edge, computed once for a selection instead of searched by every loop's properties.
///
/// The front does not change while a selection's candidates are computed, so these tables are
/// exact for that time. `Front::across` finds a neighbour by scanning the incidence list of a
/// node; the properties of every loop ask it for every face of both sides, so a selection used
/// to repeat that search (loops x faces) times. Built here once per selection, (faces) searches.

#include <cstdint>
#include <span>
#include <vector>

#include "stcweave/weave/front.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

/// The neighbours and edge angles of every face side of a front, at one moment.
struct FaceTable {
  /// Per face slot `f` and side `k`, at `4 f + k`: `front.across(f, k)` (dead slots: none).
  std::vector<FaceSide> across;
  /// At `4 f + k`: `edge_angle(front, f, k)`, the same arithmetic on the same floats.
  std::vector<double> angle;

  /// The incidence lists of the front's nodes, back to back: node `v`'s faces (in
  /// `Front::faces_at` order) are `incident[first_incident[v] .. + incident_count[v])` (nodes
  /// off the front: none).
  std::vector<std::uint32_t> first_incident;
  std::vector<std::uint32_t> incident_count;
  std::vector<FaceIndex> incident;
  /// Per face slot, its nodes (`Front::face(f).nodes`; dead slots: zeros).
  std::vector<stc::Quad> nodes;

  /// Node `v`'s faces.
  [[nodiscard]] std::span<const FaceIndex> faces_at(NodeId v) const {
    return {incident.data() + first_incident[v.index()], incident_count[v.index()]};
  }
  [[nodiscard]] const stc::Quad& nodes_of(FaceIndex f) const {
    return nodes[static_cast<std::size_t>(f)];
  }
  [[nodiscard]] const FaceSide& across_of(FaceIndex f, int k) const {
    return across[4 * static_cast<std::size_t>(f) + static_cast<std::size_t>(k)];
  }
  [[nodiscard]] double angle_of(FaceIndex f, int k) const {
    return angle[4 * static_cast<std::size_t>(f) + static_cast<std::size_t>(k)];
  }
};

/// The tables of `front` as it is now; without `angles`, `across` and `angle` stay empty (the
/// reliable weights read only the incidence lists and face nodes).
[[nodiscard]] FaceTable face_table(const Front& front, bool angles = true);

/// `front_loops(front)` read from `table` (built with angles, so with `across`): the same
/// loops in the same order, each step found by lookup instead of a scan of a node's faces.
[[nodiscard]] FrontLoops front_loops(const Front& front, const FaceTable& table);

/// `front_components(front, marks)` read from `table`: the same components.
[[nodiscard]] FrontComponents front_components(const Front& front, const FaceTable& table,
                                               Marks& marks);

}  // namespace stcweave::weave
