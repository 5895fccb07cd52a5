/// The loops of the front (seed sect. 2.1): enter a face by one side, leave by the opposite
/// side, until the loop returns. The front changes at every rule, so a loop being shrunk is
/// kept as its transversal edges and re-found from them (`retrace`).

#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

Strip trace_strip(const Front& front, FaceIndex f, int entry) {
  Strip out;
  const stc::StripStep start{QuadId(f), entry};
  stc::StripStep cur = start;
  const std::size_t limit = 2 * front.num_faces() + 4;
  do {
    out.push_back(cur);
    const FaceSide next = front.across(face_of(cur), cur.exit());
    if (next.face == kNoFace) throw InternalError("weave: open front edge while tracing a loop");
    cur = stc::StripStep{QuadId(next.face), next.index};
    if (out.size() > limit) throw InternalError("weave: runaway loop trace");
  } while (cur != start);
  return out;
}

FrontLoops front_loops(const Front& front) {
  FrontLoops out;
  out.loop_of.assign(front.face_capacity(), {-1, -1});
  for (std::size_t fi = 0; fi < front.face_capacity(); ++fi) {
    const auto f = static_cast<FaceIndex>(fi);
    if (!front.is_alive(f)) continue;
    for (int dir = 0; dir < 2; ++dir) {
      if (out.loop_of[fi][static_cast<std::size_t>(dir)] >= 0) continue;
      Strip loop = trace_strip(front, f, dir);
      const auto id = static_cast<std::int32_t>(out.strips.size());
      for (const stc::StripStep& p : loop) {
        out.loop_of[static_cast<std::size_t>(face_of(p))][static_cast<std::size_t>(p.direction())] =
            id;
      }
      out.strips.push_back(std::move(loop));
    }
  }
  return out;
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
