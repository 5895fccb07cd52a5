/// The seam (or join), seed sect. 2.2 (Fig. 2): two front faces sharing the two edges at a
/// valence-2 node are glued, which completes a chord. In the primal: A = (v, a, x, b) and
/// B = (v, b, y, a) leave the front, x and y become one node, and every other pair of front
/// faces this merge makes coincident (same four nodes) is glued in the same step, so the front
/// never stays pinched.

#include <algorithm>

#include <boost/container/small_vector.hpp>

#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

RuleResult seam(WeaveState& state, WeaveContext& ctx, NodeId v) {
  Front& front = state.front;
  const auto& at_v = front.faces_at(v);
  if (at_v.size() != 2) return RuleResult::refused("valence " + std::to_string(at_v.size()));
  const FaceIndex fa = at_v[0];
  const FaceIndex fb = at_v[1];
  const stc::Quad qa = quad_rotated(front.face(fa).nodes, front.corner_of(fa, v));
  const stc::Quad qb = quad_rotated(front.face(fb).nodes, front.corner_of(fb, v));
  const NodeId a = qa[1], x = qa[2], b = qa[3];
  if (qb[1] != b || qb[3] != a) return RuleResult::refused("its two faces do not share both edges");
  const NodeId y = qb[2];
  const FaceOwner oa = front.face(fa).owner;
  const FaceOwner ob = front.face(fb).owner;

  // ---- precondition ----
  if (oa.is_input() && ob.is_input())
    return RuleResult::refused("it would glue two input quads " + oa.str() + " and " + ob.str());
  if (oa.is_hex() && ob.is_hex() && oa.id == ob.id)
    return RuleResult::refused("it would glue two faces of " + HexId(oa.id).str());
  // The merged node keeps an input id when there is one, else the smaller id.
  const NodeId keep = (x == y)                                                         ? x
                      : (front.is_input_node(y) || (!front.is_input_node(x) && y < x)) ? y
                                                                                       : x;
  const NodeId gone = (keep == x) ? y : x;
  if (x != y) {
    if (front.is_input_node(x) && front.is_input_node(y)) {
      return RuleResult::refused("it would merge two input nodes " + x.str() + " and " + y.str());
    }
    if (state.share_hex(x, y)) {
      return RuleResult::refused("it would merge " + x.str() + " and " + y.str() +
                                 ", two nodes of one hex");
    }
    for (FaceIndex f : front.faces_at(x)) {
      if (front.corner_of(f, y) >= 0) {
        return RuleResult::refused("it would merge " + x.str() + " and " + y.str() +
                                   ", two nodes of one front face");
      }
    }
  }
  if (x == y) {
    if (oa.is_hex() && ob.is_hex() &&
        state.common_nodes(HexId(oa.id), HexId(ob.id), gone, keep) > 4) {
      return RuleResult::refused("hexes " + HexId(oa.id).str() + " and " + HexId(ob.id).str() +
                                 " would share more than one face");
    }
  } else if (auto conflict = state.merge_conflict(x, y, keep, gone)) {
    return RuleResult::refused(*conflict);
  }
  // Faces that the merge makes coincide, and the check that the front is not pinched.
  // (Inline buffers: a seam is most of a weave's rules, and these hold a few entries each;
  // heap vectors here cost four allocations per seam.)
  using Nodes = boost::container::small_vector<NodeId, 24>;
  boost::container::small_vector<std::pair<FaceIndex, FaceIndex>, 4> coincident;
  if (x != y) {
    const auto neighbours = [&front](NodeId n, FaceIndex skip, Nodes& out) {
      for (FaceIndex f : front.faces_at(n)) {
        if (f == skip) continue;
        const int c = front.corner_of(f, n);
        out.push_back(quad_at(front.face(f).nodes, c + 1));
        out.push_back(quad_at(front.face(f).nodes, c + 3));
      }
    };
    Nodes nx, ny, covered;
    neighbours(x, fa, nx);
    neighbours(y, fb, ny);
    for (FaceIndex f : front.faces_at(x)) {
      if (f == fa) continue;
      const auto key = quad_sorted(front.face(f).nodes);
      for (FaceIndex g : front.faces_at(y)) {
        if (g == fb) continue;
        stc::Quad gq = front.face(g).nodes;
        for (NodeId& n : gq)
          if (n == y) n = x;
        if (quad_sorted(gq) != key) continue;
        const FaceOwner of = front.face(f).owner, og = front.face(g).owner;
        if (of.is_input() && og.is_input()) {
          return RuleResult::refused("it would make input quads " + of.str() + " and " + og.str() +
                                     " coincide");
        }
        if (of.is_hex() && og.is_hex() && of.id == og.id)
          return RuleResult::refused("it would glue two faces of " + HexId(of.id).str());
        coincident.emplace_back(f, g);
        const int c = front.corner_of(f, x);
        covered.push_back(quad_at(front.face(f).nodes, c + 1));
        covered.push_back(quad_at(front.face(f).nodes, c + 3));
      }
    }
    for (NodeId p : nx) {
      if (p == a || p == b) continue;
      if (std::find(ny.begin(), ny.end(), p) == ny.end()) continue;
      if (std::find(covered.begin(), covered.end(), p) == covered.end()) {
        return RuleResult::refused("merging " + x.str() + " and " + y.str() +
                                   " would pinch the front along edge " + x.str() + "-" + p.str());
      }
    }
  }

  // ---- move ----
  const std::array<FaceOwner, 2> whiskers{oa, ob};
  state.link(oa, ob);
  state.push_nodes_of(fa);
  state.push_nodes_of(fb);
  front.remove_face(fa);
  front.remove_face(fb);
  if (x != y) {
    state.merge_nodes(keep, gone);
    for (const auto& [f, g] : coincident) {
      if (!front.is_alive(f) || !front.is_alive(g)) continue;
      state.link(front.face(f).owner, front.face(g).owner);
      state.push_nodes_of(f);
      state.push_nodes_of(g);
      front.remove_face(f);
      front.remove_face(g);
      ++state.stats.coincident_glues;
    }
    for (FaceIndex f : front.faces_at(keep)) state.push_nodes_of(f);
  }
  // ---- propagation: a seam introduces no face, nothing to carry (seed sect. 6) ----
  ++state.stats.seams;
  ctx.after_rule(state, x == y ? "seam-coincident" : "seam", v, whiskers, HexId::invalid());
  return RuleResult::done();
}

void seam_fixpoint(WeaveState& state, WeaveContext& ctx) {
  for (NodeId n : state.blocked_seams) state.seam_work.push_back(n);
  state.blocked_seams.clear();
  std::vector<NodeId> blocked;
  while (!state.seam_work.empty()) {
    const NodeId n = state.front.find(state.seam_work.back());
    state.seam_work.pop_back();
    if (state.front.valence(n) != 2) continue;
    if (!seam(state, ctx, n)) {
      ++state.stats.blocked_seams;
      if (std::find(blocked.begin(), blocked.end(), n) == blocked.end()) blocked.push_back(n);
    }
  }
  for (NodeId n : blocked) {
    if (state.front.valence(state.front.find(n)) == 2)
      state.blocked_seams.push_back(state.front.find(n));
  }
}

}  // namespace stcweave::weave
