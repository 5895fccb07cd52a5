// Each rule of the weave alone, on a front built by hand (weave/include/stcweave/weave/rules.hpp):
// what it does when its precondition holds, and the reason it gives when it does not.
#include "stcweave/weave/rules.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <set>
#include <span>

#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/kernel.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

stc::QuadSurface cube() {
  return test::box_surface(1, 1, 1).surface;
}

/// Two quads glued along their whole boundary: four nodes of valence 2.
stc::QuadSurface pillow() {
  stc::QuadSurface s;
  s.num_nodes = 4;
  s.quads.push_back({NodeId(0), NodeId(1), NodeId(2), NodeId(3)});
  s.quads.push_back({NodeId(0), NodeId(3), NodeId(2), NodeId(1)});
  return s;
}

/// A cube whose top face is split into two quads sharing the two edges at node 8 (a doublet):
/// its seam would merge two input nodes, so no weave of it can close.
stc::QuadSurface doublet_cube() {
  stc::QuadSurface s;
  s.num_nodes = 9;
  const auto q = [&s](int a, int b, int c, int d) {
    s.quads.push_back({NodeId(a), NodeId(b), NodeId(c), NodeId(d)});
  };
  q(0, 3, 2, 1);
  q(0, 1, 5, 4);
  q(3, 7, 6, 2);
  q(0, 4, 7, 3);
  q(1, 2, 6, 5);
  q(4, 5, 6, 8);
  q(4, 8, 6, 7);
  return s;
}

/// A state and its context, as the driver holds them (not copyable: the context refers to the
/// options).
struct Bench {
  Bench(const Bench&) = delete;
  Bench& operator=(const Bench&) = delete;
  explicit Bench(const stc::QuadSurface& s, RuleSet rules = RuleSet::Reliable) : state(s) {
    options.rules = rules;
    options.check = true;
  }
  WeaveOptions options;
  WeaveState state;
  WeaveContext ctx{options, nullptr, 100000};
};

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

NodeId node_of_valence(const Front& front, std::size_t k) {
  for (std::size_t n = 0; n < front.num_nodes(); ++n)
    if (front.valence(NodeId(n)) == k) return NodeId(n);
  return NodeId::invalid();
}

// ---------------------------------------------------------------------------------------
// cross

TEST(Cross, AtACubeCornerBuildsOneHexOnItsThreeFaces) {
  Bench b(cube());
  const RuleResult r = cross(b.state, b.ctx, NodeId(0));
  ASSERT_TRUE(r.applied) << r.why;
  ASSERT_EQ(b.state.woven.hexes.size(), 1u);
  EXPECT_EQ(r.hex, HexId(0));
  const stc::Hex& h = b.state.woven.hexes[0];
  EXPECT_EQ(std::set<NodeId>(h.begin(), h.end()).size(), 8u);
  EXPECT_EQ(h[0], NodeId(0)) << "the hex starts at the crossed node";
  EXPECT_EQ(b.state.front.num_nodes(), 9u) << "one new node";
  EXPECT_EQ(b.state.front.num_faces(), 6u) << "three faces off, three on";
  EXPECT_EQ(b.state.front.valence(NodeId(0)), 0u) << "the corner left the front";
  EXPECT_FALSE(b.state.front.check_invariants().has_value());
  std::size_t to_input = 0;
  for (const DualLink& l : b.state.woven.dual[0]) to_input += l.is_boundary && l.id >= 0 ? 1 : 0;
  EXPECT_EQ(to_input, 3u) << "its three faces on the front are linked to their input quads";
  // propagation: every new face is opposite an input (depth 0) face
  for (std::size_t f = 0; f < b.state.front.face_capacity(); ++f) {
    const auto fi = static_cast<FaceIndex>(f);
    if (b.state.front.is_alive(fi) && b.state.front.face(fi).owner.is_hex())
      EXPECT_EQ(b.state.front.face(fi).depth, 1);
  }
  EXPECT_EQ(b.state.stats.crosses, 1u);
  EXPECT_EQ(b.ctx.rules_applied, 1u);
}

TEST(Cross, RefusesANodeOfValenceFour) {
  Bench b(test::box_surface(2, 1, 1).surface);
  const NodeId v = node_of_valence(b.state.front, 4);
  ASSERT_TRUE(v.is_valid());
  const RuleResult r = cross(b.state, b.ctx, v);
  EXPECT_FALSE(r.applied);
  EXPECT_EQ(r.why, "valence 4");
  EXPECT_TRUE(b.state.woven.hexes.empty());
}

TEST(Cross, RefusesThreeFacesOfOneHex) {
  Bench b(cube());
  ASSERT_TRUE(cross(b.state, b.ctx, NodeId(0)));
  const NodeId w(8);  // the new node: its three faces are faces of h0
  ASSERT_EQ(b.state.front.valence(w), 3u);
  const RuleResult r = cross(b.state, b.ctx, w);
  EXPECT_FALSE(r.applied);
  EXPECT_TRUE(has(r.why, "belong to one hex")) << r.why;
  EXPECT_EQ(b.state.woven.hexes.size(), 1u);
}

