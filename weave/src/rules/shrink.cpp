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
#include <cstdint>
#include <span>

#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

std::optional<std::string> shrink(WeaveState& state, WeaveContext& ctx, const Strip& initial,
                                  stc::LoopSide side) {
  const Front& front = state.front;
  std::vector<Transversal> edges = transversals(front, initial, side);
  std::vector<NodeId> order;
  // The strip positions holding each side node (entry or entry + 3), grouped per node in
  // strip order: node m's are steps[start[slot[m]] .. start[slot[m] + 1]), slot[m] being m's
  // index in `order` before it is sorted. Built once per strip, so that a blind chord tried at
  // every side node does not scan the whole strip for each.
  std::vector<std::uint32_t> slot, start, steps, cursor;
  for (;;) {
    seam_fixpoint(state, ctx);
    const Strip strip = retrace(front, edges);
    if (strip.empty()) return std::nullopt;
    // Re-traced from a side-d node's edge, the strip has the shrinking side as its side A.
    edges = transversals(front, strip, stc::LoopSide::Left);
    const FaceSet strip_faces = mark_strip_faces(ctx.faces, front, strip);
    // side nodes in loop order, each once, and the strip steps that hold each
    order.clear();
    start.assign(1, 0);
    slot.resize(front.num_nodes());
    const std::uint32_t seen = ctx.nodes.fresh(front.num_nodes());
    for (const stc::StripStep& p : strip) {
      const stc::Quad& n = front.face(face_of(p)).nodes;
      for (NodeId m : {quad_at(n, p.entry), quad_at(n, p.entry + 3)}) {
        if (!ctx.nodes.is(m.index(), seen)) {
          ctx.nodes.set(m.index(), seen);
          slot[m.index()] = static_cast<std::uint32_t>(order.size());
          order.push_back(m);
          start.push_back(0);
        }
        ++start[slot[m.index()] + 1];
      }
    }
    for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
    cursor.assign(start.begin(), start.end() - 1);
    steps.resize(start.back());
    for (std::size_t i = 0; i < strip.size(); ++i) {
      const stc::Quad& n = front.face(face_of(strip[i])).nodes;
      for (NodeId m : {quad_at(n, strip[i].entry), quad_at(n, strip[i].entry + 3)})
        steps[cursor[slot[m.index()]]++] = static_cast<std::uint32_t>(i);
    }
    const auto steps_of = [&](NodeId m) {
      const std::uint32_t k = slot[m.index()];
      return std::span<const std::uint32_t>(steps.data() + start[k], start[k + 1] - start[k]);
    };
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
        const RuleResult r = blind_chord(state, ctx, v, strip, strip_faces, steps_of(v));
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
