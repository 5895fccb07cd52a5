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

namespace {

/// Sorts `order[from..]` by front valence, keeping loop order among equal valences: what
/// `std::stable_sort` by valence gives, by counting (valences are small integers), so that a
/// shrink whose first node is blocked does not pay n log n at every step of a long loop.
void stable_sort_by_valence(const Front& front, std::vector<NodeId>& order, std::size_t from,
                            std::vector<NodeId>& buffer, std::vector<std::uint32_t>& count) {
  std::size_t top = 0;
  for (std::size_t i = from; i < order.size(); ++i) top = std::max(top, front.valence(order[i]));
  count.assign(top + 2, 0);
  for (std::size_t i = from; i < order.size(); ++i) ++count[front.valence(order[i]) + 1];
  for (std::size_t k = 0; k + 1 < count.size(); ++k) count[k + 1] += count[k];
  buffer.resize(order.size() - from);
  for (std::size_t i = from; i < order.size(); ++i)
    buffer[count[front.valence(order[i])]++] = order[i];
  std::copy(buffer.begin(), buffer.end(), order.begin() + static_cast<std::ptrdiff_t>(from));
}

}  // namespace

std::optional<std::string> shrink(WeaveState& state, WeaveContext& ctx, const Strip& initial,
                                  stc::LoopSide side) {
  const Front& front = state.front;
  std::vector<Transversal> edges = transversals(front, initial, side);
  std::vector<NodeId> order;
  // The strip positions holding each side node (entry or entry + 3), grouped per node in
  // strip order: node m's are steps[start[slot[m]] .. start[slot[m] + 1]), slot[m] being m's
  // index in `order` before it is sorted. Built at most once per strip (when first read), so
  // that a blind chord tried at every side node does not scan the whole strip for each.
  std::vector<std::uint32_t> slot, start, steps, cursor;
  std::vector<NodeId> by_valence_buffer;
  std::vector<std::uint32_t> by_valence_count;
  for (;;) {
    seam_fixpoint(state, ctx);
    const Strip strip = retrace(front, edges);
    if (strip.empty()) return std::nullopt;
    // Re-traced from a side-d node's edge, the strip has the shrinking side as its side A.
    edges = transversals(front, strip, stc::LoopSide::Left);
    // The fewest-sided side node first (ties: loop order): one scan of the strip finds it.
    // Its rule usually applies; the table of side nodes below (each once, in loop order, with
    // the strip steps that hold it) is built only when a blind chord needs it or the first
    // node is blocked, so that a long loop is not indexed again for every cross.
    NodeId first = NodeId();
    std::size_t first_valence = 0;
    for (const stc::StripStep& p : strip) {
      const stc::Quad& n = front.face(face_of(p)).nodes;
      for (NodeId m : {quad_at(n, p.entry), quad_at(n, p.entry + 3)}) {
        const std::size_t k = front.valence(m);
        if (!first.is_valid() || k < first_valence) {
          first = m;
          first_valence = k;
        }
      }
    }
    FaceSet strip_faces;
    bool indexed = false;
    const auto index_side_nodes = [&] {
      indexed = true;
      strip_faces = mark_strip_faces(ctx.faces, front, strip);
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
      // The first node to the front, the others in loop order (sorted when it is blocked).
      const auto at = std::find(order.begin(), order.end(), first);
      std::rotate(order.begin(), at, at + 1);
    };
    const auto steps_of = [&](NodeId m) {
      const std::uint32_t k = slot[m.index()];
      return std::span<const std::uint32_t>(steps.data() + start[k], start[k + 1] - start[k]);
    };
    std::string reasons;
    bool applied = false;
    for (std::size_t idx = 0; idx == 0 || idx < order.size(); ++idx) {
      if (idx == 1) stable_sort_by_valence(front, order, 1, by_valence_buffer, by_valence_count);
      const NodeId v = idx == 0 ? first : order[idx];
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
        if (!indexed) index_side_nodes();
        const RuleResult r = blind_chord(state, ctx, v, strip, strip_faces, steps_of(v));
        applied = r.applied;
        if (!applied) why = "blind chord refused: " + r.why;
      }
      if (applied) break;
      if (reasons.size() < 600) reasons += (reasons.empty() ? "" : "; ") + v.str() + ": " + why;
      if (!indexed) index_side_nodes();
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
