// The per-selection face table (weave/src/select/face_table.hpp) against the front it copies:
// every neighbour, edge angle, face's nodes and incidence list read from the table must be
// what `Front::across`, `edge_angle`, `Front::face` and `Front::faces_at` give, also on a
// front with dead slots, reused slots and open edges. And the extended properties from one
// flood per loop (select/one_flood.hpp) against both sides flooded, at every front of a weave.

#include "select/face_table.hpp"

#include "select/one_flood.hpp"

#include <gtest/gtest.h>

#include <limits>

#include <string>
#include <vector>

#include "stcweave/weave/front.hpp"
#include "stcweave/weave/kernel.hpp"
#include "stcweave/weave/rules.hpp"
#include "stcweave/weave/select.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

void expect_table_of(const Front& front, const std::string& what) {
  const FaceTable t = face_table(front);
  const FaceTable bare = face_table(front, false);
  EXPECT_TRUE(bare.across.empty() && bare.angle.empty()) << what;
  ASSERT_EQ(t.across.size(), 4 * front.face_capacity()) << what;
  for (std::size_t fi = 0; fi < front.face_capacity(); ++fi) {
    const auto f = static_cast<FaceIndex>(fi);
    if (!front.is_alive(f)) continue;
    EXPECT_EQ(t.nodes_of(f), front.face(f).nodes) << what << ", face " << f;
    EXPECT_EQ(bare.nodes_of(f), front.face(f).nodes) << what << ", face " << f;
    for (int k = 0; k < 4; ++k) {
      const FaceSide g = front.across(f, k);
      EXPECT_EQ(t.across_of(f, k).face, g.face) << what << ", face " << f << " side " << k;
      EXPECT_EQ(t.across_of(f, k).index, g.index) << what << ", face " << f << " side " << k;
      // bit for bit: the properties compare these with thresholds
      EXPECT_EQ(t.angle_of(f, k), edge_angle(front, f, k)) << what << ", face " << f;
    }
  }
  for (std::size_t v = 0; v < front.num_nodes(); ++v) {
    const NodeId n(v);
    const auto span = t.faces_at(n);
    const std::vector<FaceIndex> copy(span.begin(), span.end());
    EXPECT_EQ(copy, front.faces_at(n)) << what << ", " << n.str();
    const auto bare_span = bare.faces_at(n);
    EXPECT_EQ(std::vector<FaceIndex>(bare_span.begin(), bare_span.end()), front.faces_at(n))
        << what << ", " << n.str();
  }
}

TEST(FaceTable, CopiesTheFrontOfABoxWithMixedAngles) {
  const auto box = test::box_surface(3, 2, 2);
  Front front(box.surface);
  // convex, non-convex and flat carried angles, so that every branch of the combination runs
  for (std::size_t f = 0; f < front.face_capacity(); ++f) {
    const auto x = static_cast<float>(f % 7);
    front.set_side_angles(static_cast<FaceIndex>(f),
                          {90.0F + x, 270.0F - x, 180.0F, 150.0F + 20.0F * x});
  }
  expect_table_of(front, "box 3x2x2");
}

TEST(FaceTable, FollowsDeadAndReusedSlotsAndOpenEdges) {
  const auto box = test::box_surface(2, 2, 2);
  Front front(box.surface);
  const stc::Quad gone = front.face(3).nodes;
  front.remove_face(3);  // four open edges, a dead slot
  expect_table_of(front, "one face removed");
  const NodeId extra = front.new_node();
  // the slot is reused by a face on a new node (the front stays open around it)
  const FaceIndex f =
      front.add_face({gone[0], gone[1], gone[2], extra}, FaceOwner{FaceOwner::Kind::Hex, 0, 2}, 1,
                     {100.0F, 200.0F, 180.0F, 180.0F});
  EXPECT_EQ(f, 3);
  expect_table_of(front, "slot reused");
  EXPECT_EQ(face_table(front).across_of(f, 2).face, kNoFace) << "the edge to the new node is open";
}

// ---------------------------------------------------------------------------------------
// one flood per loop (select/one_flood.hpp) against both sides flooded