TEST(Cross, RefusesAHexThatWouldShareMoreThanAFaceWithAWovenHex) {
  // After the cross at node 0, the corner opposite it still has its three input faces, whose
  // other six nodes are all nodes of h0: a second cross there would share six with it.
  Bench b(cube());
  ASSERT_TRUE(cross(b.state, b.ctx, NodeId(0)));
  const stc::Hex& h0 = b.state.woven.hexes[0];
  NodeId opposite = NodeId::invalid();
  for (std::size_t n = 0; n < 8; ++n)
    if (std::find(h0.begin(), h0.end(), NodeId(n)) == h0.end()) opposite = NodeId(n);
  ASSERT_TRUE(opposite.is_valid());
  ASSERT_EQ(b.state.front.valence(opposite), 3u);
  const RuleResult r = cross(b.state, b.ctx, opposite);
  EXPECT_FALSE(r.applied);
  EXPECT_EQ(r.why, "the new hex would share 6 nodes with h0 (more than a face)");
  EXPECT_EQ(b.state.woven.hexes.size(), 1u);
  EXPECT_EQ(b.state.front.num_nodes(), 9u) << "no node made for a refused hex";
}

TEST(ContactConflict, AcceptsTheFaceItIsGluedToAndRefusesFourOtherNodes) {
  Bench b(cube());
  ASSERT_TRUE(cross(b.state, b.ctx, NodeId(0)));
  const stc::Hex h0 = b.state.woven.hexes[0];
  // A face of h0 that is on the front (the three that hold its new node w = n8).
  FaceIndex glued = kNoFace;
  for (std::size_t f = 0; f < b.state.front.face_capacity(); ++f) {
    const auto fi = static_cast<FaceIndex>(f);
    if (b.state.front.is_alive(fi) && b.state.front.face(fi).owner.is_hex()) glued = fi;
  }
  ASSERT_NE(glued, kNoFace);
  const stc::Quad q = b.state.front.face(glued).nodes;
  const std::array<FaceIndex, 1> used{glued};
  EXPECT_FALSE(b.state.contact_conflict(q, used).has_value()) << "the face it is glued to";
  const std::array<FaceIndex, 0> none{};
  const auto off = b.state.contact_conflict(q, none);
  ASSERT_TRUE(off.has_value()) << "the same four nodes, not glued";
  EXPECT_EQ(*off,
            "the new hex would share four nodes with h0 that are not the face it is "
            "glued to");
  // Three nodes of h0 are accepted.
  EXPECT_FALSE(b.state.contact_conflict(std::span(h0).first(3), none).has_value());
}

TEST(Cross, FlatCornerIsRefusedUnlessThePreconditionIsLifted) {
  // extended, every edge flat (no angles given): the corner is "too flat"
  Bench flat(cube(), RuleSet::Extended);
  const RuleResult refused = cross(flat.state, flat.ctx, NodeId(0));
  EXPECT_FALSE(refused.applied);
  EXPECT_TRUE(has(refused.why, "too flat a corner (3 of its 3 edges")) << refused.why;
  flat.ctx.relax_geometry = true;
  ASSERT_TRUE(cross(flat.state, flat.ctx, NodeId(0)));
  EXPECT_EQ(flat.state.woven.hex_rule[0], "cross-relaxed");

  // a real cube corner (90 degrees) passes
  Bench sharp(cube(), RuleSet::Extended);
  for (std::size_t f = 0; f < 6; ++f)
    sharp.state.front.set_side_angles(static_cast<FaceIndex>(f), {90.0F, 90.0F, 90.0F, 90.0F});
  ASSERT_TRUE(cross(sharp.state, sharp.ctx, NodeId(0)));
  EXPECT_EQ(sharp.state.woven.hex_rule[0], "cross");
  // and with `reliable` the precondition does not exist
  Bench reliable(cube(), RuleSet::Reliable);
  EXPECT_TRUE(cross(reliable.state, reliable.ctx, NodeId(0)).applied);
}

// ---------------------------------------------------------------------------------------
// seam

