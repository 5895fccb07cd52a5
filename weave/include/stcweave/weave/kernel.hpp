#pragma once
/// \file
/// The weave kernel: the values every rule works on, so that a rule is a free function of the
/// front and its context that a test can call on a hand-built front.
///
/// - `WeaveState` owns everything a rule changes: the front, the woven complex (hexes, their
///   dual links, the shrink that made each), the pending seam work and the counters. Copying
///   it is the undo of a shrink (backtracking) or of a refused fold (non-convexity seam).
/// - `WeaveContext` holds what a rule reads but never undoes: the options, the number of rules
///   applied, the shrink in progress, whether the geometric preconditions are lifted, the
///   observer that records the trace, and scratch marks.
/// - A rule returns a `RuleResult`: applied, or refused with the reason.
///
/// Loops and strips use stc's vocabulary (`stc::StripStep`, `stc::LoopSide`): a `Strip` is a
/// loop of the front, each step naming the front face slot it crosses (as a `QuadId`, since a
/// front face is a quad of the front surface) and the side it enters by. Side A of
/// DESIGN.md ("Sides of a loop") is `LoopSide::Left`, side B `LoopSide::Right`.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "stcweave/stc/ids.hpp"
#include "stcweave/stc/loops.hpp"
#include "stcweave/stc/quad_surface.hpp"
#include "stcweave/weave/front.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::weave {

/// Faces opposite each other in a hex (`stc::kHexFaces` order).
inline constexpr std::array<int, 6> kOppositeFace = {1, 0, 4, 5, 2, 3};

/// Node `i` of `q`, indices taken modulo 4 (negative ones too).
[[nodiscard]] inline NodeId quad_at(const stc::Quad& q, int i) {
  return q[static_cast<std::size_t>(((i % 4) + 4) % 4)];
}
/// `q` rotated to start at its corner `start`.
[[nodiscard]] inline stc::Quad quad_rotated(const stc::Quad& q, int start) {
  return {quad_at(q, start), quad_at(q, start + 1), quad_at(q, start + 2), quad_at(q, start + 3)};
}
/// The four nodes of `q` sorted (the key of a face regardless of orientation and rotation).
[[nodiscard]] std::array<NodeId, 4> quad_sorted(stc::Quad q);

/// A loop of the front: its passages in order of travel; `quad` is the front face slot.
using Strip = std::vector<stc::StripStep>;
/// The front face slot a strip step crosses.
[[nodiscard]] inline FaceIndex face_of(const stc::StripStep& s) {
  return s.quad.value();
}
/// 0 for side A (`LoopSide::Left`), 1 for side B.
[[nodiscard]] inline int side_index(stc::LoopSide d) {
  return static_cast<int>(d);
}
[[nodiscard]] inline stc::LoopSide other_side(stc::LoopSide d) {
  return d == stc::LoopSide::Left ? stc::LoopSide::Right : stc::LoopSide::Left;
}

/// The hexes woven so far, and what lies behind each of their faces.
struct WovenComplex {
  std::vector<stc::Hex> hexes;                ///< node ids as created (canonical: Front::find)
  std::vector<std::vector<HexId>> hexes_at;   ///< per canonical node, the hexes using it
  std::vector<std::array<DualLink, 6>> dual;  ///< per hex and local face, its neighbour
  std::vector<std::int32_t> hex_shrink;       ///< per hex, the shrink that made it
  std::vector<std::string> hex_rule;          ///< per hex, the rule that made it
  std::vector<NodeId> hex_node;               ///< per hex, the node its rule was applied at
};

/// Everything a rule changes, owned by one value: a copy is a complete undo point.
struct WeaveState {
  /// The front of `surface` with nothing woven; input quad q is front face q.
  /// \throw InvalidInput as `Front::Front`.
  explicit WeaveState(const stc::QuadSurface& surface);

  Front front;
  WovenComplex woven;
  /// Nodes whose valence may have dropped to 2 since the last seam pass (a stack).
  std::vector<NodeId> seam_work;
  /// Valence-2 nodes whose seam was refused; retried at the next seam pass.
  std::vector<NodeId> blocked_seams;
  WeaveStats stats;

