/// The weave kernel's values: the state a rule changes, the context it reads, and the one move
/// every hex-making rule shares (`make_hex`).

#include "stcweave/weave/kernel.hpp"

#include <algorithm>
#include <array>
#include <vector>

#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

std::array<NodeId, 4> quad_sorted(stc::Quad q) {
  std::sort(q.begin(), q.end());
  return q;
}

// ---------------------------------------------------------------------------------------
// state

WeaveState::WeaveState(const stc::QuadSurface& surface) : front(surface) {
  woven.hexes_at.resize(front.num_nodes());
}

void WeaveState::add_hex_at(NodeId n, HexId h) {
  woven.hexes_at[n.index()].push_back(h);
  if (open_checkpoints_ > 0) {
    journal_.push_back(
        {WovenChange::Kind::HexAtPush, static_cast<std::uint32_t>(n.index()), 0, 0, {}});
  }
}

NodeId WeaveState::new_node() {
  const NodeId n = front.new_node();
  woven.hexes_at.emplace_back();
  return n;
}

void WeaveState::merge_nodes(NodeId keep, NodeId gone) {
  front.merge_nodes(keep, gone);
  auto& hk = woven.hexes_at[keep.index()];
  auto& hg = woven.hexes_at[gone.index()];
  if (open_checkpoints_ > 0) {
    journal_.push_back({WovenChange::Kind::HexAtMerge,
                        static_cast<std::uint32_t>(keep.index()),
                        static_cast<std::uint32_t>(gone.index()),
                        static_cast<std::uint32_t>(hk.size()),
                        {}});
  }
  hk.insert(hk.end(), hg.begin(), hg.end());
  hg.clear();
  hg.shrink_to_fit();
}

void WeaveState::push_nodes_of(FaceIndex f) {
  for (NodeId n : front.face(f).nodes) seam_work.push_back(n);
}

void WeaveState::link(const FaceOwner& a, const FaceOwner& b) {
  const auto set = [this](const FaceOwner& self, const FaceOwner& other) {
    if (!self.is_hex()) return;
    DualLink& l =
        woven.dual[static_cast<std::size_t>(self.id)][static_cast<std::size_t>(self.local_face)];
    if (open_checkpoints_ > 0) {
      journal_.push_back({WovenChange::Kind::Dual, static_cast<std::uint32_t>(self.id),
                          static_cast<std::uint32_t>(self.local_face), 0, l});
    }
    l.is_boundary = other.is_input();
    l.id = other.id;
    l.local_face = other.local_face;
  };
  set(a, b);
  set(b, a);
}

bool WeaveState::share_hex(NodeId x, NodeId y) const {
  const auto& hx = woven.hexes_at[x.index()];
  const auto& hy = woven.hexes_at[y.index()];
  for (HexId h : hx)
    if (std::find(hy.begin(), hy.end(), h) != hy.end()) return true;
  return false;
}

