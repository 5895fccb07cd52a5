/// Reliable Whisker Weaving on the front (DESIGN.md "Weaving, operationally").
///
/// The algorithm, and why it ends with a closed complex:
/// - The front starts as the input surface and every rule replaces front faces by faces of a
///   new hex (cross, blind chord formation) or glues two front faces that met (seam); the
///   front stays a closed oriented quad surface (checked after every rule with `check`).
/// - A loop shrink pushes one loop across the region on one side: at each step the side
///   node with the fewest front faces is collapsed (valence 3: cross; valence >= 4: blind
///   chord formation lowers it by one), seams run to a fixpoint after every rule, and the
///   loop is done when none of its transversal edges is left on the front (seed sect. 2.2,
///   Fig. 3-4). Each shrink builds one sheet of hexes.
/// - Loops are chosen by increasing topological weight (nodes strictly on the shrinking side
///   plus nodes on the strip); when a shrink is blocked everywhere, the next (loop, side) is
///   tried, and the weave fails with the reasons only when all are blocked.
/// The weave ends when the front is empty: every hex face is then glued to another hex face
/// or is an input quad.

#include "stcweave/weave/weave.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <unordered_map>

#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/front.hpp"

namespace stcweave::weave {

std::string to_string(RuleSet rules) {
  switch (rules) {
    case RuleSet::Reliable:
      return "reliable";
    case RuleSet::Extended:
      return "extended";
  }
  return "?";
}

RuleSet rule_set_from_name(const std::string& name) {
  if (name == "reliable") return RuleSet::Reliable;
  if (name == "extended") return RuleSet::Extended;
  throw InvalidInput("unknown rule set '" + name + "': valid names are: reliable, extended");
}

EdgeClass classify_edge(double angle, const ExtendedParameters& p) {
  if (angle <= p.sharp) return EdgeClass::SharpConvex;
  if (angle <= p.little_sharp) return EdgeClass::LittleSharpConvex;
  if (angle <= p.flat) return EdgeClass::Flat;
  if (angle <= p.little_sharp_nonconvex) return EdgeClass::LittleSharpNonConvex;
  return EdgeClass::SharpNonConvex;
}

void check_parameters(const ExtendedParameters& p) {
  const bool ordered = p.sharp > 0.0 && p.sharp <= p.little_sharp && p.little_sharp <= p.flat &&
                       p.flat <= p.little_sharp_nonconvex && p.little_sharp_nonconvex < 360.0;
  if (!ordered) {
    throw InvalidInput("edge class thresholds out of order: need 0 < sharp (" +
                       std::to_string(p.sharp) + ") <= little_sharp (" +
                       std::to_string(p.little_sharp) + ") <= flat (" + std::to_string(p.flat) +
                       ") <= little_sharp_nonconvex (" + std::to_string(p.little_sharp_nonconvex) +
                       ") < 360 degrees");
  }
}

std::string to_string(EdgeClass c) {
  switch (c) {
    case EdgeClass::SharpConvex:
      return "sharp convex";
    case EdgeClass::LittleSharpConvex:
      return "a little sharp convex";
    case EdgeClass::Flat:
      return "flat";
    case EdgeClass::LittleSharpNonConvex:
      return "a little sharp non-convex";
    case EdgeClass::SharpNonConvex:
      return "sharp non-convex";
  }
  return "?";
}

namespace {

/// Faces opposite each other in a hex (kHexFaces order).
constexpr std::array<int, 6> kOppositeFace = {1, 0, 4, 5, 2, 3};

/// A loop passage: the loop enters front face `face` through its side `entry`.
struct Passage {
  FaceIndex face = kNoFace;
  int entry = 0;
};

/// A directed transversal edge of a strip: (node on the shrinking side, other node).
struct Transversal {
  NodeId side_node;
  NodeId other;
};

stc::Quad rotated(const stc::Quad& q, int start) {
  return {q[static_cast<std::size_t>(start % 4)], q[static_cast<std::size_t>((start + 1) % 4)],
          q[static_cast<std::size_t>((start + 2) % 4)],
          q[static_cast<std::size_t>((start + 3) % 4)]};
}

std::array<NodeId, 4> sorted_nodes(stc::Quad q) {
  std::sort(q.begin(), q.end());
  return q;
}

NodeId at(const stc::Quad& q, int i) {
  return q[static_cast<std::size_t>(((i % 4) + 4) % 4)];
}

class Weaver {
 public:
  Weaver(const stc::QuadSurface& surface, const WeaveOptions& options,
         const std::vector<std::array<double, 4>>& side_angles)
      : front_(surface), options_(options) {
    if (options.rules == RuleSet::Extended) check_parameters(options.extended);
    if (!side_angles.empty()) {
      if (side_angles.size() != surface.quads.size()) {
        throw InvalidInput("weave: " + std::to_string(side_angles.size()) +
                           " side angle entries for " + std::to_string(surface.quads.size()) +
                           " quads");
      }
      // Input quad q is front face q: the front adds them in order into an empty slot list.
      for (std::size_t q = 0; q < side_angles.size(); ++q) {
        std::array<float, 4> angle{};
        for (std::size_t k = 0; k < 4; ++k) angle[k] = static_cast<float>(side_angles[q][k]);
        front_.set_side_angles(static_cast<FaceIndex>(q), angle);
      }
    }
    hexes_at_.resize(front_.num_nodes());
    node_mark_.assign(front_.num_nodes(), 0);
    const double q = static_cast<double>(surface.quads.size());
    max_rules_ = options.max_rules != 0 ? options.max_rules
                                        : static_cast<std::size_t>(8.0 * q * std::sqrt(q)) + 20000;
    if (auto err = front_.check_invariants())
      throw InvalidInput("the surface is not a closed oriented manifold quad surface: " + *err);
  }

  WeaveResult run();

 private:
  // ---- bookkeeping ----
  /// What a shrink changes: saved before a shrink so that a failed one can be undone.
  struct Snapshot {
    Front front;
    std::vector<stc::Hex> hexes;
    std::vector<std::vector<HexId>> hexes_at;
    std::vector<std::array<DualLink, 6>> dual;
    std::vector<std::int32_t> hex_shrink;
    std::vector<std::string> hex_rule;
    std::vector<NodeId> seam_work;
    std::vector<NodeId> blocked_seams;
    WeaveStats stats;
  };
  [[nodiscard]] Snapshot save() const {
    return {front_,    hexes_,     hexes_at_,      dual_, hex_shrink_,
            hex_rule_, seam_work_, blocked_seams_, stats_};
  }
  void restore(Snapshot&& s) {
    const WeaveStats now = stats_;
    front_ = std::move(s.front);
    hexes_ = std::move(s.hexes);
    hexes_at_ = std::move(s.hexes_at);
    dual_ = std::move(s.dual);
    hex_shrink_ = std::move(s.hex_shrink);
    hex_rule_ = std::move(s.hex_rule);
    seam_work_ = std::move(s.seam_work);
    blocked_seams_ = std::move(s.blocked_seams);
    stats_ = s.stats;
    stats_.selections = now.selections;
    stats_.failed_shrinks = now.failed_shrinks;
    stats_.rolled_back_shrinks = now.rolled_back_shrinks;
    node_mark_.resize(front_.num_nodes());
  }
  /// Merges node `gone` into `keep` on the front and in the node -> hexes lists.
  void merge_nodes(NodeId keep, NodeId gone) {
    front_.merge_nodes(keep, gone);
    auto& hk = hexes_at_[keep.index()];
    auto& hg = hexes_at_[gone.index()];
    hk.insert(hk.end(), hg.begin(), hg.end());
    hg.clear();
    hg.shrink_to_fit();
  }
  NodeId new_node() {
    const NodeId n = front_.new_node();
    hexes_at_.emplace_back();
    node_mark_.push_back(0);
    return n;
  }
  void link(const FaceOwner& a, const FaceOwner& b);
  HexId make_hex(const stc::Hex& hex, std::span<const FaceIndex> used, const char* rule,
                 NodeId at_node);
  void after_rule(const char* rule, NodeId node, std::vector<std::string> faces, HexId hex);
  void push_nodes_of(FaceIndex f) {
    for (NodeId n : front_.face(f).nodes) seam_work_.push_back(n);
  }
  [[nodiscard]] std::size_t common_nodes(HexId a, HexId b, NodeId gone, NodeId keep) const;
  [[nodiscard]] bool share_hex(NodeId x, NodeId y) const;
  /// Why merging x and y would break the complex, if it would: two hexes (one at x, one
  /// at y) sharing more than one face or four nodes that are not a face of both, or sharing
  /// a face one of whose copies is already glued (a face in three or more hexes).
  [[nodiscard]] std::optional<std::string> merge_conflict(NodeId x, NodeId y, NodeId keep,
                                                          NodeId gone) const;

  // ---- geometry carried by the front (rule set `extended`) ----
  [[nodiscard]] bool extended() const { return options_.rules == RuleSet::Extended; }
  /// The dihedral angle of a front edge: the two faces' carried angles combined, where a
  /// convex and a non-convex deviation from flat cancel (seed sect. 6, Fig. 12) and two
  /// deviations the same way keep the larger.
  [[nodiscard]] double edge_angle(FaceIndex f, int side) const;

