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
///
/// A node whose cross or blind chord refused is skipped by later walks of the same shrink
/// until a face at it changes (`StripIndex::known_refused`): on an O-grid cylinder most side
/// nodes are flat corners the cross refuses, and re-asking each of them after every rule made
/// the walk cost ~90 refusals per hex. With `WeaveOptions::check` each skipped rule is run
/// anyway and must refuse.

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <set>
#include <span>
#include <utility>

#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

namespace {

/// The strip of the loop being shrunk, kept from one rule to the next: a cycle of steps
/// (face, entry) with its side nodes filed by front valence, so that the fewest-valence side
/// node (ties: loop order from the strip's start) is found without scanning the strip, and
/// after a rule only the steps on faces it changed (Front::ChangeLog) are re-traced.
///
/// Why the result is `retrace` (front_loops.cpp) of the strip before the rule, step for step:
///  - the start: `retrace` tries the previous strip's transversal edges in order, so the walk
///    from the previous start stops at the first edge still on the front; an unchanged face
///    still holds its own edge, so the walk never passes one;
///  - the cycle: two unchanged faces that followed each other still do (the face across an
///    edge is the one holding its reverse, and both faces still hold their edge), so only the
///    steps on changed faces are traced again, from the unchanged step before them until an
///    unchanged step. When the changed faces cut the strip in more than one place, or the new
///    start is not on the repaired cycle (the loop split or was rebuilt), the whole strip is
///    traced again from the start, as `retrace` does;
///  - the order: labels increase along the cycle (one wrap-around), so loop order from the
///    start is the order of (label - start label); the side nodes of a step come entry node
///    first, entry + 3 node second, as the scan of the whole strip meets them.
/// With `WeaveOptions::check` every step is compared with `retrace` and a scan of the strip.
class StripIndex {
 public:
  explicit StripIndex(const Front& front) : front_(front) {}

  /// Forgets everything and indexes `strip` (its first step is the start).
  void build(const Strip& strip) {
    clear();
    if (strip.empty()) return;
    const std::uint64_t spacing = std::numeric_limits<std::uint64_t>::max() / (strip.size() + 1);
    std::int32_t first = -1, last = -1;
    for (std::size_t i = 0; i < strip.size(); ++i) {
      const std::int32_t x = make(strip[i], spacing * (i + 1));
      if (first < 0) first = x;
      if (last >= 0) link(last, x);
      last = x;
    }
    link(last, first);
    start_ = first;
  }

  [[nodiscard]] bool empty() const { return start_ < 0; }

  /// Brings the strip up to date with the changes in `log` (then cleared): true when the loop
  /// is still on the front, false when it shrank to nothing (`retrace` found no edge).
  bool update(Front::ChangeLog& log) {
    if (start_ < 0) return false;
    const std::uint32_t stamp = ++stamp_;
    removed_.clear();
    for (FaceIndex f : log.faces) {
      for (int e = 0; e < 4; ++e) {
        const std::int32_t x = element_at(f, e);
        if (x >= 0 && elements_[static_cast<std::size_t>(x)].mark != stamp) {
          elements_[static_cast<std::size_t>(x)].mark = stamp;
          removed_.push_back(x);
        }
      }
    }
    const auto is_removed = [&](std::int32_t x) { return element(x).mark == stamp; };
    if (!removed_.empty()) {
      // The new start: the first transversal edge of the strip still on the front.
      std::optional<stc::StripStep> start;
      std::int32_t x = start_;
      do {
        const NodeId d = front_.find(element(x).edge.side_node);
        const NodeId e = front_.find(element(x).edge.other);
        if (d != e) {
          const FaceSide fs = front_.find_edge(d, e);
          if (fs.face != kNoFace) {
            start = stc::StripStep{QuadId(fs.face), fs.index};
            break;
          }
        }
        x = element(x).next;
      } while (x != start_);
      if (!start) {
        clear();
        log.clear();
        return false;
      }
      if (!repair(*start, is_removed)) build(trace_strip(front_, face_of(*start), start->entry));
    }
    // Forget their refusals and re-file the side nodes whose valence changed (each node once:
    // the log names a node once per changed face holding it).
    const std::uint32_t visit = logged_.fresh(front_.num_nodes());
    for (NodeId v : log.nodes) {
      forget_refusal(v);
      if (v.index() >= front_.num_nodes() || logged_.is(v.index(), visit)) continue;
      logged_.set(v.index(), visit);
      const std::size_t k = front_.valence(v);
      for (FaceIndex f : front_.faces_at(v)) {
        for (int e = 0; e < 4; ++e) {
          const std::int32_t y = element_at(f, e);
          if (y < 0) continue;
          Element& el = elements_[static_cast<std::size_t>(y)];
          for (std::uint8_t which = 0; which < 2; ++which) {
            if (el.side[which] != v || el.filed[which] == k) continue;
            unfile(y, which);
            file(y, which);
          }
        }
      }
    }
    log.clear();
    return true;
  }