TEST(Seam, ClosesTheCubeAfterItsCross) {
  // After a cross at a corner, the front is three input quads and three hex faces meeting at
  // a valence-2 node; the seam merges the new node into the opposite corner and glues the
  // other two pairs that then coincide: the front is empty, h0 is the cube's hex.
  Bench b(cube());
  ASSERT_TRUE(cross(b.state, b.ctx, NodeId(0)));
  const NodeId v = node_of_valence(b.state.front, 2);
  ASSERT_TRUE(v.is_valid());
  const RuleResult r = seam(b.state, b.ctx, v);
  ASSERT_TRUE(r.applied) << r.why;
  EXPECT_EQ(b.state.front.num_faces(), 0u);
  EXPECT_EQ(b.state.stats.seams, 1u);
  EXPECT_EQ(b.state.stats.coincident_glues, 2u);
  for (const DualLink& l : b.state.woven.dual[0]) {
    EXPECT_TRUE(l.is_boundary);
    EXPECT_GE(l.id, 0);
  }
  EXPECT_TRUE(b.state.front.is_input_node(b.state.front.find(NodeId(8))))
      << "the new node was merged into an input node";
}

TEST(Seam, RefusesToGlueTwoInputQuads) {
  Bench b(pillow());
  const RuleResult r = seam(b.state, b.ctx, NodeId(0));
  EXPECT_FALSE(r.applied);
  EXPECT_TRUE(has(r.why, "two input quads q0 and q1")) << r.why;
  EXPECT_EQ(b.state.front.num_faces(), 2u);
}

TEST(Seam, RefusesToMergeTwoInputNodes) {
  // The doublet's seam at n8 glues two input quads; once a shrink has replaced one of them
  // by a hex face, the seams at the doublet's other valence-2 nodes would merge input nodes.
  Bench b(doublet_cube());
  EXPECT_TRUE(has(seam(b.state, b.ctx, NodeId(8)).why, "two input quads q5 and q6"));
  const Strip strip = front_loops(b.state.front).strips.front();
  ASSERT_TRUE(shrink(b.state, b.ctx, strip, stc::LoopSide::Left).has_value());
  std::size_t refused = 0;
  for (std::size_t n = 0; n < b.state.front.num_nodes(); ++n) {
    if (b.state.front.valence(NodeId(n)) != 2) continue;
    const RuleResult r = seam(b.state, b.ctx, NodeId(n));
    EXPECT_FALSE(r.applied);
    refused += has(r.why, "it would merge two input nodes") ? 1 : 0;
  }
  EXPECT_GT(refused, 0u);
}

TEST(Seam, RefusesANodeThatIsNotOfValenceTwo) {
  Bench b(cube());
  EXPECT_EQ(seam(b.state, b.ctx, NodeId(0)).why, "valence 3");
}

TEST(Seam, FixpointQueuesRefusedSeamsForTheNextPass) {
  Bench b(doublet_cube());
  b.state.seam_work.push_back(NodeId(8));
  seam_fixpoint(b.state, b.ctx);
  EXPECT_EQ(b.state.stats.blocked_seams, 1u);
  ASSERT_EQ(b.state.blocked_seams.size(), 1u);
  EXPECT_EQ(b.state.blocked_seams[0], NodeId(8));
  EXPECT_TRUE(b.state.seam_work.empty());
}

// ---------------------------------------------------------------------------------------
// blind chord formation

/// The first (strip, node) on side A of a loop of `front` whose node has valence >= 4.
std::pair<Strip, NodeId> strip_with_high_valence_side_node(const Front& front) {
  for (const Strip& strip : front_loops(front).strips) {
    for (const stc::StripStep& p : strip) {
      const NodeId v = quad_at(front.face(face_of(p)).nodes, p.entry);
      if (front.valence(v) >= 4) return {strip, v};
    }
  }
  return {};
}

TEST(BlindChord, LowersTheValenceOfASideNodeByOne) {
  Bench b(test::box_surface(2, 1, 1).surface);
  const auto [strip, v] = strip_with_high_valence_side_node(b.state.front);
  ASSERT_TRUE(v.is_valid());
  const std::size_t k = b.state.front.valence(v);
  const FaceSet strip_faces = mark_strip_faces(b.ctx.faces, b.state.front, strip);
  const RuleResult r = blind_chord(b.state, b.ctx, v, strip, strip_faces);
  ASSERT_TRUE(r.applied) << r.why;
  EXPECT_EQ(b.state.front.valence(v), k - 1);
  EXPECT_EQ(b.state.front.num_nodes(), b.state.front.num_input_nodes() + 2) << "two new nodes";
  EXPECT_EQ(b.state.front.num_faces(), 10u + 2u) << "two faces off, four on";
  EXPECT_EQ(b.state.stats.blind_chords, 1u);
  EXPECT_FALSE(b.state.front.check_invariants().has_value());
  // depth: the two faces opposite used input faces get 1, the two others -1 (seed sect. 6)
  std::multiset<std::int32_t> depths;
  for (std::size_t f = 0; f < b.state.front.face_capacity(); ++f) {
    const auto fi = static_cast<FaceIndex>(f);
    if (b.state.front.is_alive(fi) && b.state.front.face(fi).owner.is_hex())
      depths.insert(b.state.front.face(fi).depth);
  }
  EXPECT_EQ(depths, (std::multiset<std::int32_t>{-1, -1, 1, 1}));
}

