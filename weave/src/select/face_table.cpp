/// Per-selection face tables (face_table.hpp).

#include "face_table.hpp"

#include <cmath>

#include "../rules/front_walks.hpp"

namespace stcweave::weave {

FaceTable face_table(const Front& front, bool angles) {
  FaceTable t;
  const std::size_t n = front.face_capacity();
  if (angles) {
    t.across.assign(4 * n, FaceSide{});
    t.angle.assign(4 * n, 180.0);
  }
  for (std::size_t fi = 0; angles && fi < n; ++fi) {
    const auto f = static_cast<FaceIndex>(fi);
    if (!front.is_alive(f)) continue;
    for (int k = 0; k < 4; ++k) {
      const std::size_t at = 4 * fi + static_cast<std::size_t>(k);
      const FaceSide g = front.across(f, k);
      t.across[at] = g;
      // edge_angle (rules/propagate.cpp) with `g` found once: keep the two identical.
      const double a = front.face(f).side_angle[static_cast<std::size_t>(k)];
      if (g.face == kNoFace) {
        t.angle[at] = a;
        continue;
      }
      const double b = front.face(g.face).side_angle[static_cast<std::size_t>(g.index)];
      const double da = a - 180.0, db = b - 180.0;
      if ((da >= 0.0) == (db >= 0.0)) {
        t.angle[at] = 180.0 + (std::abs(da) >= std::abs(db) ? da : db);
      } else {
        t.angle[at] = 180.0 + da + db;
      }
    }
  }
  // Face nodes, and the incidence lists of the nodes of live faces only, in the order met (a
  // node's list is read where it starts): late in a weave most nodes made are off the front.
  t.nodes.assign(n, stc::Quad{});
  const std::size_t num_nodes = front.num_nodes();
  t.first_incident.assign(num_nodes, 0);
  t.incident_count.assign(num_nodes, 0);
  t.incident.reserve(4 * front.num_faces());
  for (std::size_t fi = 0; fi < n; ++fi) {
    if (!front.is_alive(static_cast<FaceIndex>(fi))) continue;
    t.nodes[fi] = front.face(static_cast<FaceIndex>(fi)).nodes;
    for (const NodeId v : t.nodes[fi]) {
      if (t.incident_count[v.index()] != 0) continue;
      const auto& list = front.faces_at(v);
      t.first_incident[v.index()] = static_cast<std::uint32_t>(t.incident.size());
      t.incident_count[v.index()] = static_cast<std::uint32_t>(list.size());
      t.incident.insert(t.incident.end(), list.begin(), list.end());
    }
  }
  return t;
}

FrontLoops front_loops(const Front& front, const FaceTable& table) {
  return detail::front_loops_with(front, [&](FaceIndex f, int k) { return table.across_of(f, k); });
}

FrontComponents front_components(const Front& front, const FaceTable& table, Marks& marks) {
  return detail::front_components_with(
      front, marks, [&](NodeId v) { return table.faces_at(v); },
      [&](FaceIndex f) -> const stc::Quad& { return table.nodes_of(f); });
}

}  // namespace stcweave::weave
