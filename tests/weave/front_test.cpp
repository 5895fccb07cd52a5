#include "stcweave/weave/front.hpp"

#include <gtest/gtest.h>

#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

TEST(Front, CubeIsAValidFront) {
  const auto cube = test::box_surface(1, 1, 1);
  const Front front(cube.surface);
  EXPECT_EQ(front.num_faces(), 6u);
  EXPECT_EQ(front.num_input_nodes(), 8u);
  EXPECT_FALSE(front.check_invariants().has_value());
  for (std::size_t n = 0; n < 8; ++n) EXPECT_EQ(front.valence(NodeId(n)), 3u);
}

TEST(Front, AcrossFindsTheTwinSide) {
  const auto box = test::box_surface(2, 1, 1);
  const Front front(box.surface);
  for (FaceIndex f = 0; f < static_cast<FaceIndex>(front.face_capacity()); ++f) {
    for (int side = 0; side < 4; ++side) {
      const FaceSide twin = front.across(f, side);
      ASSERT_NE(twin.face, kNoFace);
      const FaceSide back = front.across(twin.face, twin.index);
      EXPECT_EQ(back.face, f);
      EXPECT_EQ(back.index, side);
    }
  }
}

/// Every alive face side: `across` gives what a search of the faces at the edge's first node
/// gives (the remembered answers are only hints).
void expect_across_is_the_search(const Front& front) {
  for (FaceIndex f = 0; f < static_cast<FaceIndex>(front.face_capacity()); ++f) {
    if (!front.is_alive(f)) continue;
    const stc::Quad& n = front.face(f).nodes;
    for (int side = 0; side < 4; ++side) {
      const FaceSide got = front.across(f, side);
      const FaceSide want = front.find_edge(n[static_cast<std::size_t>((side + 1) % 4)],
                                            n[static_cast<std::size_t>(side)]);
      EXPECT_EQ(got.face, want.face) << "face " << f << " side " << side;
      EXPECT_EQ(got.index, want.index) << "face " << f << " side " << side;
    }
  }
}

TEST(Front, AcrossStaysRightWhenFacesChangeUnderIt) {
  // Ask every side first (so every answer is remembered), then reuse a slot for the same
  // quad started at another corner (every side index of it and of its neighbours' answers
  // moves), merge a node, and roll a checkpoint back: each time the answers follow.
  const auto box = test::box_surface(2, 1, 1);
  Front front(box.surface);
  expect_across_is_the_search(front);
  const stc::Quad q = front.face(2).nodes;
  const FaceOwner owner = front.face(2).owner;
  Front::Checkpoint c = front.checkpoint();
  front.remove_face(2);
  EXPECT_EQ(front.add_face({q[1], q[2], q[3], q[0]}, owner, 0), 2);
  EXPECT_FALSE(front.check_invariants().has_value());
  expect_across_is_the_search(front);
  const NodeId a = front.new_node();
  const stc::Quad r = front.face(5).nodes;
  front.remove_face(5);
  const FaceIndex g = front.add_face({r[0], r[1], r[2], a}, owner, 0);
  front.merge_nodes(r[3], a);
  EXPECT_FALSE(front.check_invariants().has_value());
  expect_across_is_the_search(front);
  EXPECT_EQ(front.across(g, 2).face, front.find_edge(r[3], r[2]).face);
  front.roll_back(std::move(c));
  EXPECT_FALSE(front.check_invariants().has_value());
  EXPECT_EQ(front.face(2).nodes, q);
  expect_across_is_the_search(front);
}

TEST(Front, RemovingAFaceOpensTheFront) {
  const auto cube = test::box_surface(1, 1, 1);
  Front front(cube.surface);
  front.remove_face(0);
  const auto err = front.check_invariants();
  ASSERT_TRUE(err.has_value());
  EXPECT_NE(err->find("open"), std::string::npos) << *err;
}

TEST(Front, DegenerateQuadIsRejectedWithItsId) {
  stc::QuadSurface s;
  s.num_nodes = 4;
  s.quads.push_back({NodeId(0), NodeId(1), NodeId(1), NodeId(3)});
  try {
    const Front front(s);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("q0"), std::string::npos) << e.what();
  }
}

TEST(Front, NodeOutOfRangeIsRejected) {
  stc::QuadSurface s;
  s.num_nodes = 3;
  s.quads.push_back({NodeId(0), NodeId(1), NodeId(2), NodeId(7)});
  EXPECT_THROW(Front{s}, InvalidInput);
}

TEST(Front, MergeRewritesFacesAndUnionFind) {
  const auto box = test::box_surface(1, 1, 1);
  Front front(box.surface);
  const NodeId a = front.new_node();
  const NodeId b = front.new_node();
  front.merge_nodes(a, b);
  EXPECT_EQ(front.find(b), a);
  EXPECT_EQ(front.find(a), a);
  EXPECT_FALSE(front.is_input_node(a));
}

