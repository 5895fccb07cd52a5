#pragma once
/// \file
/// The front of the weave: the not-yet-filled boundary of the region still to mesh, a closed
/// oriented quad surface made of input quads and faces of created hexes.
///
/// Representation (see DESIGN.md "Data structures"): every front face stores its four
/// corner nodes in order (oriented outward from the region still to mesh), its owner (the
/// input quad or the hex face behind it, i.e. its whisker) and its depth. Every node stores
/// the list of its incident front faces. This is the dual 4-valent map of the front in
/// another guise: the neighbour of face F across its side i is the unique face holding the
/// directed edge (F[i+1], F[i]), found among the faces of F[i+1]; the rotation around a node
/// is recovered the same way. Node identities merge (seams) through a union-find whose
/// representative is always an input node when one of the two is. Face slots are reused
/// last-freed-first, so a run is deterministic.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "stcweave/stc/ids.hpp"
#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::weave {

/// Index of a front face slot (stable while the face is alive).
using FaceIndex = std::int32_t;
inline constexpr FaceIndex kNoFace = -1;

/// What stands behind a front face: an input quad, or face `local_face` of a hex.
struct FaceOwner {
  enum class Kind : std::uint8_t { Input, Hex };
  Kind kind = Kind::Input;
  std::int32_t id = -1;         ///< QuadId value (Input) or HexId value (Hex)
  std::int8_t local_face = -1;  ///< 0..5 for a hex face (kHexFaces order)

  [[nodiscard]] bool is_input() const { return kind == Kind::Input; }
  [[nodiscard]] bool is_hex() const { return kind == Kind::Hex; }
  [[nodiscard]] std::string str() const;
};

/// One face of the front.
struct FrontFace {
  stc::Quad nodes{};  ///< canonical node ids, outward from the region still to mesh
  FaceOwner owner;
  std::int32_t depth = 0;  ///< seed sect. 6: 0 on the input, i+1 opposite an i-face, -1 else
  /// Per side, the dihedral angle (degrees, through the region still to mesh) of its edge as
  /// this face carries it: the input's angle, or the one carried over from the opposite face
  /// of the hex that created this face (seed sect. 6); 180 (flat) when nothing was carried.
  std::array<float, 4> side_angle{180.0F, 180.0F, 180.0F, 180.0F};
  bool alive = false;
};

/// A position on a face: corner/side `index` (0..3) of face `face`.
struct FaceSide {
  FaceIndex face = kNoFace;
  int index = -1;
};

class Front {
 public:
  /// The front of a closed, consistently oriented, edge- and vertex-manifold quad surface
  /// (oriented outward). Node ids 0..num_nodes-1 of the surface are the input nodes.
  /// \throw InvalidInput when a quad has a node id out of range or a repeated node.
  explicit Front(const stc::QuadSurface& surface);

  // ---- nodes ----
  [[nodiscard]] std::size_t num_nodes() const { return parent_.size(); }
  [[nodiscard]] std::size_t num_input_nodes() const { return num_input_nodes_; }
  [[nodiscard]] bool is_input_node(NodeId n) const { return n.index() < num_input_nodes_; }
  /// The canonical id of `n` after the merges so far.
  [[nodiscard]] NodeId find(NodeId n) const;
  /// A fresh (interior) node.
  NodeId new_node();
  /// Number of front faces at node `v` (0 when `v` is no longer on the front).
  [[nodiscard]] std::size_t valence(NodeId v) const { return incident_[v.index()].size(); }
  [[nodiscard]] const std::vector<FaceIndex>& faces_at(NodeId v) const {
    return incident_[v.index()];
  }
  /// Merges node `gone` into node `keep` (both canonical, distinct): every face of `gone`
  /// now uses `keep`. The caller guarantees the result stays a valid front (after gluing
  /// coincident faces).
  void merge_nodes(NodeId keep, NodeId gone);

