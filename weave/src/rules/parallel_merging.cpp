/// Parallel merging, seed sect. 5.1 (Fig. 10), as we read it (docs/extended-rules.md).
///
/// Three loops parallel and next to each other, l in the middle, all edges between them
/// sharp: the seed merges the outer two (ll, lr) into one loop and shrinks it, which makes a
/// torus of hexes. Our reading: l's strip is one face high, its side edges are sharp on both
/// sides, and its transversal edges map the rim of the region on side A (bounded by ll) onto
/// the rim on side B (bounded by lr). When that map extends, face by face, to an isomorphism
/// between the two regions (two discs facing each other), ll and lr are the two ends of one
/// sheet: it is closed at once by one hex per face pair (the first chord made, along the
/// strip, is the seed's torus of hexes). No node is created or merged.

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/shared_nodes.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {
namespace {

/// Why two of the new hexes `hexes` would share more than a face, or four nodes that are not
/// a face of both, if two would (the batch's own `WeaveState::contact_conflict`).
std::optional<std::string> batch_contact_conflict(const std::vector<stc::Hex>& hexes) {
  const auto has_face = [](const stc::Hex& h, const std::array<NodeId, 4>& key) {
    for (int lf = 0; lf < 6; ++lf)
      if (quad_sorted(stc::hex_face(h, lf)) == key) return true;
    return false;
  };
  for (const stc::SharedNodesPair& pair : stc::pairs_sharing_nodes(hexes, 4)) {
    const std::size_t a = pair.first;
    const std::size_t b = pair.second;
    const std::size_t shared = pair.shared;
    bool face = false;
    if (shared == 4) {
      std::array<NodeId, 4> key{};
      std::size_t k = 0;
      for (NodeId n : hexes[a])
        if (std::find(hexes[b].begin(), hexes[b].end(), n) != hexes[b].end()) key[k++] = n;
      std::sort(key.begin(), key.end());
      face = has_face(hexes[a], key) && has_face(hexes[b], key);
    }
    if (!face) {
      return "two new hexes would share " + std::to_string(shared) +
             " nodes other than a face (at " + hexes[a][0].str() + " and " + hexes[b][0].str() +
             ")";
    }
  }
  return std::nullopt;
}

}  // namespace

RuleResult parallel_merging(WeaveState& state, WeaveContext& ctx, const Strip& strip,
                            const FrontComponents& components) {
  const Front& front = state.front;
  // ---- precondition: a strip one face high whose transversal edges map rim onto rim ----
  const std::uint32_t strip_stamp = ctx.faces.fresh(front.face_capacity());
  const FaceSet on_strip{&ctx.faces, strip_stamp};
  for (const stc::StripStep& p : strip) {
    if (on_strip.contains(face_of(p))) return RuleResult::refused("the strip passes a face twice");
    ctx.faces.set(static_cast<std::size_t>(face_of(p)), strip_stamp);
  }
  std::unordered_map<std::size_t, NodeId> image, preimage;
  const auto assign = [&](NodeId a, NodeId b) {
    const auto ia = image.find(a.index());
    if (ia != image.end()) return ia->second == b;
    const auto ib = preimage.find(b.index());
    if (ib != preimage.end()) return false;
    if (image.count(b.index()) != 0 || preimage.count(a.index()) != 0) return false;
    image.emplace(a.index(), b);
    preimage.emplace(b.index(), a);
    return true;
  };
  // Side A's rim faces, each once (a face at a corner of the rim borders two strip faces).
  const std::uint32_t in_a = ctx.faces2.fresh(front.face_capacity());
  const FaceSet seen{&ctx.faces2, in_a};
  std::vector<FaceIndex> queue;
  for (const stc::StripStep& p : strip) {
    const FaceIndex f = face_of(p);
    const stc::Quad& n = front.face(f).nodes;
    if (!assign(quad_at(n, p.entry), quad_at(n, p.entry + 1)) ||
        !assign(quad_at(n, p.entry + 3), quad_at(n, p.entry + 2))) {
      return RuleResult::refused("the strip's transversal edges do not map one rim onto the other");
    }
    for (int side : {(p.entry + 3) % 4, (p.entry + 1) % 4}) {
      const FaceSide g = front.across(f, side);
      if (g.face == kNoFace || on_strip.contains(g.face))
        return RuleResult::refused("the strip is more than one face high");
      if (side == (p.entry + 3) % 4 && !seen.contains(g.face)) {
        ctx.faces2.set(static_cast<std::size_t>(g.face), in_a);
        queue.push_back(g.face);
      }
    }
  }
  // Extend the map over side A's region, face by face, from the rim inward.
  std::vector<std::pair<FaceIndex, FaceIndex>> pairs;
  std::vector<FaceIndex> images;
  for (std::size_t qi = 0; qi < queue.size(); ++qi) {
    const FaceIndex f = queue[qi];
    const stc::Quad& fq = front.face(f).nodes;
    int k = -1;
    for (int j = 0; j < 4 && k < 0; ++j) {
      if (image.count(quad_at(fq, j).index()) != 0 && image.count(quad_at(fq, j + 1).index()) != 0)
        k = j;
    }
    if (k < 0) {  // reached before any of its edges was mapped: try again later
      if (qi + queue.size() > 8 * front.num_faces())
        return RuleResult::refused("the region on side A is not a disc the strip maps");
      queue.push_back(f);
      continue;
    }
    const NodeId u = quad_at(fq, k), v = quad_at(fq, k + 1), w = quad_at(fq, k + 2),
                 x = quad_at(fq, k + 3);
    const FaceSide gs = front.find_edge(image.at(v.index()), image.at(u.index()));
    if (gs.face == kNoFace || on_strip.contains(gs.face) || seen.contains(gs.face))
      return RuleResult::refused("no face of side B faces " + front.face(f).owner.str());
    const stc::Quad& gq = front.face(gs.face).nodes;
    if (!assign(x, quad_at(gq, gs.index + 2)) || !assign(w, quad_at(gq, gs.index + 3)))
      return RuleResult::refused("the two regions differ at " + front.face(f).owner.str());
    const FaceOwner of = front.face(f).owner, og = front.face(gs.face).owner;
    if (of.is_hex() && og.is_hex() && of.id == og.id) {
      return RuleResult::refused("the faces " + of.str() + " and " + og.str() +
                                 " belong to one hex");
    }
    pairs.emplace_back(f, gs.face);
    images.push_back(gs.face);
    for (int j = 0; j < 4; ++j) {
      const FaceSide h = front.across(f, j);
      if (h.face == kNoFace || on_strip.contains(h.face) || seen.contains(h.face)) continue;
      ctx.faces2.set(static_cast<std::size_t>(h.face), in_a);
      queue.push_back(h.face);
    }
  }
  std::sort(images.begin(), images.end());
  if (std::adjacent_find(images.begin(), images.end()) != images.end())
    return RuleResult::refused("two faces of side A face the same face of side B");
  for (FaceIndex g : images)
    if (seen.contains(g)) return RuleResult::refused("the regions on the two sides overlap");
  // Every face of the front component must be used: the strip, side A and side B.
  const std::size_t component =
      components.component_of[front.face(face_of(strip.front())).nodes[0].index()];
  std::size_t faces_in_component = 0;
  for (std::size_t fi = 0; fi < front.face_capacity(); ++fi) {
    const auto f = static_cast<FaceIndex>(fi);
    if (front.is_alive(f) && components.component_of[front.face(f).nodes[0].index()] == component)
      ++faces_in_component;
  }
  if (faces_in_component != strip.size() + 2 * pairs.size())
    return RuleResult::refused("the strip and the two regions are not the whole front component");
  // No new hex may share more than a face with a woven hex (two faces with one hex included)
  // or with another new hex, nor four nodes other than the face between them.
  const auto front_face_of = [&front](const stc::Hex& hex, int lf) -> FaceIndex {
    const auto key = quad_sorted(stc::hex_face(hex, lf));
    for (FaceIndex g : front.faces_at(
             hex[static_cast<std::size_t>(stc::kHexFaces[static_cast<std::size_t>(lf)][0])]))
      if (quad_sorted(front.face(g).nodes) == key) return g;
    return kNoFace;
  };
  std::vector<stc::Hex> hexes;
  hexes.reserve(pairs.size());
  for (const auto& [f, g] : pairs) {
    const stc::Quad fq = front.face(f).nodes;
    const auto img = [&](NodeId n) { return image.at(n.index()); };
    hexes.push_back({fq[0], fq[3], fq[2], fq[1], img(fq[0]), img(fq[3]), img(fq[2]), img(fq[1])});
    std::vector<FaceIndex> glued;
    for (int lf = 0; lf < 6; ++lf) {
      const FaceIndex h = front_face_of(hexes.back(), lf);
      if (h != kNoFace) glued.push_back(h);
    }
    if (auto conflict = state.contact_conflict(hexes.back(), glued))
      return RuleResult::refused(*conflict);
  }
  if (auto conflict = batch_contact_conflict(hexes)) return RuleResult::refused(*conflict);
  // ---- move: each hex uses its two disc faces and whatever of its side faces is on the
  // front (strip faces on the rim, faces of the hexes just made inside); make_hex propagates.
  for (const stc::Hex& hex : hexes) {
    std::vector<FaceIndex> used;
    for (int lf = 0; lf < 6; ++lf) {
      const FaceIndex h = front_face_of(hex, lf);
      if (h != kNoFace) used.push_back(h);
    }
    make_hex(state, ctx, hex, used, "parallel-merge", hex[0]);
  }
  return RuleResult::done();
}

bool may_merge_in_parallel(const TraceCandidate& a, const TraceCandidate& b) {
  return !a.self_intersecting && a.length >= 3 && a.side_sharp == a.length &&
         b.side_sharp == b.length;
}

bool apply_parallel_merging(WeaveState& state, WeaveContext& ctx, const FrontLoops& loops,
                            const std::vector<TraceCandidate>& candidates,
                            const FrontComponents& components) {
  for (std::size_t i = 0; i + 1 < candidates.size(); i += 2) {
    const TraceCandidate& a = candidates[i];
    const TraceCandidate& b = candidates[i + 1];
    if (!may_merge_in_parallel(a, b) || a.faces_collapsed != b.faces_collapsed) continue;
    const Strip& strip = loops.strips[static_cast<std::size_t>(a.loop)];
    const std::size_t before = ctx.rules_applied;
    if (ctx.observer != nullptr) {
      const std::array<TraceCandidate, 2> pair{a, b};
      const std::array<std::string, 1> filters{"parallel_merging:1"};
      ctx.observer->on_selection(
          ctx.rules_applied, ctx.shrink_index + 1, pair, 0,
          "parallel merging: loop " + std::to_string(a.loop) +
              " has sharp edges on both sides between two discs of the front",
          filters, "parallel_merging");
    }
    ++ctx.shrink_index;
    const RuleResult r = parallel_merging(state, ctx, strip, components);
    if (r) {
      ++state.stats.parallel_merges;
      seam_fixpoint(state, ctx);
      return true;
    }
    if (ctx.rules_applied != before)
      throw InternalError("weave: parallel merging failed after changing the front: " + r.why);
    if (ctx.observer != nullptr) {
      ctx.observer->on_shrink_failed(ctx.rules_applied, ctx.shrink_index,
                                     "parallel merging refused: " + r.why);
    }
  }
  return false;
}

}  // namespace stcweave::weave
