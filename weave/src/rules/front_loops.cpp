/// The loops of the front (seed sect. 2.1): enter a face by one side, leave by the opposite
/// side, until the loop returns. The front changes at every rule, so a loop being shrunk is
/// kept as its transversal edges and re-found from them (`retrace`).

#include "front_walks.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

Strip trace_strip(const Front& front, FaceIndex f, int entry) {
  return detail::trace_strip_with(front, f, entry,
                                  [&](FaceIndex g, int k) { return front.across(g, k); });
}

FrontLoops front_loops(const Front& front) {
  return detail::front_loops_with(front, [&](FaceIndex g, int k) { return front.across(g, k); });
}

std::vector<Transversal> transversals(const Front& front, const Strip& strip, stc::LoopSide side) {
  std::vector<Transversal> out;
  out.reserve(strip.size());
  for (const stc::StripStep& p : strip) {
    const stc::Quad& n = front.face(face_of(p)).nodes;
    if (side == stc::LoopSide::Left) {
      out.push_back({quad_at(n, p.entry), quad_at(n, p.entry + 1)});
    } else {
      out.push_back({quad_at(n, p.entry + 1), quad_at(n, p.entry)});
    }
  }
  return out;
}

Strip retrace(const Front& front, const std::vector<Transversal>& edges) {
  for (const Transversal& t : edges) {
    const NodeId d = front.find(t.side_node), e = front.find(t.other);
    if (d == e) continue;
    const FaceSide fs = front.find_edge(d, e);
    if (fs.face != kNoFace) return trace_strip(front, fs.face, fs.index);
  }
  return {};
}

}  // namespace stcweave::weave