  // ---- rules ----
  bool try_seam(NodeId v, std::string* why);
  bool try_cross(NodeId v, std::string* why);
  bool try_blind_chord(NodeId v, const std::vector<Passage>& strip, std::string* why);
  bool try_parallel_merging(const std::vector<Passage>& strip, std::string* why);
  /// Non-convexity seams over the whole front (seed sect. 5.2); the number applied.
  std::size_t nonconvexity_seams();
  bool try_nonconvexity_seam(FaceIndex input_face, int side, std::string* why);
  /// Tries parallel merging on every loop that qualifies (sharp convex side edges on both
  /// sides, as many faces on either side); true when one was applied.
  bool merge_parallel(const std::vector<std::vector<Passage>>& loops,
                      const std::vector<TraceCandidate>& candidates);
  void seam_fixpoint();

  // ---- loops ----
  std::vector<Passage> trace_loop(FaceIndex f, int entry) const;
  /// Every loop of the front; also fills `loop_of_` (per face slot and direction).
  std::vector<std::vector<Passage>> all_loops();
  /// Properties of shrinking a loop to side A and to side B for the extended rule set.
  std::array<TraceCandidate, 2> extended_properties(const std::vector<Passage>& strip);
  /// The loop that `strip` runs along on side `side`, separated by sharp convex edges only
  /// (parallel crossing, seed sect. 4.5), or -1.
  std::int32_t parallel_loop(const std::vector<Passage>& strip, int side,
                             const std::vector<std::vector<Passage>>& loops) const;
  /// The candidates in the order to try them, as the extended rule set ranks them; `filters`
  /// receives the trace of the filters and `reason` what decided the first one.
  std::vector<TraceCandidate> rank_extended(std::vector<TraceCandidate> all,
                                            std::vector<std::string>* filters, std::string* reason,
                                            std::string* decided_by) const;
  /// Weights of shrinking the loop to side A and to side B. \pre label_components() ran.
  std::array<TraceCandidate, 2> weigh(const std::vector<Passage>& strip);
  void label_components();
  std::vector<Transversal> transversals(const std::vector<Passage>& strip, int side) const;
  std::vector<Passage> retrace(const std::vector<Transversal>& edges) const;
  /// Shrinks the loop to side `side`. Returns std::nullopt on success, else why it failed.
  std::optional<std::string> shrink(const std::vector<Passage>& strip, int side);

  std::uint32_t next_stamp() {
    if (++stamp_ == 0) {
      std::fill(node_mark_.begin(), node_mark_.end(), 0);
      stamp_ = 1;
    }
    return stamp_;
  }
  /// A fresh stamp for a per-face mark array, grown to the front's face capacity.
  std::uint32_t next_face_stamp(std::vector<std::uint32_t>& marks, std::uint32_t& stamp) const {
    if (marks.size() < front_.face_capacity()) marks.resize(front_.face_capacity(), 0);
    if (++stamp == 0) {
      std::fill(marks.begin(), marks.end(), 0);
      stamp = 1;
    }
    return stamp;
  }