  /// A fresh interior node.
  NodeId new_node();
  /// Merges node `gone` into `keep` on the front and in the node -> hexes lists.
  void merge_nodes(NodeId keep, NodeId gone);
  /// Queues the nodes of front face `f` for the next seam pass.
  void push_nodes_of(FaceIndex f);
  /// Records in the woven STC that the faces behind `a` and `b` are glued.
  void link(const FaceOwner& a, const FaceOwner& b);
  /// True when canonical nodes `x` and `y` are nodes of one hex.
  [[nodiscard]] bool share_hex(NodeId x, NodeId y) const;
  /// Number of nodes hexes `a` and `b` share once node `gone` is read as `keep`.
  [[nodiscard]] std::size_t common_nodes(HexId a, HexId b, NodeId gone, NodeId keep) const;
  /// Why merging `x` and `y` (as `gone` into `keep`) would break the complex, if it would:
  /// two hexes (one at x, one at y) sharing more than one face, four nodes that are not a
  /// face of both, or a face one of whose copies is already glued.
  [[nodiscard]] std::optional<std::string> merge_conflict(NodeId x, NodeId y, NodeId keep,
                                                          NodeId gone) const;
  /// Why a new hex would break the complex through its contacts with the woven hexes, if it
  /// would: it would share more than four nodes with a woven hex, or four that are not the
  /// face it is glued to (two such hexes cannot both have a positive Jacobian everywhere:
  /// `stc::shared_nodes_not_a_face`). `nodes` are the new hex's nodes already on the front
  /// (canonical; its fresh nodes left out), `used` the front faces it is glued through. Two
  /// or three shared nodes are accepted.
  [[nodiscard]] std::optional<std::string> contact_conflict(std::span<const NodeId> nodes,
                                                            std::span<const FaceIndex> used) const;
  /// Goes back to `saved` (an earlier copy of this state), keeping the counters of the
  /// selection process (selections, failed and rolled-back shrinks) as they are now.
  void roll_back_to(WeaveState&& saved);

  /// A cheap undo point (what backtracking takes before every shrink): the front's
  /// checkpoint, the sizes of the woven complex's arrays, and the journal position of the
  /// changes to existing entries (dual links, per-node hex lists).
  struct Checkpoint {
    Front::Checkpoint front;
    std::size_t hexes = 0;
    std::size_t nodes = 0;
    std::size_t journal = 0;
    std::vector<NodeId> seam_work;
    std::vector<NodeId> blocked_seams;
    WeaveStats stats;
  };
  [[nodiscard]] Checkpoint checkpoint();
  /// Undoes every change since `c`, as `roll_back_to` does (the selection counters stay).
  /// \pre `c` is the innermost open checkpoint.
  void roll_back(Checkpoint&& c);
  /// Keeps the changes since `c`. \pre `c` is the innermost open checkpoint.
  void release(Checkpoint&& c);
  /// Adds hex `h` to the hex list of node `n`.
  void add_hex_at(NodeId n, HexId h);

 private:
  /// A change to an existing entry of the woven complex, journaled while a checkpoint is open.
  struct WovenChange {
    enum class Kind : std::uint8_t { Dual, HexAtPush, HexAtMerge };
    Kind kind = Kind::Dual;
    std::uint32_t a = 0;  ///< Dual: hex; HexAtPush: node; HexAtMerge: kept node
    std::uint32_t b = 0;  ///< Dual: local face; HexAtMerge: gone node
    std::uint32_t c = 0;  ///< HexAtMerge: the kept list's former size
    DualLink link;        ///< Dual: the former link
  };
  std::vector<WovenChange> journal_;
  int open_checkpoints_ = 0;
  /// `merge_conflict`'s scratch: the sorted node images of the hexes at one node, kept
  /// between calls so that the check before every seam allocates nothing.
  mutable std::vector<std::array<NodeId, 8>> merge_images_;
  /// `contact_conflict`'s scratch: the woven hexes at the new hex's nodes, one entry per
  /// shared node.
  mutable std::vector<HexId> contact_hexes_;
};

/// Scratch marks over nodes or faces: a fresh stamp unmarks every entry in O(1).
class Marks {
 public:
  /// A new stamp, with room for `size` entries.
  std::uint32_t fresh(std::size_t size);
  [[nodiscard]] bool is(std::size_t i, std::uint32_t stamp) const {
    return i < marks_.size() && marks_[i] == stamp;
  }
  [[nodiscard]] std::uint32_t get(std::size_t i) const { return i < marks_.size() ? marks_[i] : 0; }
  /// \pre `i` is below the size given to the last `fresh`.
  void set(std::size_t i, std::uint32_t stamp) { marks_[i] = stamp; }