std::string differences(const TraceCandidate& a, const TraceCandidate& b) {
  std::string out;
  const auto field = [&](const char* name, auto x, auto y) {
    if (x != y) out += std::string(" ") + name + " " + std::to_string(x) + "/" + std::to_string(y);
  };
  field("side", a.side, b.side);
  field("length", a.length, b.length);
  field("strictly_on_side", a.strictly_on_side, b.strictly_on_side);
  field("on_strip", a.on_strip, b.on_strip);
  field("weight", a.weight, b.weight);
  field("self_intersecting", a.self_intersecting, b.self_intersecting);
  field("faces_collapsed", a.faces_collapsed, b.faces_collapsed);
  field("depth", a.depth, b.depth);
  field("crossed_sharp", a.crossed_sharp, b.crossed_sharp);
  field("side_sharp", a.side_sharp, b.side_sharp);
  field("nonconvex_on_side", a.nonconvex_on_side, b.nonconvex_on_side);
  return out;
}

struct OneFloodCount {
  std::size_t one = 0;      // loops whose properties came from one flood
  std::size_t both = 0;     // loops left to the two floods
  std::size_t kept = 0;     // loops whose flooded side came from the previous selections
  std::size_t stopped = 0;  // sides `faces_collapsed_at_least` stopped at its limit
};

/// `faces_collapsed_at_least` on `strip` against its exact faces collapsed (`ref`), at limits
/// below, at and above them: exact within the limit, the limit + 1 above it, 0 for a side not
/// asked for.
void expect_bounds_of(const Front& front, const FaceTable& table, const Strip& strip,
                      const std::array<TraceCandidate, 2>& ref, const std::string& what,
                      OneFloodCount& count) {
  Marks nodes, faces, faces2;
  const std::size_t low = std::min(ref[0].faces_collapsed, ref[1].faces_collapsed);
  const std::size_t high = std::max(ref[0].faces_collapsed, ref[1].faces_collapsed);
  for (const std::size_t limit : {std::size_t{0}, strip.size(), low - 1, low, high - 1, high,
                                  high + 7, std::numeric_limits<std::size_t>::max()}) {
    for (const unsigned sides : {1U, 2U, 3U}) {
      const auto got =
          faces_collapsed_at_least(front, table, strip, sides, limit, nodes, faces, faces2);
      for (std::size_t d = 0; d < 2; ++d) {
        const std::string where = what + ", limit " + std::to_string(limit) + ", sides " +
                                  std::to_string(sides) + ", side " + "AB"[d];
        const std::size_t exact = ref[d].faces_collapsed;
        if ((sides & (1U << d)) == 0U) {
          EXPECT_EQ(got[d], 0U) << where;
        } else if (exact <= limit) {
          EXPECT_EQ(got[d], exact) << where;
        } else {
          EXPECT_EQ(got[d], limit + 1) << where;
          if (limit >= strip.size()) ++count.stopped;  // stopped inside the flood
        }
      }
    }
  }
}