  /// Whether the cross or blind chord at `v` refused (with the geometric preconditions in
  /// force) and nothing it reads changed since: a face at `v` came or went, two nodes of one
  /// merged, or a face at `v` joined or left the strip. Those rules read only the faces at `v`
  /// (their nodes, owners and carried angles, the faces across their sides, which hold `v`
  /// too) and, for the blind chord, which of them are strip steps holding `v` on the
  /// shrinking side; so the same rule at `v` refuses again and the walk may skip it.
  [[nodiscard]] bool known_refused(NodeId v) const {
    return v.index() < refused_.size() && refused_[v.index()] != 0;
  }
  void note_refused(NodeId v) {
    if (refused_.size() <= v.index()) refused_.resize(front_.num_nodes() + 64, 0);
    refused_[v.index()] = 1;
  }

  /// The side node with the fewest front faces, the first in loop order among equals.
  [[nodiscard]] NodeId first_node() const {
    const std::uint64_t from = element(start_).label;
    for (const auto& bucket : buckets_) {
      if (bucket.empty()) continue;
      auto it = bucket.lower_bound(Key{from, 0, -1});
      if (it == bucket.end()) it = bucket.begin();
      return element(it->element).side[it->which];
    }
    return NodeId();
  }

  /// Starts a walk over the side nodes (`next_node`): fewest front faces first, ties in loop
  /// order from the start, each node once. \pre the front does not change during the walk.
  void begin_walk() {
    walk_valence_ = 0;
    walk_left_ = 0;
    walk_started_ = false;
    walk_seen_ = seen_.fresh(front_.num_nodes());
  }
  /// The next side node of the walk, or an invalid id when every one was given.
  NodeId next_node() {
    for (;;) {
      if (walk_left_ == 0) {
        if (walk_started_) ++walk_valence_;
        walk_started_ = true;
        while (walk_valence_ < buckets_.size() && buckets_[walk_valence_].empty()) ++walk_valence_;
        if (walk_valence_ >= buckets_.size()) return NodeId();
        const std::set<Key>& bucket = buckets_[walk_valence_];
        walk_at_ = bucket.lower_bound(Key{element(start_).label, 0, -1});
        if (walk_at_ == bucket.end()) walk_at_ = bucket.begin();
        walk_left_ = bucket.size();
      }
      const Key key = *walk_at_;
      if (++walk_at_ == buckets_[walk_valence_].end()) walk_at_ = buckets_[walk_valence_].begin();
      --walk_left_;
      const NodeId v = element(key.element).side[key.which];
      if (!seen_.is(v.index(), walk_seen_)) {
        seen_.set(v.index(), walk_seen_);
        return v;
      }
    }
  }

