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

}  // namespace
}  // namespace stcweave::weave
