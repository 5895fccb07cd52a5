/// Propagation of geometric information, seed sect. 6 (Fig. 12-14).
///
/// The high-level and intermediate rules read properties of the input surface (face depth,
/// edge angles). Instead of recomputing geometry, every rule that makes a hex hands them on to
/// the faces it puts on the front:
/// - depth: a new face opposite a used face of depth i >= 0 gets i + 1; every other new face
///   gets -1 (also opposite a -1 face). Seams create no face and propagate nothing.
/// - angles: each front face stores one angle per side. A new face opposite a used face F
///   takes, on each side, the angle F stores on the parallel side (a hex edge joins their
///   corners); other new faces are flat. The angle of a front edge combines the two faces'
///   stored angles (`edge_angle`): a convex and a non-convex deviation from 180 cancel (Fig.
///   12), two deviations the same way keep the larger.
/// F's own stored value is carried, not the combined one: measured, the combined value breaks
/// the structured results on boxes (cube_tf_medium 6,859 -> 8,655 hexes) although it helps the
/// larger L-block (docs/extended-rules.md).

#include <algorithm>
#include <cmath>

#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

double edge_angle(const Front& front, FaceIndex f, int side) {
  const double a = front.face(f).side_angle[static_cast<std::size_t>(side)];
  const FaceSide g = front.across(f, side);
  if (g.face == kNoFace) return a;
  const double b = front.face(g.face).side_angle[static_cast<std::size_t>(g.index)];
  const double da = a - 180.0, db = b - 180.0;
  if ((da >= 0.0) == (db >= 0.0)) return 180.0 + (std::abs(da) >= std::abs(db) ? da : db);
  return 180.0 + da + db;
}

Propagated propagate(const Front& front, const stc::Hex& hex,
                     const std::array<FaceIndex, 6>& used) {
  Propagated out;
  for (int lf = 0; lf < 6; ++lf) {
    const FaceIndex opposite =
        used[static_cast<std::size_t>(kOppositeFace[static_cast<std::size_t>(lf)])];
    out.depth[static_cast<std::size_t>(lf)] =
        (opposite != kNoFace && front.face(opposite).depth >= 0) ? front.face(opposite).depth + 1
                                                                 : -1;
  }
  for (int lf = 0; lf < 6; ++lf) {
    auto& angles = out.side_angle[static_cast<std::size_t>(lf)];
    angles.fill(180.0F);
    if (used[static_cast<std::size_t>(lf)] != kNoFace) continue;
    const FaceIndex opposite =
        used[static_cast<std::size_t>(kOppositeFace[static_cast<std::size_t>(lf)])];
    if (opposite == kNoFace) continue;
    const stc::Quad mine = stc::reversed(stc::hex_face(hex, lf));
    const FrontFace& old = front.face(opposite);
    // the node of `old` joined to hex node n by a hex edge
    const auto partner = [&](NodeId n) {
      int local = 0;
      while (hex[static_cast<std::size_t>(local)] != n) ++local;
      for (const auto& e : stc::kHexEdges) {
        const int other = e[0] == local ? e[1] : (e[1] == local ? e[0] : -1);
        if (other < 0) continue;
        const NodeId m = hex[static_cast<std::size_t>(other)];
        if (std::find(old.nodes.begin(), old.nodes.end(), m) != old.nodes.end()) return m;
      }
      return NodeId::invalid();
    };
    for (int j = 0; j < 4; ++j) {
      const NodeId a = partner(quad_at(mine, j)), b = partner(quad_at(mine, j + 1));
      for (int k = 0; k < 4; ++k) {
        const NodeId p = quad_at(old.nodes, k), q = quad_at(old.nodes, k + 1);
        if ((p == a && q == b) || (p == b && q == a))
          angles[static_cast<std::size_t>(j)] = old.side_angle[static_cast<std::size_t>(k)];
      }
    }
  }
  return out;
}

}  // namespace stcweave::weave