namespace {

/// A hex's nodes as canonical front nodes, `gone` read as `keep`, sorted.
using NodeImage = std::array<NodeId, 8>;

NodeImage node_image(const Front& front, const stc::Hex& hex, NodeId gone, NodeId keep) {
  NodeImage out{};
  for (std::size_t i = 0; i < 8; ++i) {
    const NodeId x = front.find(hex[i]);
    out[i] = x == gone ? keep : x;
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// The nodes two sorted images share (a repeated node counted as often as both repeat it).
std::size_t count_common(const NodeImage& na, const NodeImage& nb) {
  std::size_t count = 0;
  std::size_t i = 0, j = 0;
  while (i < 8 && j < 8) {
    if (na[i] == nb[j]) {
      ++count;
      ++i;
      ++j;
    } else if (na[i] < nb[j]) {
      ++i;
    } else {
      ++j;
    }
  }
  return count;
}

}  // namespace

std::size_t WeaveState::common_nodes(HexId a, HexId b, NodeId gone, NodeId keep) const {
  return count_common(node_image(front, woven.hexes[a.index()], gone, keep),
                      node_image(front, woven.hexes[b.index()], gone, keep));
}

std::optional<std::string> WeaveState::merge_conflict(NodeId x, NodeId y, NodeId keep,
                                                      NodeId gone) const {
  const auto image = [&](NodeId n) {
    n = front.find(n);
    return n == gone ? keep : n;
  };
  // the local face of hex h whose four nodes all belong to hex other (after the merge)
  const auto face_within = [&](HexId h, HexId other) -> int {
    for (int lf = 0; lf < 6; ++lf) {
      std::size_t hits = 0;
      for (NodeId n : stc::hex_face(woven.hexes[h.index()], lf)) {
        const NodeId m = image(n);
        for (NodeId o : woven.hexes[other.index()]) {
          if (image(o) == m) {
            ++hits;
            break;
          }
        }
      }
      if (hits == 4) return lf;
    }
    return -1;
  };
  // Every pair (a hex at x, a hex at y) is compared; each hex's image is made once (at a
  // node of high valence the pairs are many: measured on fandisk_quads, comparing each pair
  // from scratch was the weave's largest cost).
  // (The images of the hexes at y go in a buffer kept between calls, and the message is only
  // written for a conflict: this runs before every seam, most of a weave's rules.)
  const std::vector<HexId>& at_x = woven.hexes_at[x.index()];
  const std::vector<HexId>& at_y = woven.hexes_at[y.index()];
  std::vector<NodeImage>& image_y = merge_images_;
  image_y.clear();
  for (HexId h : at_y) image_y.push_back(node_image(front, woven.hexes[h.index()], gone, keep));
  const auto conflict = [&](const char* verb, HexId h1, HexId h2, const char* rest) {
    return "merging " + x.str() + " and " + y.str() + " would " + verb + h1.str() + " and " +
           h2.str() + rest;
  };
  for (const HexId h1 : at_x) {
    const NodeImage image_x = node_image(front, woven.hexes[h1.index()], gone, keep);
    for (std::size_t j = 0; j < at_y.size(); ++j) {
      const HexId h2 = at_y[j];
      const std::size_t common = count_common(image_x, image_y[j]);
      if (common < 4) continue;
      if (common > 4) return conflict("make ", h1, h2, " share more than one face");
      const int f1 = face_within(h1, h2), f2 = face_within(h2, h1);
      if (f1 < 0 || f2 < 0)
        return conflict("make ", h1, h2, " share four nodes that are not a common face");
      if (woven.dual[h1.index()][static_cast<std::size_t>(f1)].id >= 0 ||
          woven.dual[h2.index()][static_cast<std::size_t>(f2)].id >= 0)
        return conflict("put a face of ", h1, h2, " in more than two hexes");
    }
  }
  return std::nullopt;
}

std::optional<std::string> WeaveState::contact_conflict(std::span<const NodeId> nodes,
                                                        std::span<const FaceIndex> used) const {
  // Each woven hex appears once in the list of each of its nodes, so after sorting, the
  // length of a hex's run is the number of nodes it shares with the new hex.
  std::vector<HexId>& near = contact_hexes_;
  near.clear();
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (std::find(nodes.begin(), nodes.begin() + static_cast<std::ptrdiff_t>(i), nodes[i]) !=
        nodes.begin() + static_cast<std::ptrdiff_t>(i))
      continue;  // a node given twice counts once
    const auto& at = woven.hexes_at[nodes[i].index()];
    near.insert(near.end(), at.begin(), at.end());
  }
  if (near.size() < 4) return std::nullopt;
  std::sort(near.begin(), near.end());
  for (std::size_t i = 0; i < near.size();) {
    std::size_t j = i + 1;
    while (j < near.size() && near[j] == near[i]) ++j;
    const std::size_t shared = j - i;
    const HexId g = near[i];
    i = j;
    if (shared < 4) continue;
    if (shared > 4) {
      return "the new hex would share " + std::to_string(shared) + " nodes with " + g.str() +
             " (more than a face)";
    }
    const bool glued = std::any_of(used.begin(), used.end(), [&](FaceIndex f) {
      const FaceOwner& o = front.face(f).owner;
      return o.is_hex() && o.id == g.value();
    });
    if (!glued) {
      return "the new hex would share four nodes with " + g.str() +
             " that are not the face it is glued to";
    }
  }
  return std::nullopt;
}

void WeaveState::roll_back_to(WeaveState&& saved) {
  const WeaveStats now = stats;
  *this = std::move(saved);
  stats.selections = now.selections;
  stats.failed_shrinks = now.failed_shrinks;
  stats.rolled_back_shrinks = now.rolled_back_shrinks;
}

WeaveState::Checkpoint WeaveState::checkpoint() {
  ++open_checkpoints_;
  return {front.checkpoint(),
          woven.hexes.size(),
          woven.hexes_at.size(),
          journal_.size(),
          seam_work,
          blocked_seams,
          stats};
}

void WeaveState::roll_back(Checkpoint&& c) {
  while (journal_.size() > c.journal) {
    const WovenChange e = journal_.back();
    journal_.pop_back();
    switch (e.kind) {
      case WovenChange::Kind::Dual:
        woven.dual[e.a][e.b] = e.link;
        break;
      case WovenChange::Kind::HexAtPush:
        woven.hexes_at[e.a].pop_back();
        break;
      case WovenChange::Kind::HexAtMerge: {
        auto& kept = woven.hexes_at[e.a];
        woven.hexes_at[e.b].assign(kept.begin() + e.c, kept.end());
        kept.resize(e.c);
        break;
      }
    }
  }
  woven.hexes.resize(c.hexes);
  woven.dual.resize(c.hexes);
  woven.hex_shrink.resize(c.hexes);
  woven.hex_rule.resize(c.hexes);
  woven.hex_node.resize(c.hexes);
  woven.hexes_at.resize(c.nodes);
  front.roll_back(std::move(c.front));
  seam_work = std::move(c.seam_work);
  blocked_seams = std::move(c.blocked_seams);
  const WeaveStats now = stats;
  stats = c.stats;
  stats.selections = now.selections;
  stats.failed_shrinks = now.failed_shrinks;
  stats.rolled_back_shrinks = now.rolled_back_shrinks;
  --open_checkpoints_;
}

void WeaveState::release(Checkpoint&& c) {
  front.release(std::move(c.front));
  --open_checkpoints_;
  if (open_checkpoints_ == 0) journal_.clear();
}

// ---------------------------------------------------------------------------------------
// scratch marks

std::uint32_t Marks::fresh(std::size_t size) {
  if (marks_.size() < size) marks_.resize(size, 0);
  if (++stamp_ == 0) {
    std::fill(marks_.begin(), marks_.end(), 0);
    stamp_ = 1;
  }
  return stamp_;
}

FaceSet mark_strip_faces(Marks& marks, const Front& front, const Strip& strip) {
  const std::uint32_t stamp = marks.fresh(front.face_capacity());
  for (const stc::StripStep& p : strip) marks.set(static_cast<std::size_t>(face_of(p)), stamp);
  return {&marks, stamp};
}

// ---------------------------------------------------------------------------------------
// context

WeaveContext::WeaveContext(const WeaveOptions& opts, WeaveObserver* watcher, std::size_t limit)
    : options(opts), observer(watcher), max_rules(limit) {}

void WeaveContext::after_rule(const WeaveState& state, const char* rule, NodeId node,
                              std::span<const FaceOwner> owners, HexId hex) {
  ++rules_applied;
  if (observer != nullptr) observer->on_rule(rules_applied, shrink_index, rule, node, owners, hex);
  if (options.check) {
    if (auto err = state.front.check_invariants()) {
      throw InternalError("weave: front invariant broken after " + std::string(rule) + " at " +
                          node.str() + " (rule " + std::to_string(rules_applied) + "): " + *err);
    }
  }
  if (options.progress && options.progress_every > 0 &&
      rules_applied % options.progress_every == 0) {
    options.progress(
        WeaveProgress{state.front.num_faces(), state.woven.hexes.size(), state.stats.shrinks});
  }
  if (rules_applied > max_rules) {
    throw WeaveError("weave: gave up after " + std::to_string(max_rules) +
                     " rule applications with " + std::to_string(state.front.num_faces()) +
                     " front faces left (raise the limit with max_rules if the input is large)");
  }
}

// ---------------------------------------------------------------------------------------
// the move every hex-making rule shares

HexId make_hex(WeaveState& state, WeaveContext& ctx, const stc::Hex& hex,
               std::span<const FaceIndex> used, const char* rule, NodeId at_node) {
  Front& front = state.front;
  WovenComplex& woven = state.woven;
  const HexId id(woven.hexes.size());
  woven.hexes.push_back(hex);
  woven.dual.emplace_back();
  woven.hex_shrink.push_back(ctx.shrink_index);
  woven.hex_rule.emplace_back(rule);
  woven.hex_node.push_back(at_node);
  std::array<FaceIndex, 6> face_used{};
  face_used.fill(kNoFace);
  std::vector<FaceOwner> whiskers;
  whiskers.reserve(used.size());
  for (FaceIndex f : used) {
    const auto key = quad_sorted(front.face(f).nodes);
    bool matched = false;
    for (int lf = 0; lf < 6; ++lf) {
      if (quad_sorted(stc::hex_face(hex, lf)) == key) {
        face_used[static_cast<std::size_t>(lf)] = f;
        matched = true;
        break;
      }
    }
    if (!matched) throw InternalError("weave: a used front face is not a face of the new hex");
    whiskers.push_back(front.face(f).owner);
  }
  for (int lf = 0; lf < 6; ++lf) {
    const FaceIndex f = face_used[static_cast<std::size_t>(lf)];
    if (f == kNoFace) continue;
    state.link(FaceOwner{FaceOwner::Kind::Hex, id.value(), static_cast<std::int8_t>(lf)},
               front.face(f).owner);
  }
  const Propagated carried = propagate(front, hex, face_used);
  // Remove the used faces, then add the new ones reversed (outward from the region left).
  for (FaceIndex f : used) {
    state.push_nodes_of(f);
    front.remove_face(f);
  }
  for (int lf = 0; lf < 6; ++lf) {
    if (face_used[static_cast<std::size_t>(lf)] != kNoFace) continue;
    const FaceIndex f =
        front.add_face(stc::reversed(stc::hex_face(hex, lf)),
                       FaceOwner{FaceOwner::Kind::Hex, id.value(), static_cast<std::int8_t>(lf)},
                       carried.depth[static_cast<std::size_t>(lf)],
                       carried.side_angle[static_cast<std::size_t>(lf)]);
    state.push_nodes_of(f);
  }
  for (NodeId n : hex) state.add_hex_at(n, id);
  ctx.after_rule(state, rule, at_node, whiskers, id);
  return id;
}

}  // namespace stcweave::weave