 private:
  std::vector<std::uint32_t> marks_;
  std::uint32_t stamp_ = 0;
};

/// A set of front faces held by one stamp of a `Marks` array.
struct FaceSet {
  const Marks* marks = nullptr;
  std::uint32_t stamp = 0;
  [[nodiscard]] bool contains(FaceIndex f) const {
    return marks->is(static_cast<std::size_t>(f), stamp);
  }
};

/// The faces of `strip` as a `FaceSet` in `marks` (a fresh stamp).
[[nodiscard]] FaceSet mark_strip_faces(Marks& marks, const Front& front, const Strip& strip);

/// Watches the driver: one call per loop selection, rule application and failed shrink. The
/// trace (`WeaveOptions::trace`, `on_trace`) is one such observer; a researcher can add one.
class WeaveObserver {
 public:
  virtual ~WeaveObserver() = default;
  /// A (loop, side) is about to be shrunk: `candidates` as ranked, `chosen` indexes them.
  virtual void on_selection(std::size_t step, std::int32_t shrink,
                            std::span<const TraceCandidate> candidates, std::size_t chosen,
                            const std::string& reason, std::span<const std::string> filters,
                            const std::string& decided_by) = 0;
  /// A rule was applied at `node` on the front faces whose owners are `faces`.
  virtual void on_rule(std::size_t step, std::int32_t shrink, const char* rule, NodeId node,
                       std::span<const FaceOwner> faces, HexId hex) = 0;
  /// A shrink (or a parallel merging) ended blocked, or was refused.
  virtual void on_shrink_failed(std::size_t step, std::int32_t shrink,
                                const std::string& reason) = 0;
  /// False when `on_selection` reads only `candidates[chosen]`: the driver may then leave
  /// the other candidates partly computed (their order and properties unspecified).
  [[nodiscard]] virtual bool reads_every_candidate() const { return true; }
};

/// What a rule reads but never undoes.
class WeaveContext {
 public:
  /// \param observer may be null (nothing watches).
  WeaveContext(const WeaveOptions& options, WeaveObserver* observer, std::size_t max_rules);

  const WeaveOptions& options;
  WeaveObserver* observer = nullptr;
  std::size_t rules_applied = 0;
  std::size_t max_rules = 0;
  /// Index of the loop shrink in progress (-1 before the first).
  std::int32_t shrink_index = -1;
  /// The geometric preconditions are lifted for the current shrink step.
  bool relax_geometry = false;
  /// Scratch: node marks, and two independent face mark arrays.
  Marks nodes;
  Marks faces;
  Marks faces2;

  [[nodiscard]] bool extended() const { return options.rules == RuleSet::Extended; }
  [[nodiscard]] const ExtendedParameters& parameters() const { return options.extended; }
  /// Every rule ends here: counts it, tells the observer, checks the front (`check`), reports
  /// progress, and enforces `max_rules`.
  /// \throw InternalError when `check` finds the front broken; WeaveError past `max_rules`.
  void after_rule(const WeaveState& state, const char* rule, NodeId node,
                  std::span<const FaceOwner> owners, HexId hex);
};

/// What a rule did: applied, or refused and why.
struct RuleResult {
  bool applied = false;
  std::string why;  ///< the refusal, empty when applied
  HexId hex;        ///< the hex it made, if any

  [[nodiscard]] static RuleResult refused(std::string why) { return {false, std::move(why), {}}; }
  [[nodiscard]] static RuleResult done(HexId hex = HexId::invalid()) { return {true, {}, hex}; }
  explicit operator bool() const { return applied; }
};

/// Puts a new hex on the front: the front faces `used` (each a face of `hex`) leave the front
/// and are linked to the hex, its other faces join the front reversed, carrying depth and
/// angles (propagation, seed sect. 6; see `propagate`). Calls `after_rule`.
/// \throw InternalError when a face of `used` is not a face of `hex`.
HexId make_hex(WeaveState& state, WeaveContext& ctx, const stc::Hex& hex,
               std::span<const FaceIndex> used, const char* rule, NodeId at_node);

}  // namespace stcweave::weave