/// Shrinks `steps` loops of `surface`'s front (side angles mixed per face and side, so that
/// the non-convex counts are not all zero; depths come from the shrinks): at every front, each
/// loop's one-flood properties, when given, and `loop_candidates`'s must be those of
/// `extended_properties` field for field, also those of sides kept from earlier fronts.
OneFloodCount expect_one_flood_exact(const stc::QuadSurface& surface, std::size_t steps,
                                     const std::string& what) {
  WeaveOptions options;
  options.rules = RuleSet::Extended;
  WeaveState state(surface);
  for (std::size_t f = 0; f < state.front.face_capacity(); ++f) {
    const auto x = static_cast<float>(f % 5);
    state.front.set_side_angles(static_cast<FaceIndex>(f),
                                {90.0F + 40.0F * x, 270.0F - 30.0F * x, 185.0F, 200.0F - x});
  }
  WeaveContext ctx(options, nullptr, 1000000);
  const ExtendedParameters& par = options.extended;
  Marks nodes, faces, faces2;
  OneFloodCount count;
  SideCache cache;
  for (std::size_t step = 0; step < steps && state.front.num_faces() > 0; ++step) {
    const Front& front = state.front;
    const FrontLoops loops = front_loops(front);
    const FrontComponents comps = front_components(front, nodes);
    const FaceTable table = face_table(front);
    {
      // The loops and components read from the table are the front's own, numbered alike.
      const FrontLoops from_table = front_loops(front, table);
      EXPECT_EQ(from_table.strips, loops.strips) << what << ", step " << step;
      EXPECT_EQ(from_table.loop_of, loops.loop_of) << what << ", step " << step;
      const FrontComponents comps_from_table = front_components(front, table, nodes);
      EXPECT_EQ(comps_from_table.component_of, comps.component_of) << what << ", step " << step;
      EXPECT_EQ(comps_from_table.size, comps.size) << what << ", step " << step;
    }
    ComponentTotals totals = component_totals(front, table, comps, par.flat);
    cache.begin(front, table);
    const std::vector<TraceCandidate> all =
        loop_candidates(front, loops, comps, true, par, nodes, faces, faces2);
    EXPECT_EQ(all.size(), 2 * loops.strips.size()) << what;
    for (std::size_t l = 0; l < loops.strips.size(); ++l) {
      const Strip& strip = loops.strips[l];
      const auto ref = extended_properties(front, strip, comps, par, nodes, faces, faces2);
      const auto one = one_flood_properties(front, table, strip, comps, totals, par, nodes, faces,
                                            faces2, &cache);
      ++(one ? count.one : count.both);
      if (!ref[0].self_intersecting) {
        expect_bounds_of(front, table, strip, ref,
                         what + ", step " + std::to_string(step) + ", loop " + std::to_string(l),
                         count);
      }
      for (std::size_t d = 0; d < 2; ++d) {
        const std::string where = what + ", step " + std::to_string(step) + ", loop " +
                                  std::to_string(l) + " side " + "AB"[d];
        if (one) EXPECT_EQ(differences((*one)[d], ref[d]), "") << where << " (one flood)";
        if (2 * l + d < all.size())
          EXPECT_EQ(differences(all[2 * l + d], ref[d]), "") << where << " (loop_candidates)";
      }
    }
    cache.end();
    if (step + 1 == steps) break;
    // the next front: the first candidate that shrinks, then seams
    bool shrunk = false;
    for (std::size_t i = 0; i < all.size() && !shrunk; ++i) {
      const std::size_t before = ctx.rules_applied;
      WeaveState saved = state;
      if (!shrink(state, ctx, loops.strips[static_cast<std::size_t>(all[i].loop)],
                  static_cast<stc::LoopSide>(all[i].side))) {
        shrunk = true;
      } else if (ctx.rules_applied != before) {
        state = std::move(saved);
      }
    }
    if (!shrunk) break;
    seam_fixpoint(state, ctx);
  }
  count.kept = cache.hits;
  return count;
}

TEST(OneFlood, MatchesBothFloodsOnBoxesAndAnLBlock) {
  const OneFloodCount box = expect_one_flood_exact(test::box_surface(4, 3, 5).surface, 12, "box");
  EXPECT_GT(box.one, 0U) << "a box's loops separate it: one flood each";
  EXPECT_GT(box.kept, 0U) << "loops away from a shrink keep their flooded side";
  EXPECT_GT(box.stopped, 0U) << "the bounded floods stopped somewhere";
  const OneFloodCount lblock =
      expect_one_flood_exact(test::voxel_surface(test::lblock_cells()).surface, 12, "lblock");
  EXPECT_GT(lblock.one, 0U);
  const OneFloodCount two = expect_one_flood_exact(
      test::merged_surfaces({test::box_surface(2, 2, 3),
                             test::translated(test::box_surface(3, 2, 2), {10.0, 0.0, 0.0})})
          .surface,
      10, "two boxes");
  EXPECT_GT(two.one, 0U) << "two components, each with its own totals";
}

TEST(OneFlood, LeavesLoopsAroundAHandleToBothFloods) {
  const OneFloodCount torus = expect_one_flood_exact(test::torus_surface(8, 4).surface, 1, "torus");
  EXPECT_GT(torus.both, 0U) << "a loop around the torus does not separate its front";
}

}  // namespace
}  // namespace stcweave::weave
