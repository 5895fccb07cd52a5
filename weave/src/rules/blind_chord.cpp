/// Blind chord formation, seed sect. 2.2 (Fig. 2, Fig. 3): a new hex on only two front faces
/// that share an edge. It lowers the valence of a side node of the shrinking loop by one, so
/// that a k-sided cell collapses by k - 3 blind chords and a cross. The chord it introduces
/// runs through the two hex faces not opposite a front face.
///
/// Which two faces: one strip face f holding v on the shrinking side, and the non-strip face
/// g across f's shrinking-side edge at v. (Using the two strip faces at v instead is wrong:
/// the loop then never shrinks, or a later cross rebuilds the same hex; DESIGN.md.) The new
/// hex may share at most one of the two faces with a woven hex, and four nodes only as that
/// face (`WeaveState::contact_conflict`).

#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

RuleResult blind_chord(WeaveState& state, WeaveContext& ctx, NodeId v, const Strip& strip,
                       const FaceSet& strip_faces) {
  const Front& front = state.front;
  std::vector<std::uint32_t> steps;
  for (std::size_t i = 0; i < strip.size(); ++i) {
    const stc::Quad& n = front.face(face_of(strip[i])).nodes;
    if (quad_at(n, strip[i].entry) == v || quad_at(n, strip[i].entry + 3) == v)
      steps.push_back(static_cast<std::uint32_t>(i));
  }
  return blind_chord(state, ctx, v, strip, strip_faces, steps);
}

RuleResult blind_chord(WeaveState& state, WeaveContext& ctx, NodeId v, const Strip& strip,
                       const FaceSet& strip_faces, std::span<const std::uint32_t> steps) {
  const Front& front = state.front;
  // The refusal of the last pair tried (its message is built once, at the end).
  enum class Refusal { NoPair, SharedEdges, SameHex, Contact } last = Refusal::NoPair;
  HexId same_hex;
  std::string contact;
  for (const std::uint32_t step : steps) {
    const stc::StripStep& p = strip[step];
    const FaceIndex f = face_of(p);
    const stc::Quad& n = front.face(f).nodes;
    if (quad_at(n, p.entry) != v && quad_at(n, p.entry + 3) != v)
      throw InternalError("weave: blind chord at " + v.str() + ": strip step " +
                          std::to_string(step) + " does not hold it on the shrinking side");
    const int side = (p.entry + 3) % 4;  // edge (n[i+3], n[i]) on the shrinking side
    const FaceSide g = front.across(f, side);
    if (g.face == kNoFace) throw InternalError("weave: open front edge at " + v.str());
    if (strip_faces.contains(g.face)) continue;
    const NodeId s = quad_at(n, p.entry + 3), t = quad_at(n, p.entry);
    const NodeId p2 = quad_at(n, p.entry + 1), p3 = quad_at(n, p.entry + 2);
    const stc::Quad& qn = front.face(g.face).nodes;
    const NodeId q2 = quad_at(qn, g.index + 2), q3 = quad_at(qn, g.index + 3);
    // ---- precondition: one shared edge, two faces of different hexes ----
    std::array<NodeId, 6> six{s, t, p2, p3, q2, q3};
    std::sort(six.begin(), six.end());
    if (std::adjacent_find(six.begin(), six.end()) != six.end()) {
      last = Refusal::SharedEdges;
      continue;
    }
    const FaceOwner of = front.face(f).owner, og = front.face(g.face).owner;
    if (of.is_hex() && og.is_hex() && of.id == og.id) {
      last = Refusal::SameHex;
      same_hex = HexId(of.id);
      continue;
    }
    const std::array<FaceIndex, 2> used{f, g.face};
    if (auto conflict = state.contact_conflict(six, used)) {
      last = Refusal::Contact;
      contact = std::move(*conflict);
      continue;
    }
    // ---- move (make_hex propagates depth and angles) ----
    const NodeId n5 = state.new_node();
    const NodeId n6 = state.new_node();
    const HexId hex = make_hex(state, ctx, {s, p3, p2, t, q2, n5, n6, q3}, used, "blind-chord", v);
    ++state.stats.blind_chords;
    return RuleResult::done(hex);
  }
  switch (last) {
    case Refusal::SharedEdges:
      return RuleResult::refused("faces share more than one edge's nodes");
    case Refusal::SameHex:
      return RuleResult::refused("both faces belong to " + same_hex.str());
    case Refusal::Contact:
      return RuleResult::refused(contact);
    case Refusal::NoPair:
      break;
  }
  return RuleResult::refused("no strip face at it has a non-strip face across its side edge");
}

}  // namespace stcweave::weave
