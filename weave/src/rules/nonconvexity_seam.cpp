/// Non-convexity seam, seed sect. 5.2 (Fig. 11), as we read it (docs/extended-rules.md).
///
/// A chord arriving next to a non-convex part of the boundary is joined directly to the
/// boundary face it meets, instead of letting basic rules fill the re-entrant region. F2 is
/// an input quad, F1 a hex face across its side E (they share only E). E is convex, a side of
/// F2 next to E is non-convex, and F1's two nodes off E are interior nodes (the seed names
/// F2's, which cannot be: input nodes never merge). F1 is folded onto F2 about E: its two far
/// nodes merge with F2's and the two faces, now coincident, are glued. The faces this leaves
/// sharing two edges are sewn by the basic seams that follow. It creates no face, so it
/// propagates no depth; the angles stay with the faces that remain. The state is saved first
/// and restored when the fold would break the front.

#include <algorithm>

#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

RuleResult nonconvexity_seam(WeaveState& state, WeaveContext& ctx, FaceIndex f2, int side) {
  const ExtendedParameters& par = ctx.parameters();
  {
    const Front& front = state.front;
    const FaceSide across = front.across(f2, side);
    if (across.face == kNoFace || !front.face(across.face).owner.is_hex())
      return RuleResult::refused("no hex face across");
    if (edge_angle(front, f2, side) > par.little_sharp)
      return RuleResult::refused("the common edge is not convex");
    if (edge_angle(front, f2, (side + 1) % 4) <= par.flat &&
        edge_angle(front, f2, (side + 3) % 4) <= par.flat)
      return RuleResult::refused("no non-convex edge next to the common edge");
  }
  const FaceSide across = state.front.across(f2, side);
  const FaceIndex f1 = across.face;
  const stc::Quad q2 = state.front.face(f2).nodes;
  const stc::Quad q1 = state.front.face(f1).nodes;
  // q2 = [v, u, c, d] from its side `side`; q1 holds u -> v: q1 = [u, v, a, b].
  const NodeId v = quad_at(q2, side), u = quad_at(q2, side + 1), c = quad_at(q2, side + 2),
               d = quad_at(q2, side + 3);
  const NodeId a = quad_at(q1, across.index + 2), b = quad_at(q1, across.index + 3);
  if (quad_at(q1, across.index) != u || quad_at(q1, across.index + 1) != v)
    return RuleResult::refused("the faces do not hold their common edge in opposite directions");
  if (a.index() < state.front.num_input_nodes() || b.index() < state.front.num_input_nodes())
    return RuleResult::refused("a node of the hex face off the common edge is an input node");
  for (NodeId n : {a, b})
    if (n == c || n == d) return RuleResult::refused("the faces share more than one edge");
  // Folding about E takes a (next to v in q1) onto d (next to v in q2), b onto c.
  if (state.share_hex(a, d) || state.share_hex(b, c))
    return RuleResult::refused("a merge would join two nodes of one hex");
  if (auto conflict = state.merge_conflict(a, d, d, a)) return RuleResult::refused(*conflict);

  // ---- move, on a saved state ----
  WeaveState::Checkpoint saved = state.checkpoint();
  state.merge_nodes(d, a);
  if (auto conflict = state.merge_conflict(b, c, c, b)) {
    state.roll_back(std::move(saved));
    return RuleResult::refused(*conflict);
  }
  state.merge_nodes(c, b);
  // Glue every pair of faces that now coincide around the four nodes (q1 and q2 first).
  Front& front = state.front;
  std::vector<FaceOwner> whiskers;
  bool ok = true;
  for (NodeId n : {c, d, u, v}) {
    const auto& faces = front.faces_at(n);
    for (std::size_t i = 0; i < faces.size() && ok; ++i) {
      for (std::size_t j = i + 1; j < faces.size(); ++j) {
        const FaceIndex p = faces[i], q = faces[j];
        if (quad_sorted(front.face(p).nodes) != quad_sorted(front.face(q).nodes)) continue;
        const FaceOwner op = front.face(p).owner, oq = front.face(q).owner;
        if ((op.is_input() && oq.is_input()) || (op.is_hex() && oq.is_hex() && op.id == oq.id)) {
          ok = false;
          break;
        }
        whiskers.push_back(op);
        whiskers.push_back(oq);
        state.link(op, oq);
        state.push_nodes_of(p);
        state.push_nodes_of(q);
        front.remove_face(p < q ? q : p);
        front.remove_face(p < q ? p : q);
        j = faces.size();  // the list changed: rescan this node
        i = static_cast<std::size_t>(-1);
        break;
      }
    }
  }
  std::optional<std::string> broken;
  if (ok) broken = front.check_invariants();
  if (!ok || broken) {
    state.roll_back(std::move(saved));
    return RuleResult::refused(ok ? "the fold would break the front: " + *broken
                                  : "the fold would glue two faces that must not meet");
  }
  state.release(std::move(saved));
  for (FaceIndex f : front.faces_at(c)) state.push_nodes_of(f);
  for (FaceIndex f : front.faces_at(d)) state.push_nodes_of(f);
  ++state.stats.nonconvexity_seams;
  ctx.after_rule(state, "nonconvexity-seam", v, whiskers, HexId::invalid());
  return RuleResult::done();
}

std::size_t nonconvexity_seams(WeaveState& state, WeaveContext& ctx) {
  std::size_t applied = 0;
  for (std::size_t fi = 0; fi < state.front.face_capacity(); ++fi) {
    const auto f = static_cast<FaceIndex>(fi);
    for (int side = 0; side < 4; ++side) {
      if (!state.front.is_alive(f) || !state.front.face(f).owner.is_input()) break;
      if (nonconvexity_seam(state, ctx, f, side)) {
        ++applied;
        seam_fixpoint(state, ctx);
      }
    }
  }
  return applied;
}

}  // namespace stcweave::weave