  /// The steps holding `v` on the shrinking side, in loop order from the start.
  [[nodiscard]] Strip steps_of(NodeId v) const {
    const std::uint64_t from = element(start_).label;
    std::vector<std::pair<std::uint64_t, stc::StripStep>> found;
    for (FaceIndex f : front_.faces_at(v)) {
      for (int e = 0; e < 4; ++e) {
        const std::int32_t y = element_at(f, e);
        if (y < 0) continue;
        const Element& el = element(y);
        if (el.side[0] == v || el.side[1] == v) found.emplace_back(el.label - from, el.step);
      }
    }
    std::sort(found.begin(), found.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    Strip out;
    out.reserve(found.size());
    for (const auto& s : found) out.push_back(s.second);
    return out;
  }

  /// The faces of the strip.
  [[nodiscard]] FaceSet faces() {
    if (marked_capacity_ < front_.face_capacity()) {  // room for more slots: mark again
      marked_capacity_ = 2 * front_.face_capacity() + 64;
      face_stamp_ = face_marks_.fresh(marked_capacity_);
      for (std::size_t f = 0; f < on_strip_.size(); ++f)
        if (on_strip_[f] > 0) face_marks_.set(f, face_stamp_);
    }
    return {&face_marks_, face_stamp_};
  }

  /// The whole strip, from the start.
  [[nodiscard]] Strip strip() const {
    Strip out;
    if (start_ < 0) return out;
    std::int32_t x = start_;
    do {
      out.push_back(element(x).step);
      x = element(x).next;
    } while (x != start_);
    return out;
  }

 private:
  struct Element {
    stc::StripStep step;
    std::uint64_t label = 0;
    std::int32_t prev = -1, next = -1;
    std::array<NodeId, 2> side{};        ///< entry node, entry + 3 node
    std::array<std::size_t, 2> filed{};  ///< the valence each is filed under
    Transversal edge;                    ///< (entry node, entry + 1 node)
    std::uint32_t mark = 0;
  };
  struct Key {
    std::uint64_t label;
    std::uint8_t which;
    std::int32_t element;
    bool operator<(const Key& o) const {
      return label != o.label ? label < o.label : which < o.which;
    }
  };

  [[nodiscard]] const Element& element(std::int32_t x) const {
    return elements_[static_cast<std::size_t>(x)];
  }
  [[nodiscard]] std::int32_t element_at(FaceIndex f, int entry) const {
    const std::size_t i = 4 * static_cast<std::size_t>(f) + static_cast<std::size_t>(entry);
    return i < at_.size() ? at_[i] : -1;
  }
  void link(std::int32_t a, std::int32_t b) {
    elements_[static_cast<std::size_t>(a)].next = b;
    elements_[static_cast<std::size_t>(b)].prev = a;
  }
  void file(std::int32_t x, std::uint8_t which) {
    Element& el = elements_[static_cast<std::size_t>(x)];
    const std::size_t k = front_.valence(el.side[which]);
    if (buckets_.size() <= k) buckets_.resize(k + 1);
    buckets_[k].insert(Key{el.label, which, x});
    el.filed[which] = k;
  }
  void unfile(std::int32_t x, std::uint8_t which) {
    const Element& el = element(x);
    buckets_[el.filed[which]].erase(Key{el.label, which, x});
  }
  /// A new element for step `s` (not linked), filed.
  std::int32_t make(const stc::StripStep& s, std::uint64_t label) {
    std::int32_t x;
    if (!free_.empty()) {
      x = free_.back();
      free_.pop_back();
    } else {
      x = static_cast<std::int32_t>(elements_.size());
      elements_.emplace_back();
    }
    Element& el = elements_[static_cast<std::size_t>(x)];
    const FaceIndex f = face_of(s);
    const stc::Quad& n = front_.face(f).nodes;
    el.step = s;
    el.label = label;
    el.prev = el.next = -1;
    el.side = {quad_at(n, s.entry), quad_at(n, s.entry + 3)};
    el.edge = {quad_at(n, s.entry), quad_at(n, s.entry + 1)};
    el.mark = 0;
    for (NodeId m : n) forget_refusal(m);
    const std::size_t i = 4 * static_cast<std::size_t>(f) + static_cast<std::size_t>(s.entry);
    if (at_.size() <= i) at_.resize(4 * front_.face_capacity() + 64, -1);
    at_[i] = x;
    const auto fi = static_cast<std::size_t>(f);
    if (on_strip_.size() <= fi) on_strip_.resize(front_.face_capacity() + 16, 0);
    if (on_strip_[fi]++ == 0 && fi < marked_capacity_) face_marks_.set(fi, face_stamp_);
    file(x, 0);
    file(x, 1);
    return x;
  }
  void drop(std::int32_t x) {
    unfile(x, 0);
    unfile(x, 1);
    const Element& el = element(x);
    const FaceIndex f = face_of(el.step);
    for (NodeId m : front_.face(f).nodes) forget_refusal(m);
    at_[4 * static_cast<std::size_t>(f) + static_cast<std::size_t>(el.step.entry)] = -1;
    const auto fi = static_cast<std::size_t>(f);
    if (--on_strip_[fi] == 0 && fi < marked_capacity_) face_marks_.set(fi, 0);
    free_.push_back(x);
  }
  void forget_refusal(NodeId v) {
    if (v.index() < refused_.size()) refused_[v.index()] = 0;
  }
  void clear() {
    if (start_ >= 0) {
      std::int32_t x = start_;
      do {
        const std::int32_t next = element(x).next;
        drop(x);
        x = next;
      } while (x != start_);
    }
    start_ = -1;
  }

  /// Re-traces the steps on changed faces when they make one run of the cycle and the new
  /// start is on the repaired cycle; false (nothing changed) otherwise.
  template <class IsRemoved>
  bool repair(const stc::StripStep& new_start, const IsRemoved& is_removed) {
    // The one unchanged step followed by a changed one.
    std::int32_t left = -1;
    for (const std::int32_t x : removed_) {
      const std::int32_t p = element(x).prev;
      if (is_removed(p)) continue;
      if (left >= 0) return false;
      left = p;
    }
    if (left < 0) return false;  // every step changed
    std::int32_t right = element(left).next;
    while (is_removed(right)) right = element(right).next;
    // Trace from `left` until an unchanged step: it must be `right`.
    fresh_.clear();
    const std::size_t limit = 2 * front_.num_faces() + 4;
    stc::StripStep cur = element(left).step;
    for (;;) {
      const FaceSide next = front_.across(face_of(cur), cur.exit());
      if (next.face == kNoFace) throw InternalError("weave: open front edge while tracing a loop");
      cur = stc::StripStep{QuadId(next.face), next.index};
      const std::int32_t y = element_at(next.face, next.index);
      if (y >= 0 && !is_removed(y)) {
        if (y != right) return false;
        break;
      }
      fresh_.push_back(cur);
      if (fresh_.size() > limit) return false;
    }
    // The new start must be on this cycle.
    const std::int32_t s = element_at(face_of(new_start), new_start.entry);
    const bool start_kept = s >= 0 && !is_removed(s);
    if (!start_kept && std::find(fresh_.begin(), fresh_.end(), new_start) == fresh_.end())
      return false;
    const std::uint64_t from = element(left).label;
    const std::uint64_t gap =
        right == left ? std::numeric_limits<std::uint64_t>::max() : element(right).label - from;
    const std::uint64_t spacing = gap / (fresh_.size() + 1);
    if (spacing == 0) return false;  // no room for the labels: index the strip again
    for (const std::int32_t x : removed_) drop(x);
    std::int32_t last = left;
    std::int32_t start_element = start_kept ? s : -1;
    for (std::size_t i = 0; i < fresh_.size(); ++i) {
      const std::int32_t x = make(fresh_[i], from + spacing * (i + 1));
      link(last, x);
      last = x;
      if (fresh_[i] == new_start) start_element = x;
    }
    link(last, right);
    start_ = start_element;
    return true;
  }

  const Front& front_;
  std::vector<Element> elements_;
  std::vector<std::int32_t> free_;
  std::vector<std::int32_t> at_;         ///< per face slot and entry, its element or -1
  std::vector<std::set<Key>> buckets_;   ///< per valence, the side nodes filed under it
  std::vector<std::uint32_t> on_strip_;  ///< per face slot, its steps on the strip
  Marks face_marks_;
  std::uint32_t face_stamp_ = 0;
  std::size_t marked_capacity_ = 0;
  std::int32_t start_ = -1;
  std::uint32_t stamp_ = 0;
  std::vector<std::int32_t> removed_;
  std::vector<std::uint8_t> refused_;  ///< per node, 1: `known_refused`
  Strip fresh_;
  Marks seen_;
  Marks logged_;  ///< `update`'s nodes already re-filed
  std::uint32_t walk_seen_ = 0;
  std::size_t walk_valence_ = 0, walk_left_ = 0;
  bool walk_started_ = false;
  std::set<Key>::const_iterator walk_at_;
};

/// With `WeaveOptions::check`: the index agrees with `expected` (`retrace` of the strip before
/// the rule) and its walk over the side nodes with the order a scan of that strip gives: each
/// node once, by fewest front faces, ties in loop order.
void check_index(const Front& front, StripIndex& index, const Strip& expected) {
  if (expected != index.strip())
    throw InternalError("weave: the shrink's strip index differs from the re-traced strip");
  std::vector<NodeId> order;
  std::set<NodeId> seen;
  for (const stc::StripStep& p : expected) {
    const stc::Quad& n = front.face(face_of(p)).nodes;
    for (NodeId m : {quad_at(n, p.entry), quad_at(n, p.entry + 3)})
      if (seen.insert(m).second) order.push_back(m);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](NodeId a, NodeId b) { return front.valence(a) < front.valence(b); });
  std::vector<NodeId> walk;
  index.begin_walk();
  for (NodeId v = index.next_node(); v.is_valid(); v = index.next_node()) walk.push_back(v);
  if (walk != order)
    throw InternalError("weave: the shrink's side node order differs from a scan of the strip");
}

/// With `WeaveOptions::check`: a rule the walk skipped as a known refusal applied.
[[noreturn]] void remembered_refusal_applied(std::size_t valence, NodeId v) {
  std::string what = "weave: the shrink remembered a refusal of the ";
  what += valence == 3 ? "cross" : "blind chord";
  what += " at n";
  what += std::to_string(v.value());
  what += " from an unchanged neighbourhood, and the rule applied";
  throw InternalError(what);
}

}  // namespace

