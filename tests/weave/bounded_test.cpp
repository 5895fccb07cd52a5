// The reliable selection's branch and bound (weave/src/select/bounded.hpp) against every
// weight computed: the weave without a trace or an observer takes the bounded path, and with
// `check` the driver ranks every candidate again at every selection and throws when the two
// first candidates differ; with an observer attached the driver computes every weight. Both
// weaves must build the same complex with the same counters.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/kernel.hpp"
#include "stcweave/weave/weave.hpp"
#include "support/counting_observer.hpp"
#include "support/same_weave.hpp"
#include "support/shapes.hpp"

namespace stcweave::weave {
namespace {

struct Shape {
  std::string name;
  stc::QuadSurface surface;
};

std::vector<Shape> shapes() {
  std::vector<Shape> out;
  out.push_back({"box 5x4x3", test::box_surface(5, 4, 3).surface});
  out.push_back({"box 7x2x6", test::box_surface(7, 2, 6).surface});
  out.push_back({"l-block", test::voxel_surface(test::lblock_cells()).surface});
  out.push_back({"rhombic dodecahedron", test::rhombic_dodecahedron().surface});
  out.push_back(
      {"ogrid cylinder",
       test::boundary_of(test::extruded_hexes(test::ogrid_disk(), {0.0, 0.5, 1.0})).surface});
  return out;
}

/// The outcome of a weave: its result, or the message of the weave error it ended with.
struct Outcome {
  WeaveResult result;
  std::string error;
};

Outcome run(const stc::QuadSurface& surface, const WeaveOptions& options) {
  Outcome out;
  try {
    out.result = weave(surface, options);
  } catch (const WeaveError& e) {
    out.error = e.what();
  }
  return out;
}

TEST(BoundedSelection, FailedShrinksFallBackToEveryWeight) {
  // A ring (genus 1) is not weavable: shrinks fail, and after the first candidate of a
  // bounded selection fails the driver ranks every candidate and tries them in that order.
  const stc::QuadSurface ring = test::voxel_surface(test::ring_cells()).surface;
  for (const bool backtrack : {true, false}) {
    WeaveOptions bounded;
    bounded.check = true;
    bounded.backtrack = backtrack;
    bounded.max_rules = 300;
    test::CountingObserver counting;
    WeaveOptions full = bounded;
    full.observer = &counting;
    const Outcome a = run(ring, bounded);
    const Outcome b = run(ring, full);
    EXPECT_GT(counting.failed, 0U) << "backtrack " << backtrack << ": no shrink failed";
    EXPECT_EQ(a.error, b.error) << "backtrack " << backtrack;
    if (a.error.empty() && b.error.empty()) test::expect_same_weave(a.result, b.result, "ring");
  }
}

TEST(BoundedSelection, ChoosesAsEveryWeightAtEverySelection) {
  for (const Shape& s : shapes()) {
    WeaveOptions bounded;
    bounded.check = true;  // the driver compares with the full ranking at every selection
    WeaveResult a;
    ASSERT_NO_THROW(a = weave(s.surface, bounded)) << s.name;
    test::CountingObserver counting;
    WeaveOptions full;
    full.observer = &counting;
    const WeaveResult b = weave(s.surface, full);
    test::expect_same_weave(a, b, s.name);
    EXPECT_EQ(counting.selections, b.stats.shrinks + b.stats.failed_shrinks) << s.name;
    EXPECT_GT(a.stats.selections, 1U) << s.name << ": more than one selection to compare";
  }
}

TEST(BoundedSelection, SameWithoutBacktracking) {
  for (const Shape& s : shapes()) {
    WeaveOptions bounded;
    bounded.check = true;
    bounded.backtrack = false;
    test::CountingObserver counting;
    WeaveOptions full = bounded;
    full.check = false;
    full.observer = &counting;
    WeaveResult a;
    WeaveResult b;
    bool a_failed = false;
    bool b_failed = false;
    try {
      a = weave(s.surface, bounded);
    } catch (const WeaveError&) {
      a_failed = true;
    }
    try {
      b = weave(s.surface, full);
    } catch (const WeaveError&) {
      b_failed = true;
    }
    ASSERT_EQ(a_failed, b_failed) << s.name;
    if (!a_failed) test::expect_same_weave(a, b, s.name);
  }
}

}  // namespace
}  // namespace stcweave::weave
