/// The cross, seed sect. 2.2 (Fig. 2): three front faces pairwise sharing edges at a valence-3
/// node become three faces of one new hex. Its geometric precondition (RWW, sect. 2.2: "the
/// angles between the faces are not too flat") is ours to set: with `extended`, a corner
/// where more than one of its three edges is flatter than `little_sharp` is refused, unless
/// the shrink lifted the preconditions for this step (`WeaveContext::relax_geometry`). Its
/// topological precondition: the new hex shares at most a face (one of the three) with any
/// woven hex, and four nodes only as that face (`WeaveState::contact_conflict`).

#include <algorithm>

#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

RuleResult cross(WeaveState& state, WeaveContext& ctx, NodeId v) {
  const Front& front = state.front;
  const auto& at_v = front.faces_at(v);
  if (at_v.size() != 3) return RuleResult::refused("valence " + std::to_string(at_v.size()));
  const FaceIndex f1 = at_v[0];
  const stc::Quad q1 = quad_rotated(front.face(f1).nodes, front.corner_of(f1, v));
  const NodeId a = q1[1], xab = q1[2], b = q1[3];
  FaceIndex f2 = kNoFace, f3 = kNoFace;
  stc::Quad q2{}, q3{};
  for (FaceIndex f : {at_v[1], at_v[2]}) {
    const stc::Quad quad = quad_rotated(front.face(f).nodes, front.corner_of(f, v));
    if (quad[1] == b) {
      f2 = f;
      q2 = quad;
    } else if (quad[3] == a) {
      f3 = f;
      q3 = quad;
    }
  }
  if (f2 == kNoFace || f3 == kNoFace || q2[3] != q3[1])
    return RuleResult::refused("its three faces do not form a corner");
  const NodeId xbc = q2[2], c = q2[3], xca = q3[2];
  std::array<NodeId, 7> nodes{v, a, b, c, xab, xbc, xca};
  std::sort(nodes.begin(), nodes.end());
  if (std::adjacent_find(nodes.begin(), nodes.end()) != nodes.end())
    return RuleResult::refused("its three faces do not have 7 distinct nodes");

  // ---- geometric precondition ----
  const ExtendedParameters& par = ctx.parameters();
  if (ctx.extended() && par.flat_cross_precondition && !ctx.relax_geometry) {
    // The three edges at v: (v, a) and (b, v) in q1, (c, v) in q2.
    const int c1 = front.corner_of(f1, v), c2 = front.corner_of(f2, v);
    const std::array<double, 3> corner{edge_angle(front, f1, c1),
                                       edge_angle(front, f1, (c1 + 3) % 4),
                                       edge_angle(front, f2, (c2 + 3) % 4)};
    const auto flat = std::count_if(corner.begin(), corner.end(),
                                    [&par](double x) { return x > par.little_sharp; });
    if (flat > 1) {
      return RuleResult::refused("too flat a corner (" + std::to_string(flat) +
                                 " of its 3 edges flatter than " +
                                 std::to_string(static_cast<int>(par.little_sharp)) + " degrees)");
    }
  }
  // ---- topological precondition ----
  const FaceOwner o1 = front.face(f1).owner, o2 = front.face(f2).owner, o3 = front.face(f3).owner;
  const auto same_hex = [](const FaceOwner& p, const FaceOwner& q) {
    return p.is_hex() && q.is_hex() && p.id == q.id;
  };
  if (same_hex(o1, o2) || same_hex(o2, o3) || same_hex(o1, o3)) {
    return RuleResult::refused(
        "two of its faces belong to one hex (the new hex would share two faces with it)");
  }
  const std::array<FaceIndex, 3> used{f1, f2, f3};
  if (auto conflict = state.contact_conflict(nodes, used)) return RuleResult::refused(*conflict);
  // ---- move (make_hex propagates depth and angles) ----
  const NodeId w = state.new_node();
  const HexId hex = make_hex(state, ctx, {v, b, xab, a, c, xbc, w, xca}, used,
                             ctx.relax_geometry ? "cross-relaxed" : "cross", v);
  ++state.stats.crosses;
  return RuleResult::done(hex);
}

}  // namespace stcweave::weave