std::optional<std::string> shrink(WeaveState& state, WeaveContext& ctx, const Strip& initial,
                                  stc::LoopSide side) {
  Front& front = state.front;
  // The strip is indexed once, then brought up to date after every rule from the faces the
  // rule changed (StripIndex above): the cost of a step does not grow with the loop's length.
  StripIndex index(front);
  Front::ChangeLog changes;
  struct Detach {
    Front& front;
    ~Detach() { front.attach_change_log(nullptr); }
  } detach{front};
  const bool check = ctx.options.check;
  std::vector<Transversal> check_edges;  // with `check`: the strip's, for `retrace`
  for (;;) {
    seam_fixpoint(state, ctx);
    Strip expected;  // with `check`: what `retrace` gives
    if (index.empty()) {
      // Re-traced from a side-d node's edge, the strip has the shrinking side as its side A.
      const Strip traced = retrace(front, transversals(front, initial, side));
      if (traced.empty()) return std::nullopt;
      index.build(traced);
      front.attach_change_log(&changes);
      if (check) expected = traced;
    } else {
      if (check) expected = retrace(front, check_edges);
      if (!index.update(changes)) {
        if (check && !expected.empty())
          throw InternalError("weave: the shrink's strip index lost a loop still on the front");
        return std::nullopt;
      }
    }
    if (check) {
      check_index(front, index, expected);
      check_edges = transversals(front, expected, stc::LoopSide::Left);
    }
    // The side nodes by fewest front faces (ties: loop order), each once, until a rule
    // applies: the fewest-sided first, whose rule usually applies. Refusals are remembered
    // while the geometric preconditions are in force (a relaxed step evaluates every node); a
    // walk that skipped one and found nothing is walked again at once, on the same front,
    // without skipping, so that the refusal message names every node as before.
    std::string reasons;
    bool applied = false;
    // The cross at a valence-3 node, the blind chord at a higher one.
    const auto collapse = [&](NodeId v, std::size_t k) {
      // Tried at the strip steps holding v on the shrinking side, in loop order.
      return k == 3 ? cross(state, ctx, v)
                    : blind_chord(state, ctx, v, index.steps_of(v), index.faces());
    };
    for (bool skip_known = !ctx.relax_geometry;; skip_known = false) {
      index.begin_walk();
      reasons.clear();
      bool skipped = false;
      for (NodeId v = index.next_node(); v.is_valid(); v = index.next_node()) {
        std::string why;
        const std::size_t k = front.valence(v);
        if (k >= 3 && skip_known && index.known_refused(v)) {
          skipped = true;
          // With `check`, the rule runs all the same: it must refuse again.
          if (check && collapse(v, k).applied) remembered_refusal_applied(k, v);
          continue;
        }
        if (k == 2) {
          why = "valence 2 but its seam is blocked";
          const RuleResult r = seam(state, ctx, v);
          if (!r) {
            why += " (" + r.why + ")";
          } else {
            applied = true;
          }
        } else {
          const RuleResult r = collapse(v, k);
          applied = r.applied;
          if (!applied) why = (k == 3 ? "cross refused: " : "blind chord refused: ") + r.why;
        }
        if (applied) break;
        // A rule refuses before it moves anything, so the walk goes on over the same front.
        if (!changes.faces.empty() || !changes.nodes.empty())
          throw InternalError("weave: a refused rule changed the front (" + why + ")");
        if (k >= 3 && !ctx.relax_geometry) index.note_refused(v);
        if (reasons.size() < 600) reasons += (reasons.empty() ? "" : "; ") + v.str() + ": " + why;
      }
      if (applied || !skipped) break;
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
