#pragma once
/// The extended properties of a loop that separates its front component, from one flood of
/// its smaller side (select/properties.cpp; docs/weave-loop-properties.md).
///
/// `extended_properties` floods both sides of every loop completely. A side's faces, depths
/// and non-convex edges are sums over its faces, and when the loop separates its component
/// the two sides and the strip are the whole component: one side is then the component's
/// totals (computed once per selection) minus the other side and the strip. The results are
/// exactly those of `extended_properties` (same counts, same least depth), only cheaper.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "face_table.hpp"
#include "stcweave/weave/select.hpp"

namespace stcweave::weave {

/// Per component of the front, what `extended_properties` reads over a whole side, summed
/// over every face of the component: the side of a loop that separates its component is then
/// the component minus the other side and the strip (`one_flood_properties`).
struct ComponentTotals {
  std::vector<std::size_t> faces;  ///< alive faces per component
  /// Per component, the face sides whose edge angle is above `flat`, each edge once: the side
  /// with no face across or across a face of a higher slot (the count of `extended_properties`
  /// with no strip).
  std::vector<std::size_t> nonconvex;
  /// Per component, its faces' positive depths and how many faces have each, ascending.
  std::vector<std::vector<std::pair<std::int32_t, std::size_t>>> depths;
  /// Scratch, indexed by depth (up to the front's greatest depth), zero between loops.
  std::vector<std::size_t> depth_count;
};

/// The greatest face depth `component_totals` indexes densely; a deeper front is weighed by
/// two floods per loop, as before.
constexpr std::int32_t kMaxDenseDepth = 1 << 20;

/// What the flood of the side a loop's one flood exhausted found (`one_flood_properties`).
struct FloodedSide {
  std::size_t side = 0;       ///< 0: side A, 1: side B
  std::size_t nodes = 0;      ///< nodes strictly on that side
  std::size_t faces = 0;      ///< faces on that side, the strip's not counted
  std::int32_t depth = 0;     ///< least positive depth of those faces, or 0
  std::size_t nonconvex = 0;  ///< non-convex edges of those faces, as `extended_properties`
  std::size_t plain = 0;      ///< the same counted with no strip (`ComponentTotals::nonconvex`)
  std::size_t to_strip = 0;   ///< non-convex sides across a strip face of a lower slot
  /// Positive depths of those faces and how many faces have each, ascending.
  std::vector<std::pair<std::int32_t, std::size_t>> depths;
};

/// Flooded sides kept from one selection to the next. A kept side is exact for a later front
/// when that loop's strip is the same sequence of (face slot, entry) and no face slot holding
/// one of the side's or the strip's nodes changed in between (its nodes, depth, neighbours or
/// edge angles): the flood would read the same faces. `begin` compares every face slot of the
/// front with the previous selection's and forgets every side a changed slot touches (all of
/// them when more than a quarter of the nodes are touched: another front, a rollback far back),
/// so the cache never changes a result, only the work: a shrink edits the strips it crosses and
/// the region around it, and the loops elsewhere keep their flooded side.
class SideCache {
 public:
  /// A new selection on `front` (`table` with angles).
  void begin(const Front& front, const FaceTable& table);
  /// The selection is over: forgets the loops it did not have.
  void end();
  /// The kept side of `strip`, or null.
  [[nodiscard]] const FloodedSide* find(const Strip& strip);
  /// Whether a side of `strip` is kept (`find` would find it), counting nothing.
  [[nodiscard]] bool contains(const Strip& strip) const;
  /// Keeps `side` for `strip`; `nodes`: the side's nodes and the strip's.
  void keep(const Strip& strip, const FloodedSide& side, std::span<const NodeId> nodes);

  std::size_t hits = 0;    ///< `find` calls that found a side
  std::size_t misses = 0;  ///< and those that did not

 private:
  struct Slot {
    bool alive = false;
    stc::Quad nodes{};
    std::int32_t depth = 0;
    std::array<FaceSide, 4> across{};
    std::array<double, 4> angle{};
  };
  struct Entry {
    Strip strip;
    FloodedSide side;
    std::vector<std::uint64_t> bits;  ///< the side's and the strip's nodes, one bit per node id
    bool used = false;
  };
  static bool same_across(const Slot& a, const Slot& b);
  static std::uint64_t key(const Strip& strip);
  std::vector<Slot> slots_;
  std::unordered_map<std::uint64_t, Entry> entries_;
};

/// The totals of every component of `front` (`table` with angles, `flat` the non-convex
/// threshold of `ExtendedParameters`).
[[nodiscard]] ComponentTotals component_totals(const Front& front, const FaceTable& table,
                                               const FrontComponents& components, double flat);

/// `extended_properties` for a loop that separates its component, with one side flooded:
/// the two sides are flooded one node at a time each until one is exhausted; that side's
/// properties are counted as `extended_properties` counts them, and the other side is the
/// component's totals minus that side and the strip. Nothing (the caller floods both sides)
/// when the loop crosses itself or the two floods touch: a face reached from one side that
/// holds a node of the other side's strip corners or its flood, or a face reached from both.
///
/// Why the rest is the other side: every strip node is a corner of the strip on side A or on
/// side B, and every non-strip face of the component is reached, through non-strip nodes,
/// from a face at a strip node; so every such face is reached by side A's full flood or side
/// B's. When the exhausted side's faces hold no node of the other side, no face is reached
/// from both (the first face of the other side's flood also reached from this side would
/// hold one of its corners, or a node it reached through a face this side reached first). A
/// non-strip face of the other side then has its neighbours on that side or on the strip.
///
/// With `cache`, the flooded side of a loop whose strip and side no edit has touched since the
/// selection that flooded it is taken from there instead of flooded again (`SideCache`).
[[nodiscard]] std::optional<std::array<TraceCandidate, 2>> one_flood_properties(
    const Front& front, const FaceTable& table, const Strip& strip,
    const FrontComponents& components, ComponentTotals& totals, const ExtendedParameters& par,
    Marks& nodes, Marks& faces, Marks& faces2, SideCache* cache = nullptr);

/// Lower bounds of the faces collapsed of the two sides of `strip`, a loop that does not
/// cross itself (index 0: side A, 1: side B): each side of `sides` (bit d for side d) is
/// flooded as `extended_properties` floods it, but only until its faces and the strip's are
/// more than `limit`. A side whose flood ended first gets its exact faces collapsed (at most
/// `limit`); a side stopped gets `limit + 1`, a side not asked for 0. The partial flood reads
/// a subset of the faces the full one reads, so each figure is at most the side's faces
/// collapsed: a side above a limit can be left out of a ranking by fewest faces without
/// flooding the rest of it (`CandidateSet::bound_faces`).
[[nodiscard]] std::array<std::size_t, 2> faces_collapsed_at_least(
    const Front& front, const FaceTable& table, const Strip& strip, unsigned sides,
    std::size_t limit, Marks& nodes, Marks& faces, Marks& faces2);

}  // namespace stcweave::weave