  Front front_;
  const WeaveOptions& options_;
  std::vector<stc::Hex> hexes_;
  std::vector<std::vector<HexId>> hexes_at_;  // canonical node -> hexes using it
  std::vector<std::array<DualLink, 6>> dual_;
  std::vector<std::int32_t> hex_shrink_;
  std::vector<std::string> hex_rule_;
  WeaveStats stats_;
  std::vector<TraceEvent> trace_;
  [[nodiscard]] bool tracing() const { return options_.trace || options_.on_trace; }
  void record(TraceEvent e) {
    if (options_.on_trace) options_.on_trace(e);
    if (options_.trace) trace_.push_back(std::move(e));
  }
  std::vector<NodeId> seam_work_;
  std::vector<NodeId> blocked_seams_;
  std::int32_t shrink_index_ = -1;
  std::size_t rules_applied_ = 0;
  std::size_t max_rules_ = 0;
  std::vector<std::uint32_t> node_mark_;
  std::uint32_t stamp_ = 0;
  std::vector<std::uint32_t> face_mark_;
  std::vector<std::array<std::int32_t, 2>> loop_of_;
  bool relax_geometry_ = false;
  std::vector<std::size_t> component_of_;
  std::vector<std::size_t> component_size_;
  std::uint32_t face_stamp_ = 0;
  std::vector<std::uint32_t> side_face_mark_;  ///< faces met by a side flood (extended)
  std::uint32_t side_face_stamp_ = 0;
};

// ---------------------------------------------------------------------------------------
// bookkeeping

void Weaver::link(const FaceOwner& a, const FaceOwner& b) {
  const auto set = [this](const FaceOwner& self, const FaceOwner& other) {
    if (!self.is_hex()) return;
    DualLink& l =
        dual_[static_cast<std::size_t>(self.id)][static_cast<std::size_t>(self.local_face)];
    l.is_boundary = other.is_input();
    l.id = other.id;
    l.local_face = other.local_face;
  };
  set(a, b);
  set(b, a);
}

HexId Weaver::make_hex(const stc::Hex& hex, std::span<const FaceIndex> used, const char* rule,
                       NodeId at_node) {
  const HexId id(hexes_.size());
  hexes_.push_back(hex);
  dual_.emplace_back();
  hex_shrink_.push_back(shrink_index_);
  hex_rule_.emplace_back(rule);
  std::array<FaceIndex, 6> face_used{};
  face_used.fill(kNoFace);
  std::vector<std::string> whiskers;
  for (FaceIndex f : used) {
    const auto key = sorted_nodes(front_.face(f).nodes);
    bool matched = false;
    for (int lf = 0; lf < 6; ++lf) {
      if (sorted_nodes(stc::hex_face(hex, lf)) == key) {
        face_used[static_cast<std::size_t>(lf)] = f;
        matched = true;
        break;
      }
    }
    if (!matched) throw InternalError("weave: a used front face is not a face of the new hex");
    whiskers.push_back(front_.face(f).owner.str());
  }
  for (int lf = 0; lf < 6; ++lf) {
    const FaceIndex f = face_used[static_cast<std::size_t>(lf)];
    if (f == kNoFace) continue;
    link(FaceOwner{FaceOwner::Kind::Hex, id.value(), static_cast<std::int8_t>(lf)},
         front_.face(f).owner);
  }
  // Remove the used faces, then add the new ones reversed (outward from the region left).
  std::array<std::int32_t, 6> depth_of{};
  for (int lf = 0; lf < 6; ++lf) {
    const FaceIndex opposite =
        face_used[static_cast<std::size_t>(kOppositeFace[static_cast<std::size_t>(lf)])];
    depth_of[static_cast<std::size_t>(lf)] =
        (opposite != kNoFace && front_.face(opposite).depth >= 0) ? front_.face(opposite).depth + 1
                                                                  : -1;
  }
  // Angles carried over (seed sect. 6): a new face opposite a used face F takes, on each
  // side, the angle F itself holds on the parallel side (a hex edge joins their corners).
  // Faces not opposite a used face carry nothing (flat). F's value is used as stored, not
  // combined with its current neighbour (edge_angle): measured, the combined value breaks
  // the structured results on boxes (cube_tf_medium 6859 -> 8655 hexes) although it helps
  // the larger L-block; see docs/extended-rules.md.
  std::array<std::array<float, 4>, 6> angles_of{};
  for (int lf = 0; lf < 6; ++lf) {
    auto& out = angles_of[static_cast<std::size_t>(lf)];
    out.fill(180.0F);
    if (face_used[static_cast<std::size_t>(lf)] != kNoFace) continue;
    const FaceIndex opposite =
        face_used[static_cast<std::size_t>(kOppositeFace[static_cast<std::size_t>(lf)])];
    if (opposite == kNoFace) continue;
    const stc::Quad mine = stc::reversed(stc::hex_face(hex, lf));
    const FrontFace& old = front_.face(opposite);
    const auto partner = [&](NodeId n) {
      int local = 0;
      while (hex[static_cast<std::size_t>(local)] != n) ++local;
      for (const auto& e : stc::kHexEdges) {
        const int other = e[0] == local ? e[1] : (e[1] == local ? e[0] : -1);
        if (other < 0) continue;
        const NodeId m = hex[static_cast<std::size_t>(other)];
        if (std::find(old.nodes.begin(), old.nodes.end(), m) != old.nodes.end()) return m;
      }
      return NodeId::invalid();
    };
    for (int j = 0; j < 4; ++j) {
      const NodeId a = partner(at(mine, j)), b = partner(at(mine, j + 1));
      for (int k = 0; k < 4; ++k) {
        const NodeId p = at(old.nodes, k), q = at(old.nodes, k + 1);
        if ((p == a && q == b) || (p == b && q == a))
          out[static_cast<std::size_t>(j)] = old.side_angle[static_cast<std::size_t>(k)];
      }
    }
  }
  for (FaceIndex f : used) {
    push_nodes_of(f);
    front_.remove_face(f);
  }
  for (int lf = 0; lf < 6; ++lf) {
    if (face_used[static_cast<std::size_t>(lf)] != kNoFace) continue;
    const FaceIndex f = front_.add_face(
        stc::reversed(stc::hex_face(hex, lf)),
        FaceOwner{FaceOwner::Kind::Hex, id.value(), static_cast<std::int8_t>(lf)},
        depth_of[static_cast<std::size_t>(lf)], angles_of[static_cast<std::size_t>(lf)]);
    push_nodes_of(f);
  }
  for (NodeId n : hex) hexes_at_[n.index()].push_back(id);
  after_rule(rule, at_node, std::move(whiskers), id);
  return id;
}

void Weaver::after_rule(const char* rule, NodeId node, std::vector<std::string> faces, HexId hex) {
  ++rules_applied_;
  if (tracing()) {
    TraceEvent e;
    e.kind = TraceEvent::Kind::Rule;
    e.step = rules_applied_;
    e.rule = rule;
    e.node = node;
    e.faces = std::move(faces);
    e.hex = hex;
    e.shrink = shrink_index_;
    record(std::move(e));
  }
  if (options_.check) {
    if (auto err = front_.check_invariants()) {
      throw InternalError("weave: front invariant broken after " + std::string(rule) + " at " +
                          node.str() + " (rule " + std::to_string(rules_applied_) + "): " + *err);
    }
  }
  if (options_.progress && options_.progress_every > 0 &&
      rules_applied_ % options_.progress_every == 0)
    options_.progress(WeaveProgress{front_.num_faces(), hexes_.size(), stats_.shrinks});
  if (rules_applied_ > max_rules_) {
    throw WeaveError("weave: gave up after " + std::to_string(max_rules_) +
                     " rule applications with " + std::to_string(front_.num_faces()) +
                     " front faces left (raise the limit with max_rules if the input is large)");
  }
}

std::size_t Weaver::common_nodes(HexId a, HexId b, NodeId gone, NodeId keep) const {
  std::array<NodeId, 8> na{}, nb{};
  for (int i = 0; i < 8; ++i) {
    NodeId x = front_.find(hexes_[a.index()][static_cast<std::size_t>(i)]);
    NodeId y = front_.find(hexes_[b.index()][static_cast<std::size_t>(i)]);
    na[static_cast<std::size_t>(i)] = x == gone ? keep : x;
    nb[static_cast<std::size_t>(i)] = y == gone ? keep : y;
  }
  std::sort(na.begin(), na.end());
  std::sort(nb.begin(), nb.end());
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

bool Weaver::share_hex(NodeId x, NodeId y) const {
  const auto& hx = hexes_at_[x.index()];
  const auto& hy = hexes_at_[y.index()];
  for (HexId h : hx)
    if (std::find(hy.begin(), hy.end(), h) != hy.end()) return true;
  return false;
}

std::optional<std::string> Weaver::merge_conflict(NodeId x, NodeId y, NodeId keep,
                                                  NodeId gone) const {
  const auto image = [&](NodeId n) {
    n = front_.find(n);
    return n == gone ? keep : n;
  };
  // the local face of hex h whose four nodes all belong to hex other (after the merge)
  const auto face_within = [&](HexId h, HexId other) -> int {
    for (int lf = 0; lf < 6; ++lf) {
      std::size_t hits = 0;
      for (NodeId n : stc::hex_face(hexes_[h.index()], lf)) {
        const NodeId m = image(n);
        for (NodeId o : hexes_[other.index()]) {
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
  for (HexId h1 : hexes_at_[x.index()]) {
    for (HexId h2 : hexes_at_[y.index()]) {
      const std::size_t common = common_nodes(h1, h2, gone, keep);
      if (common < 4) continue;
      const std::string pair = h1.str() + " and " + h2.str();
      if (common > 4) {
        return "merging " + x.str() + " and " + y.str() + " would make " + pair +
               " share more than one face";
      }
      const int f1 = face_within(h1, h2), f2 = face_within(h2, h1);
      if (f1 < 0 || f2 < 0) {
        return "merging " + x.str() + " and " + y.str() + " would make " + pair +
               " share four nodes that are not a common face";
      }
      if (dual_[h1.index()][static_cast<std::size_t>(f1)].id >= 0 ||
          dual_[h2.index()][static_cast<std::size_t>(f2)].id >= 0) {
        return "merging " + x.str() + " and " + y.str() + " would put a face of " + pair +
               " in more than two hexes";
      }
    }
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------
// rules

/// Seam at a valence-2 node v: faces A = (v, a, x, b) and B = (v, b, y, a) share two edges;
/// both leave the front, x and y merge, and every other pair of faces the merge makes
/// coincident is glued in the same step. \cite seed sect. 2.2 (Fig. 2), RWW.
bool Weaver::try_seam(NodeId v, std::string* why) {
  const auto& at_v = front_.faces_at(v);
  if (at_v.size() != 2) {
    *why = "valence " + std::to_string(at_v.size());
    return false;
  }
  const FaceIndex fa = at_v[0];
  const FaceIndex fb = at_v[1];
  const stc::Quad qa = rotated(front_.face(fa).nodes, front_.corner_of(fa, v));
  const stc::Quad qb = rotated(front_.face(fb).nodes, front_.corner_of(fb, v));
  const NodeId a = qa[1], x = qa[2], b = qa[3];
  if (qb[1] != b || qb[3] != a) {
    *why = "its two faces do not share both edges";
    return false;
  }
  const NodeId y = qb[2];
  const FaceOwner oa = front_.face(fa).owner;
  const FaceOwner ob = front_.face(fb).owner;
  if (oa.is_input() && ob.is_input()) {
    *why = "it would glue two input quads " + oa.str() + " and " + ob.str();
    return false;
  }
  if (oa.is_hex() && ob.is_hex() && oa.id == ob.id) {
    *why = "it would glue two faces of " + HexId(oa.id).str();
    return false;
  }
  const NodeId keep = (x == y)                                                           ? x
                      : (front_.is_input_node(y) || (!front_.is_input_node(x) && y < x)) ? y
                                                                                         : x;
  const NodeId gone = (keep == x) ? y : x;
  if (x != y) {
    if (front_.is_input_node(x) && front_.is_input_node(y)) {
      *why = "it would merge two input nodes " + x.str() + " and " + y.str();
      return false;
    }
    if (share_hex(x, y)) {
      *why = "it would merge " + x.str() + " and " + y.str() + ", two nodes of one hex";
      return false;
    }
    for (FaceIndex f : front_.faces_at(x)) {
      if (front_.corner_of(f, y) >= 0) {
        *why = "it would merge " + x.str() + " and " + y.str() + ", two nodes of one front face";
        return false;
      }
    }
  }
  if (x == y) {
    if (oa.is_hex() && ob.is_hex() && common_nodes(HexId(oa.id), HexId(ob.id), gone, keep) > 4) {
      *why = "hexes " + HexId(oa.id).str() + " and " + HexId(ob.id).str() +
             " would share more than one face";
      return false;
    }
  } else if (auto conflict = merge_conflict(x, y, keep, gone)) {
    *why = *conflict;
    return false;
  }
  // Faces that the merge makes coincide, and the check that the front is not pinched.
  std::vector<std::pair<FaceIndex, FaceIndex>> coincident;
  if (x != y) {
    const auto neighbours = [this](NodeId n, FaceIndex skip, std::vector<NodeId>& out) {
      for (FaceIndex f : front_.faces_at(n)) {
        if (f == skip) continue;
        const int c = front_.corner_of(f, n);
        out.push_back(at(front_.face(f).nodes, c + 1));
        out.push_back(at(front_.face(f).nodes, c + 3));
      }
    };
    std::vector<NodeId> nx, ny, covered;
    neighbours(x, fa, nx);
    neighbours(y, fb, ny);
    for (FaceIndex f : front_.faces_at(x)) {
      if (f == fa) continue;
      const auto key = sorted_nodes(front_.face(f).nodes);
      for (FaceIndex g : front_.faces_at(y)) {
        if (g == fb) continue;
        stc::Quad gq = front_.face(g).nodes;
        for (NodeId& n : gq)
          if (n == y) n = x;
        if (sorted_nodes(gq) != key) continue;
        const FaceOwner of = front_.face(f).owner, og = front_.face(g).owner;
        if (of.is_input() && og.is_input()) {
          *why = "it would make input quads " + of.str() + " and " + og.str() + " coincide";
          return false;
        }
        if (of.is_hex() && og.is_hex() && of.id == og.id) {
          *why = "it would glue two faces of " + HexId(of.id).str();
          return false;
        }
        coincident.emplace_back(f, g);
        const int c = front_.corner_of(f, x);
        covered.push_back(at(front_.face(f).nodes, c + 1));
        covered.push_back(at(front_.face(f).nodes, c + 3));
      }
    }
    for (NodeId p : nx) {
      if (p == a || p == b) continue;
      if (std::find(ny.begin(), ny.end(), p) == ny.end()) continue;
      if (std::find(covered.begin(), covered.end(), p) == covered.end()) {
        *why = "merging " + x.str() + " and " + y.str() + " would pinch the front along edge " +
               x.str() + "-" + p.str();
        return false;
      }
    }
  }
  // Apply.
  std::vector<std::string> whiskers{oa.str(), ob.str()};
  link(oa, ob);
  push_nodes_of(fa);
  push_nodes_of(fb);
  front_.remove_face(fa);
  front_.remove_face(fb);
  if (x != y) {
    merge_nodes(keep, gone);
    for (const auto& [f, g] : coincident) {
      if (!front_.is_alive(f) || !front_.is_alive(g)) continue;
      link(front_.face(f).owner, front_.face(g).owner);
      push_nodes_of(f);
      push_nodes_of(g);
      front_.remove_face(f);
      front_.remove_face(g);
      ++stats_.coincident_glues;
    }
    for (FaceIndex f : front_.faces_at(keep)) push_nodes_of(f);
  }
  ++stats_.seams;
  after_rule(x == y ? "seam-coincident" : "seam", v, std::move(whiskers), HexId::invalid());
  return true;
}

void Weaver::seam_fixpoint() {
  for (NodeId n : blocked_seams_) seam_work_.push_back(n);
  blocked_seams_.clear();
  std::vector<NodeId> blocked;
  while (!seam_work_.empty()) {
    const NodeId n = front_.find(seam_work_.back());
    seam_work_.pop_back();
    if (front_.valence(n) != 2) continue;
    std::string why;
    if (!try_seam(n, &why)) {
      ++stats_.blocked_seams;
      if (std::find(blocked.begin(), blocked.end(), n) == blocked.end()) blocked.push_back(n);
    }
  }
  for (NodeId n : blocked)
    if (front_.valence(front_.find(n)) == 2) blocked_seams_.push_back(front_.find(n));
}

/// Cross at a valence-3 node v: its three faces F1 = (v, a, xab, b), F2 = (v, b, xbc, c),
/// F3 = (v, c, xca, a) become three faces of a new hex (v, b, xab, a, c, xbc, w, xca) with one
/// new node w. \cite seed sect. 2.2 (Fig. 2).
bool Weaver::try_cross(NodeId v, std::string* why) {
  const auto& at_v = front_.faces_at(v);
  if (at_v.size() != 3) {
    *why = "valence " + std::to_string(at_v.size());
    return false;
  }
  const FaceIndex f1 = at_v[0];
  const stc::Quad q1 = rotated(front_.face(f1).nodes, front_.corner_of(f1, v));
  const NodeId a = q1[1], xab = q1[2], b = q1[3];
  FaceIndex f2 = kNoFace, f3 = kNoFace;
  stc::Quad q2{}, q3{};
  for (FaceIndex f : {at_v[1], at_v[2]}) {
    const stc::Quad quad = rotated(front_.face(f).nodes, front_.corner_of(f, v));
    if (quad[1] == b) {
      f2 = f;
      q2 = quad;
    } else if (quad[3] == a) {
      f3 = f;
      q3 = quad;
    }
  }
  if (f2 == kNoFace || f3 == kNoFace || q2[3] != q3[1]) {
    *why = "its three faces do not form a corner";
    return false;
  }
  const NodeId xbc = q2[2], c = q2[3], xca = q3[2];
  std::array<NodeId, 7> nodes{v, a, b, c, xab, xbc, xca};
  std::sort(nodes.begin(), nodes.end());
  if (std::adjacent_find(nodes.begin(), nodes.end()) != nodes.end()) {
    *why = "its three faces do not have 7 distinct nodes";
    return false;
  }
  if (extended() && options_.extended.flat_cross_precondition && !relax_geometry_) {
    // The three edges at v: (v, a) and (b, v) in q1, (c, v) in q2.
    const int c1 = front_.corner_of(f1, v), c2 = front_.corner_of(f2, v);
    const std::array<double, 3> corner{edge_angle(f1, c1), edge_angle(f1, (c1 + 3) % 4),
                                       edge_angle(f2, (c2 + 3) % 4)};
    const auto flat = std::count_if(corner.begin(), corner.end(), [this](double x) {
      return x > options_.extended.little_sharp;
    });
    if (flat > 1) {
      *why = "too flat a corner (" + std::to_string(flat) + " of its 3 edges flatter than " +
             std::to_string(static_cast<int>(options_.extended.little_sharp)) + " degrees)";
      return false;
    }
  }
  const FaceOwner o1 = front_.face(f1).owner, o2 = front_.face(f2).owner,
                  o3 = front_.face(f3).owner;
  const auto same_hex = [](const FaceOwner& p, const FaceOwner& q) {
    return p.is_hex() && q.is_hex() && p.id == q.id;
  };
  if (same_hex(o1, o2) || same_hex(o2, o3) || same_hex(o1, o3)) {
    *why = "two of its faces belong to one hex (the new hex would share two faces with it)";
    return false;
  }
  const NodeId w = new_node();
  const std::array<FaceIndex, 3> used{f1, f2, f3};
  make_hex({v, b, xab, a, c, xbc, w, xca}, used, relax_geometry_ ? "cross-relaxed" : "cross", v);
  ++stats_.crosses;
  return true;
}

/// Blind chord formation at a node v of valence >= 4 on the shrinking side: a strip face f
/// holding v on that side and the non-strip face g across f's shrinking-side edge at v share
/// one edge; a new hex sits on both (two new nodes). \cite seed sect. 2.2 (Fig. 2, Fig. 3).
bool Weaver::try_blind_chord(NodeId v, const std::vector<Passage>& strip, std::string* why) {
  *why = "no strip face at it has a non-strip face across its side edge";
  for (const Passage& p : strip) {
    const stc::Quad& n = front_.face(p.face).nodes;
    if (at(n, p.entry) != v && at(n, p.entry + 3) != v) continue;
    const int side = (p.entry + 3) % 4;  // edge (n[i+3], n[i]) on the shrinking side
    const FaceSide g = front_.across(p.face, side);
    if (g.face == kNoFace) throw InternalError("weave: open front edge at " + v.str());
    if (face_mark_[static_cast<std::size_t>(g.face)] == face_stamp_) continue;  // a strip face
    const NodeId s = at(n, p.entry + 3), t = at(n, p.entry);
    const NodeId p2 = at(n, p.entry + 1), p3 = at(n, p.entry + 2);
    const stc::Quad& qn = front_.face(g.face).nodes;
    const NodeId q2 = at(qn, g.index + 2), q3 = at(qn, g.index + 3);
    std::array<NodeId, 6> six{s, t, p2, p3, q2, q3};
    std::sort(six.begin(), six.end());
    if (std::adjacent_find(six.begin(), six.end()) != six.end()) {
      *why = "faces share more than one edge's nodes";
      continue;
    }
    const FaceOwner of = front_.face(p.face).owner, og = front_.face(g.face).owner;
    if (of.is_hex() && og.is_hex() && of.id == og.id) {
      *why = "both faces belong to " + HexId(of.id).str();
      continue;
    }
    const NodeId n5 = new_node();
    const NodeId n6 = new_node();
    const std::array<FaceIndex, 2> used{p.face, g.face};
    make_hex({s, p3, p2, t, q2, n5, n6, q3}, used, "blind-chord", v);
    ++stats_.blind_chords;
    return true;
  }
  return false;
}

/// Parallel merging, seed sect. 5.1 (Fig. 10), as we read it (docs/extended-rules.md): the
/// strip of the central loop l is one face high, its side edges are sharp on both sides, and
/// the strip's transversal edges map the rim of the region on side A (bounded by ll) onto
/// the rim of the region on side B (bounded by lr). When that map extends, face by face, to
/// an isomorphism between the two regions (two discs facing each other), ll and lr are the
/// two ends of one sheet: it is closed at once by one hex per face pair (the first chord
/// made, along the strip, is the torus of hexes of the seed). No node is created or merged.
bool Weaver::try_parallel_merging(const std::vector<Passage>& strip, std::string* why) {
  const std::uint32_t strip_stamp = next_face_stamp(face_mark_, face_stamp_);
  for (const Passage& p : strip) {
    if (face_mark_[static_cast<std::size_t>(p.face)] == strip_stamp) {
      *why = "the strip passes a face twice";
      return false;
    }
    face_mark_[static_cast<std::size_t>(p.face)] = strip_stamp;
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
  std::vector<FaceIndex> queue;
  for (const Passage& p : strip) {
    const stc::Quad& n = front_.face(p.face).nodes;
    if (!assign(at(n, p.entry), at(n, p.entry + 1)) ||
        !assign(at(n, p.entry + 3), at(n, p.entry + 2))) {
      *why = "the strip's transversal edges do not map one rim onto the other";
      return false;
    }
    for (int side : {(p.entry + 3) % 4, (p.entry + 1) % 4}) {
      const FaceSide g = front_.across(p.face, side);
      if (g.face == kNoFace || face_mark_[static_cast<std::size_t>(g.face)] == strip_stamp) {
        *why = "the strip is more than one face high";
        return false;
      }
      if (side == (p.entry + 3) % 4) queue.push_back(g.face);
    }
  }
  // Extend the map over side A's region, face by face, from the rim inward.
  std::vector<std::uint32_t>& seen = side_face_mark_;
  const std::uint32_t in_a = next_face_stamp(side_face_mark_, side_face_stamp_);
  std::vector<std::pair<FaceIndex, FaceIndex>> pairs;
  std::vector<FaceIndex> images;
  for (FaceIndex f : queue) seen[static_cast<std::size_t>(f)] = in_a;
  for (std::size_t qi = 0; qi < queue.size(); ++qi) {
    const FaceIndex f = queue[qi];
    const stc::Quad& fq = front_.face(f).nodes;
    int k = -1;
    for (int j = 0; j < 4 && k < 0; ++j)
      if (image.count(at(fq, j).index()) != 0 && image.count(at(fq, j + 1).index()) != 0) k = j;
    if (k < 0) {  // reached before any of its edges was mapped: try again later
      if (qi + queue.size() > 8 * front_.num_faces()) {
        *why = "the region on side A is not a disc the strip maps";
        return false;
      }
      queue.push_back(f);
      continue;
    }
    const NodeId u = at(fq, k), v = at(fq, k + 1), w = at(fq, k + 2), x = at(fq, k + 3);
    const FaceSide gs = front_.find_edge(image.at(v.index()), image.at(u.index()));
    if (gs.face == kNoFace || face_mark_[static_cast<std::size_t>(gs.face)] == strip_stamp ||
        seen[static_cast<std::size_t>(gs.face)] == in_a) {
      *why = "no face of side B faces " + front_.face(f).owner.str();
      return false;
    }
    const stc::Quad& gq = front_.face(gs.face).nodes;
    if (!assign(x, at(gq, gs.index + 2)) || !assign(w, at(gq, gs.index + 3))) {
      *why = "the two regions differ at " + front_.face(f).owner.str();
      return false;
    }
    const FaceOwner of = front_.face(f).owner, og = front_.face(gs.face).owner;
    if (of.is_hex() && og.is_hex() && of.id == og.id) {
      *why = "the faces " + of.str() + " and " + og.str() + " belong to one hex";
      return false;
    }
    pairs.emplace_back(f, gs.face);
    images.push_back(gs.face);
    for (int j = 0; j < 4; ++j) {
      const FaceSide h = front_.across(f, j);
      if (h.face == kNoFace || face_mark_[static_cast<std::size_t>(h.face)] == strip_stamp ||
          seen[static_cast<std::size_t>(h.face)] == in_a)
        continue;
      seen[static_cast<std::size_t>(h.face)] = in_a;
      queue.push_back(h.face);
    }
  }
  std::sort(images.begin(), images.end());
  if (std::adjacent_find(images.begin(), images.end()) != images.end()) {
    *why = "two faces of side A face the same face of side B";
    return false;
  }
  for (FaceIndex g : images) {
    if (seen[static_cast<std::size_t>(g)] == in_a) {
      *why = "the regions on the two sides overlap";
      return false;
    }
  }
  // Every face of the front component must be used: the strip, side A and side B.
  const std::size_t component = component_of_[front_.face(strip.front().face).nodes[0].index()];
  std::size_t faces_in_component = 0;
  for (std::size_t fi = 0; fi < front_.face_capacity(); ++fi) {
    const auto f = static_cast<FaceIndex>(fi);
    if (front_.is_alive(f) && component_of_[front_.face(f).nodes[0].index()] == component)
      ++faces_in_component;
  }
  if (faces_in_component != strip.size() + 2 * pairs.size()) {
    *why = "the strip and the two regions are not the whole front component";
    return false;
  }
  // No new hex may share two faces with one hex.
  const auto hex_of = [this](const stc::Hex& hex, int lf) -> FaceIndex {
    const auto key = sorted_nodes(stc::hex_face(hex, lf));
    for (FaceIndex g : front_.faces_at(
             hex[static_cast<std::size_t>(stc::kHexFaces[static_cast<std::size_t>(lf)][0])]))
      if (sorted_nodes(front_.face(g).nodes) == key) return g;
    return kNoFace;
  };
  std::vector<stc::Hex> hexes;
  hexes.reserve(pairs.size());
  for (const auto& [f, g] : pairs) {
    const stc::Quad fq = front_.face(f).nodes;
    const auto img = [&](NodeId n) { return image.at(n.index()); };
    hexes.push_back({fq[0], fq[3], fq[2], fq[1], img(fq[0]), img(fq[3]), img(fq[2]), img(fq[1])});
    std::vector<std::int32_t> owners;
    for (int lf = 0; lf < 6; ++lf) {
      const FaceIndex h = hex_of(hexes.back(), lf);
      if (h != kNoFace && front_.face(h).owner.is_hex()) owners.push_back(front_.face(h).owner.id);
    }
    std::sort(owners.begin(), owners.end());
    if (std::adjacent_find(owners.begin(), owners.end()) != owners.end()) {
      *why = "a new hex would share two faces with one hex";
      return false;
    }
  }
  // Apply: each hex uses its two disc faces and whatever of its side faces is on the front
  // (strip faces on the rim, faces of the hexes just made inside).
  for (std::size_t i = 0; i < hexes.size(); ++i) {
    std::vector<FaceIndex> used;
    for (int lf = 0; lf < 6; ++lf) {
      const FaceIndex h = hex_of(hexes[i], lf);
      if (h != kNoFace) used.push_back(h);
    }
    make_hex(hexes[i], used, "parallel-merge", hexes[i][0]);
  }
  return true;
}

bool Weaver::merge_parallel(const std::vector<std::vector<Passage>>& loops,
                            const std::vector<TraceCandidate>& candidates) {
  for (std::size_t i = 0; i + 1 < candidates.size(); i += 2) {
    const TraceCandidate& a = candidates[i];
    const TraceCandidate& b = candidates[i + 1];
    if (a.self_intersecting || a.length < 3 || a.side_sharp != a.length ||
        b.side_sharp != b.length || a.faces_collapsed != b.faces_collapsed)
      continue;
    const auto& strip = loops[static_cast<std::size_t>(a.loop)];
    std::string why;
    const std::size_t before = rules_applied_;
    if (tracing()) {
      TraceEvent e;
      e.kind = TraceEvent::Kind::Selection;
      e.step = rules_applied_;
      e.candidates = {a, b};
      e.chosen = 0;
      e.reason = "parallel merging: loop " + std::to_string(a.loop) +
                 " has sharp edges on both sides between two discs of the front";
      e.filters = {"parallel_merging:1"};
      e.decided_by = "parallel_merging";
      e.shrink = shrink_index_ + 1;
      record(std::move(e));
    }
    ++shrink_index_;
    if (try_parallel_merging(strip, &why)) {
      ++stats_.parallel_merges;
      seam_fixpoint();
      return true;
    }
    if (rules_applied_ != before)
      throw InternalError("weave: parallel merging failed after changing the front: " + why);
    if (tracing()) {
      TraceEvent e;
      e.kind = TraceEvent::Kind::ShrinkFailed;
      e.step = rules_applied_;
      e.reason = "parallel merging refused: " + why;
      e.shrink = shrink_index_;
      record(std::move(e));
    }
  }
  return false;
}

/// Non-convexity seam, seed sect. 5.2 (Fig. 11), as we read it (docs/extended-rules.md):
/// F2 is an input quad, F1 a hex face across its side E (they share only E). E is convex,
/// a side of F2 next to E is non-convex, and F1's two nodes off E are interior nodes (the
/// seed names F2's, which cannot be: input nodes never merge). F1 is folded onto F2 about
/// E: its two far nodes merge with F2's and the two faces, now coincident, are glued. The
/// faces this leaves sharing two edges are sewn by the basic seams that follow. The front is
/// saved first and restored when the fold would break it.
bool Weaver::try_nonconvexity_seam(FaceIndex f2, int side, std::string* why) {
  const ExtendedParameters& par = options_.extended;
  const FaceSide across = front_.across(f2, side);
  if (across.face == kNoFace || !front_.face(across.face).owner.is_hex()) {
    *why = "no hex face across";
    return false;
  }
  if (edge_angle(f2, side) > par.little_sharp) {
    *why = "the common edge is not convex";
    return false;
  }
  if (edge_angle(f2, (side + 1) % 4) <= par.flat && edge_angle(f2, (side + 3) % 4) <= par.flat) {
    *why = "no non-convex edge next to the common edge";
    return false;
  }
  const FaceIndex f1 = across.face;
  const stc::Quad q2 = front_.face(f2).nodes;
  const stc::Quad q1 = front_.face(f1).nodes;
  // q2 = [v, u, c, d] from its side `side`; q1 holds u -> v: q1 = [u, v, a, b].
  const NodeId v = at(q2, side), u = at(q2, side + 1), c = at(q2, side + 2), d = at(q2, side + 3);
  const NodeId a = at(q1, across.index + 2), b = at(q1, across.index + 3);
  if (at(q1, across.index) != u || at(q1, across.index + 1) != v) {
    *why = "the faces do not hold their common edge in opposite directions";
    return false;
  }
  if (a.index() < front_.num_input_nodes() || b.index() < front_.num_input_nodes()) {
    *why = "a node of the hex face off the common edge is an input node";
    return false;
  }
  for (NodeId n : {a, b}) {
    if (n == c || n == d) {
      *why = "the faces share more than one edge";
      return false;
    }
  }
  // Folding about E takes a (next to v in q1) onto d (next to v in q2), b onto c.
  if (share_hex(a, d) || share_hex(b, c)) {
    *why = "a merge would join two nodes of one hex";
    return false;
  }
  if (auto conflict = merge_conflict(a, d, d, a)) {
    *why = *conflict;
    return false;
  }
  Snapshot saved = save();
  merge_nodes(d, a);
  if (auto conflict = merge_conflict(b, c, c, b)) {
    restore(std::move(saved));
    *why = *conflict;
    return false;
  }
  merge_nodes(c, b);
  // Glue every pair of faces that now coincide around the four nodes (q1 and q2 first).
  std::vector<std::string> whiskers;
  bool ok = true;
  for (NodeId n : {c, d, u, v}) {
    const auto& faces = front_.faces_at(n);
    for (std::size_t i = 0; i < faces.size() && ok; ++i) {
      for (std::size_t j = i + 1; j < faces.size(); ++j) {
        const FaceIndex p = faces[i], q = faces[j];
        if (sorted_nodes(front_.face(p).nodes) != sorted_nodes(front_.face(q).nodes)) continue;
        const FaceOwner op = front_.face(p).owner, oq = front_.face(q).owner;
        if ((op.is_input() && oq.is_input()) || (op.is_hex() && oq.is_hex() && op.id == oq.id)) {
          ok = false;
          break;
        }
        whiskers.push_back(op.str());
        whiskers.push_back(oq.str());
        link(op, oq);
        push_nodes_of(p);
        push_nodes_of(q);
        front_.remove_face(p < q ? q : p);
        front_.remove_face(p < q ? p : q);
        j = faces.size();  // the list changed: rescan this node
        i = static_cast<std::size_t>(-1);
        break;
      }
    }
  }
  std::optional<std::string> broken;
  if (ok) broken = front_.check_invariants();
  if (!ok || broken) {
    restore(std::move(saved));
    *why = ok ? "the fold would break the front: " + *broken
              : "the fold would glue two faces "
                "that must not meet";
    return false;
  }
  for (FaceIndex f : front_.faces_at(c)) push_nodes_of(f);
  for (FaceIndex f : front_.faces_at(d)) push_nodes_of(f);
  ++stats_.nonconvexity_seams;
  after_rule("nonconvexity-seam", v, std::move(whiskers), HexId::invalid());
  return true;
}

std::size_t Weaver::nonconvexity_seams() {
  std::size_t applied = 0;
  for (std::size_t fi = 0; fi < front_.face_capacity(); ++fi) {
    const auto f = static_cast<FaceIndex>(fi);
    for (int side = 0; side < 4; ++side) {
      if (!front_.is_alive(f) || !front_.face(f).owner.is_input()) break;
      std::string why;
      if (try_nonconvexity_seam(f, side, &why)) {
        ++applied;
        seam_fixpoint();
      }
    }
  }
  return applied;
}

// ---------------------------------------------------------------------------------------
// loops

std::vector<Passage> Weaver::trace_loop(FaceIndex f, int entry) const {
  std::vector<Passage> out;
  const Passage start{f, entry};
  Passage cur = start;
  const std::size_t limit = 2 * front_.num_faces() + 4;
  do {
    out.push_back(cur);
    const FaceSide next = front_.across(cur.face, (cur.entry + 2) % 4);
    if (next.face == kNoFace) throw InternalError("weave: open front edge while tracing a loop");
    cur = Passage{next.face, next.index};
    if (out.size() > limit) throw InternalError("weave: runaway loop trace");
  } while (cur.face != start.face || cur.entry != start.entry);
  return out;
}

double Weaver::edge_angle(FaceIndex f, int side) const {
  const double a = front_.face(f).side_angle[static_cast<std::size_t>(side)];
  const FaceSide g = front_.across(f, side);
  if (g.face == kNoFace) return a;
  const double b = front_.face(g.face).side_angle[static_cast<std::size_t>(g.index)];
  const double da = a - 180.0, db = b - 180.0;
  if ((da >= 0.0) == (db >= 0.0)) return 180.0 + (std::abs(da) >= std::abs(db) ? da : db);
  return 180.0 + da + db;
}

std::vector<std::vector<Passage>> Weaver::all_loops() {
  loop_of_.assign(front_.face_capacity(), {-1, -1});
  std::vector<std::array<bool, 2>> seen(front_.face_capacity(), {false, false});
  std::vector<std::vector<Passage>> loops;
  for (std::size_t fi = 0; fi < front_.face_capacity(); ++fi) {
    const auto f = static_cast<FaceIndex>(fi);
    if (!front_.is_alive(f)) continue;
    for (int dir = 0; dir < 2; ++dir) {
      if (seen[fi][static_cast<std::size_t>(dir)]) continue;
      auto loop = trace_loop(f, dir);
      for (const Passage& p : loop) {
        const auto d = static_cast<std::size_t>(p.entry % 2);
        seen[static_cast<std::size_t>(p.face)][d] = true;
        loop_of_[static_cast<std::size_t>(p.face)][d] = static_cast<std::int32_t>(loops.size());
      }
      loops.push_back(std::move(loop));
    }
  }
  return loops;
}

std::array<TraceCandidate, 2> Weaver::weigh(const std::vector<Passage>& strip) {
  std::array<TraceCandidate, 2> c;
  c[0].side = 0;
  c[1].side = 1;
  c[0].length = c[1].length = strip.size();
  next_face_stamp(face_mark_, face_stamp_);
  bool self_intersecting = false;
  for (const Passage& p : strip) {
    if (face_mark_[static_cast<std::size_t>(p.face)] == face_stamp_) self_intersecting = true;
    face_mark_[static_cast<std::size_t>(p.face)] = face_stamp_;
  }
  c[0].self_intersecting = c[1].self_intersecting = self_intersecting;
  // Stamps: `on` for strip nodes, `side[0]`/`side[1]` for nodes reached from either side.
  const std::uint32_t on = next_stamp();
  const std::array<std::uint32_t, 2> side{next_stamp(), next_stamp()};
  std::array<std::vector<NodeId>, 2> stack;
  std::size_t on_strip = 0;
  for (const Passage& p : strip) {
    const stc::Quad& n = front_.face(p.face).nodes;
    for (NodeId m : n) {
      if (node_mark_[m.index()] == on) continue;
      node_mark_[m.index()] = on;
      ++on_strip;
    }
    // side A nodes: n[i], n[i+3]; side B: n[i+1], n[i+2]
    stack[0].push_back(at(n, p.entry));
    stack[0].push_back(at(n, p.entry + 3));
    stack[1].push_back(at(n, p.entry + 1));
    stack[1].push_back(at(n, p.entry + 2));
  }
  c[0].on_strip = c[1].on_strip = on_strip;
  // Flood both sides through non-strip faces, one node at a time each, until one side is
  // exhausted: that side is then complete, and on a loop that separates its component the
  // other side is the rest of the component. If the floods meet, the loop does not separate
  // (it crosses itself): count each side by a full flood.
  std::array<std::size_t, 2> count{0, 0};
  bool met = false;
  const auto expand = [&](int d) {
    const NodeId n = stack[static_cast<std::size_t>(d)].back();
    stack[static_cast<std::size_t>(d)].pop_back();
    for (FaceIndex f : front_.faces_at(n)) {
      if (face_mark_[static_cast<std::size_t>(f)] == face_stamp_) continue;
      for (NodeId m : front_.face(f).nodes) {
        const std::uint32_t mark = node_mark_[m.index()];
        if (mark == on || mark == side[static_cast<std::size_t>(d)]) continue;
        if (mark == side[static_cast<std::size_t>(1 - d)]) {
          met = true;
          continue;
        }
        node_mark_[m.index()] = side[static_cast<std::size_t>(d)];
        ++count[static_cast<std::size_t>(d)];
        stack[static_cast<std::size_t>(d)].push_back(m);
      }
    }
  };
  while (!met && !stack[0].empty() && !stack[1].empty()) {
    expand(0);
    if (!met && !stack[1].empty()) expand(1);
  }
  if (!met) {
    const int done = stack[0].empty() ? 0 : 1;
    const std::size_t total =
        component_size_[component_of_[front_.face(strip.front().face).nodes[0].index()]];
    c[static_cast<std::size_t>(done)].strictly_on_side = count[static_cast<std::size_t>(done)];
    c[static_cast<std::size_t>(1 - done)].strictly_on_side =
        total - on_strip - count[static_cast<std::size_t>(done)];
  } else {
    for (int d = 0; d < 2; ++d) {
      const std::uint32_t mark = next_stamp();
      for (const Passage& p : strip)
        for (NodeId m : front_.face(p.face).nodes) node_mark_[m.index()] = mark;
      std::vector<NodeId> st;
      for (const Passage& p : strip) {
        const stc::Quad& n = front_.face(p.face).nodes;
        st.push_back(at(n, d == 0 ? p.entry : p.entry + 1));
        st.push_back(at(n, d == 0 ? p.entry + 3 : p.entry + 2));
      }
      std::size_t strict = 0;
      while (!st.empty()) {
        const NodeId n = st.back();
        st.pop_back();
        for (FaceIndex f : front_.faces_at(n)) {
          if (face_mark_[static_cast<std::size_t>(f)] == face_stamp_) continue;
          for (NodeId m : front_.face(f).nodes) {
            if (node_mark_[m.index()] == mark) continue;
            node_mark_[m.index()] = mark;
            ++strict;
            st.push_back(m);
          }
        }
      }
      c[static_cast<std::size_t>(d)].strictly_on_side = strict;
    }
  }
  for (auto& x : c) x.weight = x.strictly_on_side + x.on_strip;
  return c;
}

void Weaver::label_components() {
  component_of_.assign(front_.num_nodes(), 0);
  component_size_.clear();
  const std::uint32_t mark = next_stamp();
  std::vector<NodeId> stack;
  for (std::size_t v = 0; v < front_.num_nodes(); ++v) {
    const NodeId start(v);
    if (front_.valence(start) == 0 || node_mark_[v] == mark) continue;
    const std::size_t comp = component_size_.size();
    component_size_.push_back(0);
    node_mark_[v] = mark;
    stack.push_back(start);
    while (!stack.empty()) {
      const NodeId n = stack.back();
      stack.pop_back();
      component_of_[n.index()] = comp;
      ++component_size_[comp];
      for (FaceIndex f : front_.faces_at(n)) {
        for (NodeId m : front_.face(f).nodes) {
          if (node_mark_[m.index()] == mark) continue;
          node_mark_[m.index()] = mark;
          stack.push_back(m);
        }
      }
    }
  }
}

std::array<TraceCandidate, 2> Weaver::extended_properties(const std::vector<Passage>& strip) {
  std::array<TraceCandidate, 2> c = weigh(strip);  // marks the strip faces (face_stamp_)
  const ExtendedParameters& par = options_.extended;
  std::vector<FaceIndex> strip_face_list;
  strip_face_list.reserve(strip.size());
  for (const Passage& p : strip) strip_face_list.push_back(p.face);
  std::sort(strip_face_list.begin(), strip_face_list.end());
  const auto strip_faces = static_cast<std::size_t>(
      std::unique(strip_face_list.begin(), strip_face_list.end()) - strip_face_list.begin());
  std::size_t crossed = 0;
  std::array<std::size_t, 2> side_sharp{0, 0};
  std::array<std::size_t, 2> nonconvex{0, 0};
  for (const Passage& p : strip) {
    if (edge_angle(p.face, p.entry) <= par.little_sharp) ++crossed;
    for (int d = 0; d < 2; ++d) {
      const int side = d == 0 ? (p.entry + 3) % 4 : (p.entry + 1) % 4;
      const double a = edge_angle(p.face, side);
      if (a <= par.sharp) ++side_sharp[static_cast<std::size_t>(d)];
      if (a > par.flat) ++nonconvex[static_cast<std::size_t>(d)];
    }
  }
  for (int d = 0; d < 2; ++d) {
    // Flood side d from its strip nodes through non-strip faces: faces on that side, their
    // depths and their non-convex edges (each edge counted once).
    const std::uint32_t node_seen = next_stamp();
    for (const Passage& p : strip)
      for (NodeId m : front_.face(p.face).nodes) node_mark_[m.index()] = node_seen;
    std::vector<NodeId> stack;
    for (const Passage& p : strip) {
      const stc::Quad& n = front_.face(p.face).nodes;
      stack.push_back(at(n, d == 0 ? p.entry : p.entry + 1));
      stack.push_back(at(n, d == 0 ? p.entry + 3 : p.entry + 2));
    }
    std::vector<FaceIndex> faces;
    next_face_stamp(side_face_mark_, side_face_stamp_);
    while (!stack.empty()) {
      const NodeId n = stack.back();
      stack.pop_back();
      for (FaceIndex f : front_.faces_at(n)) {
        if (face_mark_[static_cast<std::size_t>(f)] == face_stamp_ ||
            side_face_mark_[static_cast<std::size_t>(f)] == side_face_stamp_)
          continue;
        side_face_mark_[static_cast<std::size_t>(f)] = side_face_stamp_;
        faces.push_back(f);
        for (NodeId m : front_.face(f).nodes) {
          if (node_mark_[m.index()] == node_seen) continue;
          node_mark_[m.index()] = node_seen;
          stack.push_back(m);
        }
      }
    }
    std::int32_t depth = 0;
    for (FaceIndex f : faces) {
      const std::int32_t fd = front_.face(f).depth;
      if (fd > 0 && (depth == 0 || fd < depth)) depth = fd;
      for (int k = 0; k < 4; ++k) {
        const FaceSide g = front_.across(f, k);
        const bool once = g.face == kNoFace ||
                          face_mark_[static_cast<std::size_t>(g.face)] == face_stamp_ || f < g.face;
        if (once && edge_angle(f, k) > par.flat) ++nonconvex[static_cast<std::size_t>(d)];
      }
    }
    TraceCandidate& x = c[static_cast<std::size_t>(d)];
    x.faces_collapsed = faces.size() + strip_faces;
    x.depth = depth;
    x.crossed_sharp = crossed;
    x.side_sharp = side_sharp[static_cast<std::size_t>(d)];
    x.nonconvex_on_side = nonconvex[static_cast<std::size_t>(d)];
  }
  return c;
}

std::int32_t Weaver::parallel_loop(const std::vector<Passage>& strip, int side,
                                   const std::vector<std::vector<Passage>>& loops) const {
  std::int32_t other = -1;
  const std::int32_t self = loop_of_[static_cast<std::size_t>(strip.front().face)]
                                    [static_cast<std::size_t>(strip.front().entry % 2)];
  for (const Passage& p : strip) {
    const int s = side == 0 ? (p.entry + 3) % 4 : (p.entry + 1) % 4;
    if (edge_angle(p.face, s) > options_.extended.sharp) return -1;
    const FaceSide g = front_.across(p.face, s);
    if (g.face == kNoFace) return -1;
    // the loop that has this edge as a side edge enters g perpendicularly to it
    const std::int32_t l =
        loop_of_[static_cast<std::size_t>(g.face)][static_cast<std::size_t>((g.index + 1) % 2)];
    if (l < 0 || l == self || (other >= 0 && l != other)) return -1;
    other = l;
  }
  if (other < 0 || loops[static_cast<std::size_t>(other)].size() != strip.size()) return -1;
  return other;
}

std::vector<TraceCandidate> Weaver::rank_extended(std::vector<TraceCandidate> all,
                                                  std::vector<std::string>* filters,
                                                  std::string* reason,
                                                  std::string* decided_by) const {
  const ExtendedParameters& par = options_.extended;
  const auto topological = [](const TraceCandidate& p, const TraceCandidate& q) {
    if (p.faces_collapsed != q.faces_collapsed) return p.faces_collapsed < q.faces_collapsed;
    return p.weight < q.weight;
  };
  std::stable_sort(all.begin(), all.end(), topological);
  std::vector<TraceCandidate> set;
  for (const auto& c : all)
    if (!c.self_intersecting) set.push_back(c);
  if (set.empty()) set = all;
  const auto note = [&](const std::string& name, std::size_t before, bool relaxed) {
    filters->push_back(name + ":" + std::to_string(before) + "->" +
                       (relaxed ? std::string("relaxed") : std::to_string(set.size())));
  };
  const auto keep = [&](const std::string& name, auto pred, bool relaxable) {
    std::vector<TraceCandidate> kept;
    for (const auto& c : set)
      if (pred(c)) kept.push_back(c);
    const std::size_t before = set.size();
    if (kept.empty() && relaxable) {
      note(name, before, true);
      return;
    }
    if (!kept.empty()) set = std::move(kept);
    note(name, before, false);
    if (set.size() == 1 && decided_by->empty()) *decided_by = name;
  };
  bool decided = false;
  if (par.parallel_crossing) {
    std::vector<TraceCandidate> parallel;
    for (const auto& c : set)
      if (c.parallel_to >= 0) parallel.push_back(c);
    filters->push_back("parallel_crossing:" + std::to_string(parallel.size()));
    if (!parallel.empty()) {
      set = std::move(parallel);
      *reason = "parallel crossing: runs along loop " + std::to_string(set.front().parallel_to) +
                " across sharp convex edges; fewest faces collapsed";
      decided = true;
      *decided_by = "parallel_crossing";
    }
  }
  if (!decided) {
    if (par.nonconvex_filter) {
      keep(
          "nonconvex", [](const TraceCandidate& c) { return c.nonconvex_on_side == 0; }, true);
    }
    if (par.depth_filter) {
      std::int32_t least = std::numeric_limits<std::int32_t>::max();
      for (const auto& c : set) least = std::min(least, c.depth);
      keep(
          "depth", [least](const TraceCandidate& c) { return c.depth == least; }, false);
    }
    if (par.first_convex_filter) {
      keep(
          "first_convex", [](const TraceCandidate& c) { return c.crossed_sharp > 0; }, true);
    }
    if (par.second_convex_filter) {
      double best = 0.0;
      const auto ratio = [](const TraceCandidate& c) {
        return static_cast<double>(c.side_sharp) /
               static_cast<double>(std::max<std::size_t>(1, c.length));
      };
      for (const auto& c : set) best = std::max(best, ratio(c));
      keep(
          "second_convex", [&](const TraceCandidate& c) { return ratio(c) >= best - 1e-12; },
          false);
    }
    filters->push_back("topological:" + std::to_string(set.size()));
    if (decided_by->empty()) *decided_by = "topological";
    *reason = "filters " + [&] {
      std::string joined;
      for (const auto& f : *filters) joined += (joined.empty() ? "" : ", ") + f;
      return joined;
    }() + "; fewest faces collapsed";
  }
  // The chosen set first (already in topological order), then every other candidate.
  std::vector<TraceCandidate> order = set;
  for (const auto& c : all) {
    const bool in = std::any_of(set.begin(), set.end(), [&](const TraceCandidate& x) {
      return x.loop == c.loop && x.side == c.side;
    });
    if (!in) order.push_back(c);
  }
  return order;
}

std::vector<Transversal> Weaver::transversals(const std::vector<Passage>& strip, int side) const {
  std::vector<Transversal> out;
  out.reserve(strip.size());
  for (const Passage& p : strip) {
    const stc::Quad& n = front_.face(p.face).nodes;
    if (side == 0) {
      out.push_back({at(n, p.entry), at(n, p.entry + 1)});
    } else {
      out.push_back({at(n, p.entry + 1), at(n, p.entry)});
    }
  }
  return out;
}

std::vector<Passage> Weaver::retrace(const std::vector<Transversal>& edges) const {
  for (const Transversal& t : edges) {
    const NodeId d = front_.find(t.side_node), e = front_.find(t.other);
    if (d == e) continue;
    const FaceSide fs = front_.find_edge(d, e);
    if (fs.face != kNoFace) return trace_loop(fs.face, fs.index);
  }
  return {};
}

std::optional<std::string> Weaver::shrink(const std::vector<Passage>& initial, int side) {
  std::vector<Transversal> edges = transversals(initial, side);
  std::vector<NodeId> order;
  for (;;) {
    seam_fixpoint();
    const std::vector<Passage> strip = retrace(edges);
    if (strip.empty()) return std::nullopt;
    edges = transversals(strip, 0);
    // mark strip faces for the blind chord rule
    next_face_stamp(face_mark_, face_stamp_);
    for (const Passage& p : strip) face_mark_[static_cast<std::size_t>(p.face)] = face_stamp_;
    // side nodes in loop order, each once, then by increasing valence (stable)
    order.clear();
    const std::uint32_t seen = next_stamp();
    for (const Passage& p : strip) {
      const stc::Quad& n = front_.face(p.face).nodes;
      for (NodeId m : {at(n, p.entry), at(n, p.entry + 3)}) {
        if (node_mark_[m.index()] == seen) continue;
        node_mark_[m.index()] = seen;
        order.push_back(m);
      }
    }
    // The fewest-sided node first (ties: loop order). Usually its rule applies, so find it
    // by a scan and sort the rest only when it is blocked.
    const auto by_valence = [this](NodeId p, NodeId q) {
      return front_.valence(p) < front_.valence(q);
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
      const std::size_t k = front_.valence(v);
      if (k == 2) {
        why = "valence 2 but its seam is blocked";
        std::string detail;
        if (!try_seam(v, &detail)) {
          why += " (" + detail + ")";
        } else {
          applied = true;
        }
      } else if (k == 3) {
        applied = try_cross(v, &why);
        if (!applied) why.insert(0, "cross refused: ");
      } else {
        applied = try_blind_chord(v, strip, &why);
        if (!applied) why.insert(0, "blind chord refused: ");
      }
      if (applied) break;
      if (reasons.size() < 600) reasons += (reasons.empty() ? "" : "; ") + v.str() + ": " + why;
    }
    if (!applied && extended() && options_.extended.flat_cross_precondition && !relax_geometry_) {
      relax_geometry_ = true;  // RWW: geometric preconditions give way to complete the weave
      ++stats_.relaxed_preconditions;
      continue;
    }
    relax_geometry_ = false;
    if (!applied) return "every node on the shrinking side is blocked: " + reasons;
  }
}

WeaveResult Weaver::run() {
  for (std::size_t n = 0; n < front_.num_nodes(); ++n) seam_work_.push_back(NodeId(n));
  std::reverse(seam_work_.begin(), seam_work_.end());
  seam_fixpoint();
  while (front_.num_faces() > 0) {
    if (extended() && options_.extended.nonconvexity_seam && nonconvexity_seams() > 0 &&
        front_.num_faces() == 0)
      break;
    const auto loops = all_loops();
    std::vector<TraceCandidate> candidates;
    candidates.reserve(loops.size() * 2);
    label_components();
    for (std::size_t l = 0; l < loops.size(); ++l) {
      const auto pair = extended() ? extended_properties(loops[l]) : weigh(loops[l]);
      for (TraceCandidate c : pair) {
        c.loop = static_cast<std::int32_t>(l);
        if (extended() && options_.extended.parallel_crossing && !c.self_intersecting)
          c.parallel_to = parallel_loop(loops[l], c.side, loops);
        candidates.push_back(c);
      }
    }
    if (extended() && options_.extended.parallel_merging && merge_parallel(loops, candidates))
      continue;
    std::vector<std::string> filters;
    std::string decided_by = "weight";
    std::string first_reason = "smallest weight (strictly on side + on strip)";
    if (extended()) {
      decided_by.clear();
      candidates = rank_extended(std::move(candidates), &filters, &first_reason, &decided_by);
    } else {
      // Ranking: loops that do not cross themselves first, then the smallest weight, then the
      // lowest loop index (loops are enumerated from the lowest front face slot), side A
      // first.
      std::stable_sort(candidates.begin(), candidates.end(),
                       [](const TraceCandidate& p, const TraceCandidate& q) {
                         if (p.self_intersecting != q.self_intersecting)
                           return !p.self_intersecting;
                         return p.weight < q.weight;
                       });
    }
    ++stats_.selections;
    bool progressed = false;
    std::string failures;
    // Backtracking: a shrink that ends blocked is undone and the next candidate is tried;
    // when every candidate fails from this front, the first one's partial shrink is kept
    // (the front changed, so the selection starts again) as the last resort.
    const bool backtrack = options_.backtrack;
    for (std::size_t attempt = 0; attempt < (backtrack ? 2U : 1U) && !progressed; ++attempt) {
      const bool last_resort = backtrack && attempt == 1;
      const std::size_t count =
          last_resort ? std::min<std::size_t>(1, candidates.size()) : candidates.size();
      for (std::size_t ci = 0; ci < count; ++ci) {
        const TraceCandidate& c = candidates[ci];
        if (tracing()) {
          TraceEvent e;
          e.kind = TraceEvent::Kind::Selection;
          e.step = rules_applied_;
          e.candidates = candidates;
          e.chosen = static_cast<std::int32_t>(ci);
          e.reason = last_resort ? "every candidate failed: the first one's partial shrink is kept"
                     : ci == 0   ? first_reason
                                 : "previous candidates failed to shrink";
          e.filters = filters;
          e.decided_by = ci == 0 && !last_resort ? decided_by : "fallback";
          e.shrink = shrink_index_ + 1;
          record(std::move(e));
        }
        ++shrink_index_;
        const std::size_t before = rules_applied_;
        std::optional<Snapshot> saved;
        if (backtrack && !last_resort) saved = save();
        const auto failure = shrink(loops[static_cast<std::size_t>(c.loop)], c.side);
        if (!failure) {
          ++stats_.shrinks;
          progressed = true;
          break;
        }
        ++stats_.failed_shrinks;
        if (tracing()) {
          TraceEvent e;
          e.kind = TraceEvent::Kind::ShrinkFailed;
          e.step = rules_applied_;
          e.reason = *failure + (saved ? " (undone)" : "");
          e.shrink = shrink_index_;
          record(std::move(e));
        }
        if (failures.size() < 2000) {
          failures +=
              "\n  loop " + std::to_string(c.loop) + " side " + "AB"[c.side] + ": " + *failure;
        }
        if (saved) {
          restore(std::move(*saved));
          ++stats_.rolled_back_shrinks;
          continue;
        }
        if (rules_applied_ != before) {
          progressed = true;  // the front changed: select again
          break;
        }
      }
    }
    if (!progressed) {
      throw WeaveError("weave: every (loop, side) is blocked with " +
                       std::to_string(front_.num_faces()) + " front faces left and " +
                       std::to_string(hexes_.size()) + " hexes built:" + failures);
    }
    seam_fixpoint();
  }

  // Assemble the result: canonical node ids, input nodes unchanged, interior nodes compacted
  // in order of creation.
  WeaveResult result;
  result.num_input_nodes = front_.num_input_nodes();
  std::vector<NodeId> renumber(front_.num_nodes(), NodeId::invalid());
  std::size_t next = front_.num_input_nodes();
  for (std::size_t n = 0; n < front_.num_input_nodes(); ++n) renumber[n] = NodeId(n);
  for (std::size_t n = front_.num_input_nodes(); n < front_.num_nodes(); ++n)
    if (front_.find(NodeId(n)) == NodeId(n)) renumber[n] = NodeId(next++);
  result.complex.num_nodes = next;
  result.complex.hexes.reserve(hexes_.size());
  for (const stc::Hex& h : hexes_) {
    stc::Hex out{};
    for (std::size_t i = 0; i < 8; ++i) out[i] = renumber[front_.find(h[i]).index()];
    result.complex.hexes.push_back(out);
  }
  result.dual = std::move(dual_);
  result.hex_shrink = std::move(hex_shrink_);
  result.hex_rule = std::move(hex_rule_);
  result.stats = stats_;
  result.trace = std::move(trace_);
  return result;
}

}  // namespace

WeaveResult weave(const stc::QuadSurface& surface, const WeaveOptions& options,
                  const std::vector<std::array<double, 4>>& side_angles) {
  Weaver weaver(surface, options, side_angles);
  return weaver.run();
}

}  // namespace stcweave::weave
