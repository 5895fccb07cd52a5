#pragma once
// Every small sphere quadrangulation reachable from the pseudo-double wheels (the cube is
// the smallest) by the two expansions of sphere_quads.hpp (a node split, +1 quad, in every
// way it applies; a quad cut into five, +4, on every quad), each map once (canonical_code:
// a map and its mirror image count twice), kept when it is a strong quadrangulation
// (tests/support/quadrangulations.hpp). Exhaustive over that closure, not a random sample.
// The simple quadrangulations of minimum degree 3 are known to be generated from the
// pseudo-double wheels by expansions of these two kinds (Brinkmann et al., "Generation of
// simple quadrangulations of the sphere", 2005); the counts the test pins can be compared
// with the published ones (OEIS A007022).
#include <cstddef>
#include <map>
#include <set>
#include <vector>

#include "sphere_quads.hpp"
#include "support/quadrangulations.hpp"

namespace stcweave::test {

/// The pseudo-double wheel with 2 k quads (k >= 3; k = 3 is the cube): a rim of 2 k nodes,
/// one hub on the even rim nodes and one on the odd ones, consistently oriented.
inline stc::QuadSurface pseudo_double_wheel(std::size_t k) {
  stc::QuadSurface s;
  const std::size_t rim = 2 * k;
  s.num_nodes = rim + 2;
  const NodeId x(rim);
  const NodeId y(rim + 1);
  const auto r = [rim](std::size_t i) { return NodeId((i + rim) % rim); };
  for (std::size_t i = 0; i < k; ++i) {
    s.quads.push_back({x, r(2 * i), r(2 * i + 1), r(2 * i + 2)});
    s.quads.push_back({y, r(2 * i + 1), r(2 * i), r(2 * i + rim - 1)});
  }
  return s;
}

/// For each count 6..`max_quads`, the distinct quadrangulations of the closure, in order of
/// discovery (deterministic).
inline std::map<std::size_t, std::vector<stc::QuadSurface>> sphere_closure(std::size_t max_quads) {
  std::map<std::size_t, std::vector<stc::QuadSurface>> by_count;
  std::map<std::size_t, std::set<std::vector<std::uint32_t>>> codes;
  const auto add = [&](stc::QuadSurface&& s) {
    const std::size_t n = s.quads.size();
    if (n > max_quads || !is_strong_quadrangulation(s)) return;
    if (codes[n].insert(canonical_code(s)).second) by_count[n].push_back(std::move(s));
  };
  for (std::size_t k = 3; 2 * k <= max_quads; ++k) add(pseudo_double_wheel(k));
  for (std::size_t n = 6; n <= max_quads; ++n) {
    // by_count[n] is complete once every smaller count has been expanded.
    const std::vector<stc::QuadSurface> level = by_count[n];
    for (const stc::QuadSurface& s : level) {
      if (n + 1 <= max_quads) {
        for (std::size_t v = 0; v < s.num_nodes; ++v) {
          std::size_t d = 0;
          for (const stc::Quad& q : s.quads) {
            for (NodeId m : q) d += m.index() == v ? 1 : 0;
          }
          for (std::size_t i = 0; i < d; ++i) {
            for (std::size_t m = 2; m + 2 <= d; ++m) {
              stc::QuadSurface t = s;
              if (split_node(t, v, i, m)) add(std::move(t));
            }
          }
        }
      }
      if (n + 4 <= max_quads) {
        for (std::size_t q = 0; q < s.quads.size(); ++q) {
          stc::QuadSurface t = s;
          cut_in_five(t, q);
          add(std::move(t));
        }
      }
    }
  }
  return by_count;
}

}  // namespace stcweave::test