TEST(BlindChord, RefusesANodeOffTheShrinkingSide) {
  Bench b(test::box_surface(2, 1, 1).surface);
  const auto [strip, v] = strip_with_high_valence_side_node(b.state.front);
  ASSERT_TRUE(v.is_valid());
  // a node on side B only: not a corner entry / entry+3 of any step
  std::set<NodeId> side_a;
  for (const stc::StripStep& p : strip) {
    const stc::Quad& n = b.state.front.face(face_of(p)).nodes;
    side_a.insert(quad_at(n, p.entry));
    side_a.insert(quad_at(n, p.entry + 3));
  }
  NodeId off;
  for (const stc::StripStep& p : strip) {
    const NodeId m = quad_at(b.state.front.face(face_of(p)).nodes, p.entry + 1);
    if (side_a.count(m) == 0) off = m;
  }
  ASSERT_TRUE(off.is_valid());
  const FaceSet strip_faces = mark_strip_faces(b.ctx.faces, b.state.front, strip);
  const RuleResult r = blind_chord(b.state, b.ctx, off, strip, strip_faces);
  EXPECT_FALSE(r.applied);
  EXPECT_TRUE(has(r.why, "no strip face at it")) << r.why;
  EXPECT_TRUE(b.state.woven.hexes.empty());
}

