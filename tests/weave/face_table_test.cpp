// The per-selection face table (weave/src/select/face_table.hpp) against the front it copies:
// every neighbour, edge angle, face's nodes and incidence list read from the table must be
// what `Front::across`, `edge_angle`, `Front::face` and `Front::faces_at` give, also on a
// front with dead slots, reused slots and open edges.

#include "select/face_table.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "stcweave/weave/front.hpp"
#include "stcweave/weave/rules.hpp"
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

}  // namespace
}  // namespace stcweave::weave
