/// Loop shrinking, seed sect. 2.2 (Fig. 3-4): contracting a loop sweeps out a sheet behind
/// it, i.e. one layer of hexes. The faces next to the loop on the shrinking side are
/// collapsed one after the other, the one with the fewest sides first: at a side node of
/// valence 2 a seam, of valence 3 a cross, of valence k >= 4 a blind chord (k -> k - 1).
/// After every rule the seams run to a fixpoint and the loop is re-found from its transversal
/// edges; it is gone when none of them is left on the front.
///
/// With `extended`, when every side node is blocked, the geometric preconditions give way for
/// one step (RWW: "it is usually necessary to turn the geometric rules off to complete the
/// weave"). When every node is still blocked the shrink fails, naming each node and why.

#include <algorithm>

#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

std::optional<std::string> shrink(WeaveState& state, WeaveContext& ctx, const Strip& initial,
                                  stc::LoopSide side) {
  const Front& front = state.front;
  std::vector<Transversal> edges = transversals(front, initial, side);
  std::vector<NodeId> order;
  for (;;) {
    seam_fixpoint(state, ctx);
    const Strip strip = retrace(front, edges);
    if (strip.empty()) return std::nullopt;
    // Re-traced from a side-d node's edge, the strip has the shrinking side as its side A.
    edges = transversals(front, strip, stc::LoopSide::Left);
    const FaceSet strip_faces = mark_strip_faces(ctx.faces, front, strip);
    // side nodes in loop order, each once
    order.clear();
    const std::uint32_t seen = ctx.nodes.fresh(front.num_nodes());
    for (const stc::StripStep& p : strip) {
      const stc::Quad& n = front.face(face_of(p)).nodes;
      for (NodeId m : {quad_at(n, p.entry), quad_at(n, p.entry + 3)}) {
        if (ctx.nodes.is(m.index(), seen)) continue;
        ctx.nodes.set(m.index(), seen);
        order.push_back(m);
      }
    }
    // The fewest-sided node first (ties: loop order). Usually its rule applies, so find it
    // by a scan and sort the rest only when it is blocked.
    const auto by_valence = [&front](NodeId p, NodeId q) {
      return front.valence(p) < front.valence(q);
    };
    const auto first = std::min_element(order.begin(), order.end(), by_valence);
    std::rotate(order.begin(), first, first + 1);
    std::string reasons;
    bool applied = false;
    bool sorted = false;
    for (std::size_t idx = 0; idx < order.size(); ++idx) {
      if (idx == 1 && !sorted) {
        std::stable_sort(order.begin() + 1, order.end(), by_valence);
        sorted = true;
      }
      const NodeId v = order[idx];
      std::string why;
      const std::size_t k = front.valence(v);
      if (k == 2) {
        why = "valence 2 but its seam is blocked";
        const RuleResult r = seam(state, ctx, v);
        if (!r) {
          why += " (" + r.why + ")";
        } else {
          applied = true;
        }
      } else if (k == 3) {
        const RuleResult r = cross(state, ctx, v);
        applied = r.applied;
        if (!applied) why = "cross refused: " + r.why;
      } else {
        const RuleResult r = blind_chord(state, ctx, v, strip, strip_faces);
        applied = r.applied;
        if (!applied) why = "blind chord refused: " + r.why;
      }
      if (applied) break;
      if (reasons.size() < 600) reasons += (reasons.empty() ? "" : "; ") + v.str() + ": " + why;
    }
    if (!applied && ctx.extended() && ctx.parameters().flat_cross_precondition &&
        !ctx.relax_geometry) {
      ctx.relax_geometry = true;
      ++state.stats.relaxed_preconditions;
      continue;
    }
    ctx.relax_geometry = false;
    if (!applied) return "every node on the shrinking side is blocked: " + reasons;
  }
}

}  // namespace stcweave::weave