/// The positions of the steps of `strip` that hold v at entry or entry + 3, in strip order.
std::vector<std::uint32_t> steps_holding(const Front& front, const Strip& strip, NodeId v) {
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < strip.size(); ++i) {
    const stc::Quad& n = front.face(face_of(strip[i])).nodes;
    if (quad_at(n, strip[i].entry) == v || quad_at(n, strip[i].entry + 3) == v)
      out.push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

TEST(BlindChord, GivenItsStepsBuildsTheHexTheScanBuilds) {
  // Every node of every loop's strip of a 3 x 2 x 1 box, on the input front and after one
  // cross, once with the strip scanned and once with the steps given (what shrink does): the
  // same verdict, reason and hex.
  const stc::QuadSurface surface = test::box_surface(3, 2, 1).surface;
  std::size_t compared = 0, applied = 0, refused_on_side = 0;
  for (const bool after_cross : {false, true}) {
    const auto prepare = [after_cross](Bench& b) {
      if (after_cross) ASSERT_TRUE(cross(b.state, b.ctx, node_of_valence(b.state.front, 3)));
    };
    Bench probe(surface);
    prepare(probe);
    for (const Strip& strip : front_loops(probe.state.front).strips) {
      std::set<NodeId> nodes;
      for (const stc::StripStep& p : strip)
        for (const NodeId m : probe.state.front.face(face_of(p)).nodes) nodes.insert(m);
      for (const NodeId v : nodes) {
        Bench scan(surface), given(surface);
        prepare(scan);
        prepare(given);
        const FaceSet fs = mark_strip_faces(scan.ctx.faces, scan.state.front, strip);
        const RuleResult a = blind_chord(scan.state, scan.ctx, v, strip, fs);
        const FaceSet fg = mark_strip_faces(given.ctx.faces, given.state.front, strip);
        const std::vector<std::uint32_t> steps = steps_holding(given.state.front, strip, v);
        const RuleResult b = blind_chord(given.state, given.ctx, v, strip, fg, steps);
        EXPECT_EQ(a.applied, b.applied) << v.str();
        EXPECT_EQ(a.why, b.why) << v.str();
        EXPECT_EQ(scan.state.woven.hexes, given.state.woven.hexes) << v.str();
        EXPECT_EQ(scan.state.front.num_faces(), given.state.front.num_faces()) << v.str();
        ++compared;
        applied += a.applied ? 1 : 0;
        refused_on_side += !a.applied && !steps.empty() ? 1 : 0;
      }
    }
  }
  EXPECT_GT(applied, 0u) << "the comparison should include applied rules";
  EXPECT_GT(refused_on_side, 0u) << "and rules refused at a node on the shrinking side";
  EXPECT_LT(applied + refused_on_side, compared) << "and nodes off it";
}

TEST(BlindChord, AStepThatDoesNotHoldTheNodeIsAnInternalError) {
  Bench b(test::box_surface(2, 1, 1).surface);
  const auto [strip, v] = strip_with_high_valence_side_node(b.state.front);
  ASSERT_TRUE(v.is_valid());
  std::vector<std::uint32_t> wrong;
  for (std::size_t i = 0; i < strip.size() && wrong.empty(); ++i) {
    const stc::Quad& n = b.state.front.face(face_of(strip[i])).nodes;
    if (quad_at(n, strip[i].entry) != v && quad_at(n, strip[i].entry + 3) != v)
      wrong.push_back(static_cast<std::uint32_t>(i));
  }
  ASSERT_FALSE(wrong.empty());
  const FaceSet strip_faces = mark_strip_faces(b.ctx.faces, b.state.front, strip);
  EXPECT_THROW((void)blind_chord(b.state, b.ctx, v, strip, strip_faces, wrong), InternalError);
  EXPECT_TRUE(b.state.woven.hexes.empty());
  // no steps at all: refused, nothing built
  const RuleResult r = blind_chord(b.state, b.ctx, v, strip, strip_faces, {});
  EXPECT_FALSE(r.applied);
  EXPECT_TRUE(has(r.why, "no strip face at it")) << r.why;
}

// ---------------------------------------------------------------------------------------
// loop shrinking

TEST(Shrink, OneLoopOfABarBuildsOneLayer) {
  // A 1 x 1 x 2 bar: the loop around its lower half, shrunk toward the bottom, makes the lower
  // cube's hex and leaves the upper cube's six faces on the front.
  Bench b(test::box_surface(1, 1, 2).surface);
  const FrontLoops loops = front_loops(b.state.front);
  bool done = false;
  for (const Strip& strip : loops.strips) {
    if (strip.size() != 4 || done) continue;
    for (const stc::LoopSide side : {stc::LoopSide::Left, stc::LoopSide::Right}) {
      WeaveState copy = b.state;
      WeaveContext ctx(b.options, nullptr, 1000);
      if (shrink(copy, ctx, strip, side).has_value()) continue;
      if (copy.woven.hexes.size() != 1) continue;
      EXPECT_EQ(copy.front.num_faces(), 6u);
      EXPECT_FALSE(copy.front.check_invariants().has_value());
      EXPECT_EQ(copy.stats.crosses, 1u);
      done = true;
      break;
    }
  }
  EXPECT_TRUE(done) << "no loop of length 4 shrinks to one hex";
}

TEST(Shrink, FailsNamingEveryBlockedNode) {
  Bench b(pillow());
  const Strip strip = front_loops(b.state.front).strips.front();
  const auto failure = shrink(b.state, b.ctx, strip, stc::LoopSide::Left);
  ASSERT_TRUE(failure.has_value());
  EXPECT_TRUE(has(*failure, "every node on the shrinking side is blocked")) << *failure;
  EXPECT_TRUE(has(*failure, "two input quads")) << *failure;
}

// ---------------------------------------------------------------------------------------
// parallel merging

const Strip* loop_of_length(const FrontLoops& loops, std::size_t n) {
  for (const Strip& s : loops.strips)
    if (s.size() == n) return &s;
  return nullptr;
}

TEST(ParallelMerging, ClosesASlabInOneLayer) {
  // The 2 x 2 x 1 slab: the ring of its eight side faces is one face high, between two discs
  // of four faces that its transversal edges map onto each other: one hex per face pair.
  Bench b(test::box_surface(2, 2, 1).surface, RuleSet::Extended);
  const FrontLoops loops = front_loops(b.state.front);
  const Strip* ring = loop_of_length(loops, 8);
  ASSERT_NE(ring, nullptr);
  const FrontComponents components = front_components(b.state.front, b.ctx.nodes);
  const RuleResult r = parallel_merging(b.state, b.ctx, *ring, components);
  ASSERT_TRUE(r.applied) << r.why;
  EXPECT_EQ(b.state.woven.hexes.size(), 4u);
  EXPECT_EQ(b.state.front.num_nodes(), b.state.front.num_input_nodes()) << "no node created";
  // The hexes glue to each other by faces that are still on the front until seams sew them.
  seam_fixpoint(b.state, b.ctx);
  EXPECT_EQ(b.state.front.num_faces(), 0u);
}

TEST(ParallelMerging, ClosesACubeAsOneHex) {
  // The cube: any loop's strip is the ring between two opposite faces (each rim face borders
  // all four strip faces).
  Bench b(cube(), RuleSet::Extended);
  const FrontLoops loops = front_loops(b.state.front);
  const FrontComponents components = front_components(b.state.front, b.ctx.nodes);
  const RuleResult r = parallel_merging(b.state, b.ctx, loops.strips.front(), components);
  ASSERT_TRUE(r.applied) << r.why;
  EXPECT_EQ(b.state.woven.hexes.size(), 1u);
  EXPECT_EQ(b.state.front.num_faces(), 0u);
}

TEST(ParallelMerging, RefusesWhenTheTwoSidesDiffer) {
  // The 1 x 1 x 2 bar: a ring loop has one face on one side and five on the other.
  Bench b(test::box_surface(1, 1, 2).surface, RuleSet::Extended);
  const FrontLoops loops = front_loops(b.state.front);
  const Strip* ring = loop_of_length(loops, 4);
  ASSERT_NE(ring, nullptr);
  const FrontComponents components = front_components(b.state.front, b.ctx.nodes);
  const RuleResult r = parallel_merging(b.state, b.ctx, *ring, components);
  EXPECT_FALSE(r.applied);
  EXPECT_FALSE(r.why.empty());
  EXPECT_EQ(b.ctx.rules_applied, 0u) << "a refused merge changes nothing";
  EXPECT_TRUE(b.state.woven.hexes.empty());
}

// ---------------------------------------------------------------------------------------
// non-convexity seam

TEST(NonConvexitySeam, RefusesWithoutAHexFaceAcross) {
  Bench b(cube(), RuleSet::Extended);
  const RuleResult r = nonconvexity_seam(b.state, b.ctx, 0, 0);
  EXPECT_FALSE(r.applied);
  EXPECT_EQ(r.why, "no hex face across");
}

/// A cube with real (90 degree) angles after a cross at node 0: the three input quads left
/// each meet a hex face across one side. \pre `b` holds the cube, extended.
void cross_the_cube(Bench& b) {
  for (std::size_t f = 0; f < 6; ++f)
    b.state.front.set_side_angles(static_cast<FaceIndex>(f), {90.0F, 90.0F, 90.0F, 90.0F});
  EXPECT_TRUE(cross(b.state, b.ctx, NodeId(0)).applied);
}

/// An input face and its side across which a hex face lies.
std::pair<FaceIndex, int> input_side_next_to_hex(const Front& front) {
  for (std::size_t f = 0; f < front.face_capacity(); ++f) {
    const auto fi = static_cast<FaceIndex>(f);
    if (!front.is_alive(fi) || !front.face(fi).owner.is_input()) continue;
    for (int s = 0; s < 4; ++s)
      if (front.face(front.across(fi, s).face).owner.is_hex()) return {fi, s};
  }
  return {kNoFace, -1};
}

TEST(NonConvexitySeam, RefusesWithoutANonConvexEdgeNextToTheCommonOne) {
  Bench b(cube(), RuleSet::Extended);
  cross_the_cube(b);
  const auto [f2, side] = input_side_next_to_hex(b.state.front);
  ASSERT_NE(f2, kNoFace);
  EXPECT_LE(edge_angle(b.state.front, f2, side), 170.0) << "convex by propagation";
  const RuleResult r = nonconvexity_seam(b.state, b.ctx, f2, side);
  EXPECT_EQ(r.why, "no non-convex edge next to the common edge");
}

TEST(NonConvexitySeam, RefusesToMergeAnInputNode) {
  // Make the edge next to the common one non-convex (both faces carry 270 there): the next
  // precondition, the hex face's far nodes being interior, fails on a one-hex front.
  Bench b(cube(), RuleSet::Extended);
  cross_the_cube(b);
  const auto [f2, side] = input_side_next_to_hex(b.state.front);
  ASSERT_NE(f2, kNoFace);
  const int next = (side + 1) % 4;
  auto angles = b.state.front.face(f2).side_angle;
  angles[static_cast<std::size_t>(next)] = 270.0F;
  b.state.front.set_side_angles(f2, angles);
  const FaceSide g = b.state.front.across(f2, next);
  auto other = b.state.front.face(g.face).side_angle;
  other[static_cast<std::size_t>(g.index)] = 270.0F;
  b.state.front.set_side_angles(g.face, other);
  EXPECT_GT(edge_angle(b.state.front, f2, next), 190.0);
  const RuleResult r = nonconvexity_seam(b.state, b.ctx, f2, side);
  EXPECT_FALSE(r.applied);
  EXPECT_TRUE(has(r.why, "input node")) << r.why;
}

// ---------------------------------------------------------------------------------------
// propagation

TEST(Propagate, ConvexAndNonConvexCancel) {
  Bench b(cube());
  const FaceSide g = b.state.front.across(0, 0);
  auto a0 = b.state.front.face(0).side_angle;
  auto a1 = b.state.front.face(g.face).side_angle;
  a0[0] = 90.0F;
  a1[static_cast<std::size_t>(g.index)] = 270.0F;
  b.state.front.set_side_angles(0, a0);
  b.state.front.set_side_angles(g.face, a1);
  EXPECT_DOUBLE_EQ(edge_angle(b.state.front, 0, 0), 180.0) << "seed Fig. 12: they cancel";
  a1[static_cast<std::size_t>(g.index)] = 120.0F;
  b.state.front.set_side_angles(g.face, a1);
  EXPECT_DOUBLE_EQ(edge_angle(b.state.front, 0, 0), 90.0) << "two convex: the sharper";
  EXPECT_DOUBLE_EQ(edge_angle(b.state.front, g.face, g.index), 90.0) << "symmetric";
}

TEST(Propagate, NewFacesCarryDepthAndAnglesFromTheOppositeFace) {
  Bench b(cube());
  // distinct angles on face 0 (the bottom q0) so that each side can be told apart
  b.state.front.set_side_angles(0, {100.0F, 110.0F, 120.0F, 130.0F});
  const stc::Quad bottom = b.state.front.face(0).nodes;
  // a hex on the bottom face alone, top face made of new nodes
  const NodeId n0 = b.state.new_node(), n1 = b.state.new_node(), n2 = b.state.new_node(),
               n3 = b.state.new_node();
  const stc::Hex hex{bottom[0], bottom[3], bottom[2], bottom[1], n0, n3, n2, n1};
  std::array<FaceIndex, 6> used{};
  used.fill(kNoFace);
  used[0] = 0;  // hex face 0 (0,1,2,3) = the bottom reversed
  const Propagated p = propagate(b.state.front, hex, used);
  EXPECT_EQ(p.depth[1], 1) << "opposite the depth-0 face";
  for (int lf = 2; lf < 6; ++lf) EXPECT_EQ(p.depth[static_cast<std::size_t>(lf)], -1);
  std::multiset<float> top(p.side_angle[1].begin(), p.side_angle[1].end());
  EXPECT_EQ(top, (std::multiset<float>{100.0F, 110.0F, 120.0F, 130.0F}))
      << "the top face carries the bottom's four angles";
  for (int lf = 2; lf < 6; ++lf)
    for (float a : p.side_angle[static_cast<std::size_t>(lf)]) EXPECT_EQ(a, 180.0F);
}

// ---------------------------------------------------------------------------------------
// backtracking: a shrink that fails after changing the front, and the roll-back

void expect_same_front(const Front& a, const Front& b) {
  ASSERT_EQ(a.num_nodes(), b.num_nodes());
  ASSERT_EQ(a.face_capacity(), b.face_capacity());
  EXPECT_EQ(a.num_faces(), b.num_faces());
  for (std::size_t f = 0; f < a.face_capacity(); ++f) {
    const auto fi = static_cast<FaceIndex>(f);
    ASSERT_EQ(a.is_alive(fi), b.is_alive(fi)) << "face slot " << f;
    if (!a.is_alive(fi)) continue;
    EXPECT_EQ(a.face(fi).nodes, b.face(fi).nodes);
    EXPECT_EQ(a.face(fi).owner.str(), b.face(fi).owner.str());
    EXPECT_EQ(a.face(fi).depth, b.face(fi).depth);
    EXPECT_EQ(a.face(fi).side_angle, b.face(fi).side_angle);
  }
  for (std::size_t n = 0; n < a.num_nodes(); ++n) {
    EXPECT_EQ(a.find(NodeId(n)), b.find(NodeId(n)));
    EXPECT_EQ(a.faces_at(NodeId(n)), b.faces_at(NodeId(n))) << "node " << n;
  }
}

TEST(Backtracking, ACheckpointUndoesAFailedShrinkExactly) {
  // The driver's undo: a checkpoint before the shrink, a journal of what it changed.
  Bench b(doublet_cube());
  const WeaveState pristine = b.state;
  const FrontLoops loops = front_loops(b.state.front);
  std::size_t undone = 0;
  for (const Strip& strip : loops.strips) {
    for (const stc::LoopSide side : {stc::LoopSide::Left, stc::LoopSide::Right}) {
      WeaveState::Checkpoint saved = b.state.checkpoint();
      const std::size_t before = b.ctx.rules_applied;
      const auto failure = shrink(b.state, b.ctx, strip, side);
      const bool changed = b.ctx.rules_applied != before;
      b.state.roll_back(std::move(saved));
      expect_same_front(b.state.front, pristine.front);
      EXPECT_EQ(b.state.woven.hexes.size(), 0u);
      EXPECT_EQ(b.state.woven.hexes_at, pristine.woven.hexes_at);
      EXPECT_EQ(b.state.seam_work, pristine.seam_work);
      EXPECT_EQ(b.state.stats.crosses, 0u);
      undone += changed ? 1 : 0;
      (void)failure;
    }
  }
  EXPECT_GT(undone, 2u) << "shrinks that changed the front were undone";
  // A released checkpoint keeps the changes.
  WeaveState::Checkpoint kept = b.state.checkpoint();
  ASSERT_TRUE(cross(b.state, b.ctx, NodeId(0)));
  b.state.release(std::move(kept));
  EXPECT_EQ(b.state.woven.hexes.size(), 1u);
  EXPECT_FALSE(b.state.front.check_invariants().has_value());
}

TEST(Backtracking, AFailedShrinkIsRolledBackExactly) {
  Bench b(doublet_cube());
  const WeaveState pristine = b.state;
  const FrontLoops loops = front_loops(b.state.front);
  bool found = false;
  for (const Strip& strip : loops.strips) {
    for (const stc::LoopSide side : {stc::LoopSide::Left, stc::LoopSide::Right}) {
      WeaveState saved = b.state;
      const std::size_t before = b.ctx.rules_applied;
      b.state.stats.selections = 7;  // a selection counter the roll-back must keep
      const auto failure = shrink(b.state, b.ctx, strip, side);
      if (!failure || b.ctx.rules_applied == before) {
        b.state.roll_back_to(std::move(saved));
        continue;
      }
      // the shrink did work before it was blocked
      EXPECT_FALSE(b.state.woven.hexes.empty());
      b.state.roll_back_to(std::move(saved));
      expect_same_front(b.state.front, pristine.front);
      EXPECT_TRUE(b.state.woven.hexes.empty());
      EXPECT_TRUE(b.state.woven.dual.empty());
      EXPECT_EQ(b.state.woven.hexes_at.size(), pristine.woven.hexes_at.size());
      EXPECT_EQ(b.state.stats.crosses, 0u);
      EXPECT_EQ(b.state.stats.selections, 7u) << "selection counters survive the roll-back";
      found = true;
      break;
    }
    if (found) break;
  }
  EXPECT_TRUE(found) << "no shrink of the doublet cube fails after changing the front";
}

/// Counts what the driver reports.
class Counter final : public WeaveObserver {
 public:
  void on_selection(std::size_t, std::int32_t, std::span<const TraceCandidate>, std::size_t,
                    const std::string& reason, std::span<const std::string>,
                    const std::string&) override {
    ++selections;
    if (has(reason, "partial shrink is kept")) ++last_resorts;
  }
  void on_rule(std::size_t, std::int32_t, const char*, NodeId, std::span<const FaceOwner>,
               HexId) override {
    ++rules;
  }
  void on_shrink_failed(std::size_t, std::int32_t, const std::string& reason) override {
    ++failures;
    if (has(reason, "(undone)")) ++undone;
  }
  int selections = 0, rules = 0, failures = 0, undone = 0, last_resorts = 0;
};

// WeaveOptions::undo_seam_blocking_on_block when the second weave fails too: the caller gets
// the first weave's error, word for word, and the trace streamed is the first weave's.
TEST(SeamUndoRetry, WhenTheRetryFailsTooTheFirstWeavesErrorIsThrown) {
  const auto failure = [](WeaveOptions o, std::size_t& events) {
    events = 0;
    o.on_trace = [&events](const TraceEvent&) { ++events; };
    try {
      (void)weave(doublet_cube(), o);
    } catch (const WeaveError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  WeaveOptions no_retry;
  no_retry.undo_seam_blocking_on_block = false;
  WeaveOptions undo = no_retry;
  undo.undo_seam_blocking_shrinks = true;
  std::size_t first_events = 0, undo_events = 0, events = 0;
  const std::string first = failure(no_retry, first_events);
  ASSERT_FALSE(first.empty()) << "the doublet cube no longer blocks";
  ASSERT_FALSE(failure(undo, undo_events).empty())
      << "the doublet cube now weaves undoing the shrinks: the retry would complete it";
  // The two weaves stream different traces (9 and 26 events when written), so the count
  // tells which one reached the caller.
  ASSERT_NE(undo_events, first_events);
  const std::string retried = failure(WeaveOptions{}, events);
  EXPECT_EQ(retried, first);
  EXPECT_EQ(events, first_events);
}

TEST(Backtracking, TheDriverUndoesFailedShrinksThenKeepsTheFirstAsALastResort) {
  for (const bool backtrack : {true, false}) {
    Counter counter;
    WeaveOptions o;
    o.backtrack = backtrack;
    o.observer = &counter;
    o.undo_seam_blocking_on_block = false;  // one weave: the observer would see the retry too
    EXPECT_THROW(weave(doublet_cube(), o), WeaveError);
    if (backtrack) {
      EXPECT_GT(counter.undone, 0) << "failed shrinks are undone";
      EXPECT_EQ(counter.last_resorts, 1) << "then the first one's partial shrink is kept";
    } else {
      EXPECT_EQ(counter.undone, 0);
      EXPECT_EQ(counter.last_resorts, 0);
    }
    EXPECT_GT(counter.failures, 0);
  }
}

}  // namespace
}  // namespace stcweave::weave

namespace stcweave::weave {
namespace {

TEST(Observer, SeesWhatTheTraceRecords) {
  // An observer of one's own beside the trace: both are told about every event.
  Counter counter;
  WeaveOptions o;
  o.trace = true;
  o.observer = &counter;
  const WeaveResult r = weave(test::box_surface(2, 2, 3).surface, o);
  int rules = 0, selections = 0;
  for (const TraceEvent& e : r.trace) {
    rules += e.kind == TraceEvent::Kind::Rule ? 1 : 0;
    selections += e.kind == TraceEvent::Kind::Selection ? 1 : 0;
  }
  EXPECT_GT(rules, 0);
  EXPECT_EQ(counter.rules, rules);
  EXPECT_EQ(counter.selections, selections);
  EXPECT_EQ(r.complex.hexes.size(), 12u);
}

}  // namespace
}  // namespace stcweave::weave