TEST(Front, ChangeLogListsTheFacesAndNodesOfEveryChange) {
  const auto cube = test::box_surface(1, 1, 1);
  Front front(cube.surface);
  Front::ChangeLog log;
  front.remove_face(0);  // before the log is attached: not listed
  front.attach_change_log(&log);
  const stc::Quad q = front.face(3).nodes;
  front.remove_face(3);
  ASSERT_EQ(log.faces, std::vector<FaceIndex>{3});
  EXPECT_EQ(log.nodes, std::vector<NodeId>(q.begin(), q.end()));
  log.clear();
  const FaceIndex f = front.add_face(q, FaceOwner{}, 0);
  EXPECT_EQ(log.faces, std::vector<FaceIndex>{f});
  EXPECT_EQ(log.nodes.size(), 4u);
  log.clear();
  // A merge lists the faces renamed (with their nodes after it) and the node gone.
  const NodeId keep = q[0];
  const NodeId gone = front.new_node();
  front.add_face({gone, q[1], q[2], q[3]}, FaceOwner{}, 0);
  log.clear();
  front.merge_nodes(keep, gone);
  ASSERT_EQ(log.faces.size(), 1u);
  EXPECT_EQ(std::count(log.nodes.begin(), log.nodes.end(), keep), 1);
  EXPECT_EQ(log.nodes.back(), gone);
  front.attach_change_log(nullptr);
  log.clear();
  front.remove_face(f);
  EXPECT_TRUE(log.faces.empty()) << "a detached log hears nothing";
}

TEST(Front, CornerOfFindsTheCornerHoldingANode) {
  const auto cube = test::box_surface(1, 1, 1);
  const Front front(cube.surface);
  for (FaceIndex f = 0; f < 6; ++f) {
    for (int i = 0; i < 4; ++i)
      EXPECT_EQ(front.corner_of(f, front.face(f).nodes[static_cast<std::size_t>(i)]), i);
  }
  // a node not on face 0
  NodeId off;
  for (std::size_t n = 0; n < 8; ++n)
    if (front.corner_of(0, NodeId(n)) < 0) off = NodeId(n);
  ASSERT_TRUE(off.is_valid());
  EXPECT_EQ(front.corner_of(0, off), -1);
}

TEST(Front, FindEdgeFindsTheDirectedEdgeOnly) {
  const auto cube = test::box_surface(1, 1, 1);
  const Front front(cube.surface);
  const stc::Quad q = front.face(2).nodes;
  const FaceSide fs = front.find_edge(q[1], q[2]);
  EXPECT_EQ(fs.face, 2);
  EXPECT_EQ(fs.index, 1);
  const FaceSide back = front.find_edge(q[2], q[1]);
  EXPECT_NE(back.face, 2) << "the reverse edge is the neighbour's";
  EXPECT_NE(back.face, kNoFace);
  EXPECT_EQ(front.find_edge(q[0], q[2]).face, kNoFace) << "a diagonal is no edge";
}

TEST(Front, AddFaceAndRemoveFaceKeepIncidenceAndReuseSlots) {
  const auto cube = test::box_surface(1, 1, 1);
  Front front(cube.surface);
  const stc::Quad q = front.face(3).nodes;
  const FaceOwner owner = front.face(3).owner;
  front.remove_face(3);
  EXPECT_EQ(front.num_faces(), 5u);
  EXPECT_FALSE(front.is_alive(3));
  for (NodeId n : q) EXPECT_EQ(front.valence(n), 2u);
  const FaceIndex f = front.add_face(q, owner, 4, {90.0F, 91.0F, 92.0F, 93.0F});
  EXPECT_EQ(f, 3) << "the freed slot is reused";
  EXPECT_EQ(front.face(f).depth, 4);
  EXPECT_EQ(front.face(f).side_angle[1], 91.0F);
  EXPECT_EQ(front.num_faces(), 6u);
  for (NodeId n : q) {
    EXPECT_EQ(front.valence(n), 3u);
    const auto& list = front.faces_at(n);
    EXPECT_EQ(std::count(list.begin(), list.end(), f), 1);
  }
  EXPECT_FALSE(front.check_invariants().has_value());
  const FaceIndex g = front.add_face(q, owner, 0);
  EXPECT_EQ(g, 6) << "a new slot when none is free";
  const auto err = front.check_invariants();
  ASSERT_TRUE(err.has_value());
  EXPECT_NE(err->find("pinched"), std::string::npos) << *err;
}

TEST(Front, MergeMovesTheFacesOfTheGoneNode) {
  const auto cube = test::box_surface(1, 1, 1);
  Front front(cube.surface);
  const NodeId a = front.new_node();
  const stc::Quad q = front.face(0).nodes;
  front.remove_face(0);
  const FaceIndex f = front.add_face({q[0], q[1], q[2], a}, FaceOwner{}, 0);
  EXPECT_EQ(front.valence(a), 1u);
  front.merge_nodes(q[3], a);
  EXPECT_EQ(front.face(f).nodes[3], q[3]);
  EXPECT_EQ(front.valence(a), 0u);
  EXPECT_EQ(front.valence(q[3]), 3u);
  EXPECT_FALSE(front.check_invariants().has_value());
}

}  // namespace
}  // namespace stcweave::weave