  // ---- faces ----
  [[nodiscard]] std::size_t num_faces() const { return alive_; }
  [[nodiscard]] std::size_t face_capacity() const { return faces_.size(); }
  [[nodiscard]] const FrontFace& face(FaceIndex f) const {
    return faces_[static_cast<std::size_t>(f)];
  }
  [[nodiscard]] bool is_alive(FaceIndex f) const {
    return f >= 0 && static_cast<std::size_t>(f) < faces_.size() && face(f).alive;
  }
  FaceIndex add_face(const stc::Quad& nodes, FaceOwner owner, std::int32_t depth,
                     const std::array<float, 4>& side_angle = {180.0F, 180.0F, 180.0F, 180.0F});
  /// Sets the carried angles of an input face (used once, at the start).
  void set_side_angles(FaceIndex f, const std::array<float, 4>& side_angle) {
    faces_[static_cast<std::size_t>(f)].side_angle = side_angle;
  }
  void remove_face(FaceIndex f);
  /// Corner of `f` holding node `v`, or -1.
  [[nodiscard]] int corner_of(FaceIndex f, NodeId v) const;
  /// The face and side holding the directed edge from -> to, or {kNoFace, -1}.
  [[nodiscard]] FaceSide find_edge(NodeId from, NodeId to) const;
  /// The face across side `side` of `f` and the index of the same edge in it. O(1) when the
  /// answer is the one given for this side before (kept as a checked hint), else a search of
  /// the faces at one node.
  [[nodiscard]] FaceSide across(FaceIndex f, int side) const;

  /// An undo point: `roll_back` returns the front to it exactly. The flat arrays (faces,
  /// free slots, union-find) are copied; the incidence lists are journaled while a checkpoint
  /// is open, so that taking one costs O(faces + nodes) copies and no allocation per node.
  /// Checkpoints nest; each is rolled back or released, innermost first.
  struct Checkpoint {
    std::vector<FrontFace> faces;
    std::vector<FaceIndex> free;
    std::vector<NodeId> parent;
    std::size_t alive = 0;
    std::size_t journal = 0;
  };
  [[nodiscard]] Checkpoint checkpoint();
  /// Undoes every change since `c` was taken. \pre `c` is the innermost open checkpoint.
  void roll_back(Checkpoint&& c);
  /// Keeps the changes since `c` and closes it. \pre `c` is the innermost open checkpoint.
  void release(Checkpoint&& c);

  /// The face slots and nodes changed since it was attached: every face added or removed (with
  /// its nodes) and every node merge (both nodes and the faces renamed). A rolled-back change
  /// stays listed. Lets a caller that keeps facts about a few faces (the strip of the loop
  /// being shrunk, rules/shrink.cpp) re-examine only what changed.
  struct ChangeLog {
    std::vector<FaceIndex> faces;
    std::vector<NodeId> nodes;
    void clear() {
      faces.clear();
      nodes.clear();
    }
  };
  /// Reports changes to `log` from now on (nullptr: to nowhere, the default). The caller keeps
  /// `log` alive while it is attached.
  void attach_change_log(ChangeLog* log) { change_log_ = log; }

  /// Checks that the front is a closed oriented 2-manifold quad surface: four distinct nodes
  /// per face, every directed edge once with its reverse present, incidence lists exact,
  /// every vertex link one cycle. Returns a description of the first violation.
  [[nodiscard]] std::optional<std::string> check_invariants() const;

 private:
  std::vector<FrontFace> faces_;
  std::vector<FaceIndex> free_;
  std::vector<std::vector<FaceIndex>> incident_;
  mutable std::vector<NodeId> parent_;
  std::size_t num_input_nodes_ = 0;
  std::size_t alive_ = 0;
  /// A change to an incidence list, journaled while a checkpoint is open.
  struct IncidenceChange {
    enum class Kind : std::uint8_t { Push, Erase, Merge };
    Kind kind = Kind::Push;
    std::uint32_t node = 0;    ///< the list changed (Merge: the kept node)
    std::uint32_t other = 0;   ///< Merge: the gone node
    std::uint32_t pos = 0;     ///< Erase: the position; Merge: the kept list's former size
    FaceIndex face = kNoFace;  ///< Erase: the face erased
  };
  std::vector<IncidenceChange> journal_;
  int open_checkpoints_ = 0;
  /// Per face slot and side, the last answer of `across`: a hint, checked before use (the
  /// face it names must be alive and hold the reversed edge at that index, which in a valid
  /// front only one face does), so it needs no upkeep when faces come and go, merges rename
  /// nodes or a checkpoint is rolled back.
  mutable std::vector<std::array<FaceSide, 4>> across_hint_;
  ChangeLog* change_log_ = nullptr;
  void log_face(FaceIndex f) {
    if (change_log_ == nullptr) return;
    change_log_->faces.push_back(f);
    for (NodeId n : faces_[static_cast<std::size_t>(f)].nodes) change_log_->nodes.push_back(n);
  }
};

}  // namespace stcweave::weave
