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
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
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

/// The directed edges of `s` (edge k of quad q is 4 q + k, from corner k to corner k + 1) and,
/// for each, the reverse edge (or -1). With `n` = s.num_nodes, `at[a * n + b]` is a -> b.
struct EdgeTwins {
  std::vector<std::int32_t> twin;
  bool ok = true;  ///< every directed edge once and its reverse present
};

inline EdgeTwins edge_twins(const stc::QuadSurface& s) {
  const std::size_t n = s.num_nodes;
  std::vector<std::int32_t> at(n * n, -1);
  EdgeTwins t;
  t.twin.assign(4 * s.quads.size(), -1);
  for (std::size_t q = 0; q < s.quads.size(); ++q) {
    for (std::size_t k = 0; k < 4; ++k) {
      const std::size_t a = s.quads[q][k].index();
      const std::size_t b = s.quads[q][(k + 1) % 4].index();
      std::int32_t& e = at[a * n + b];
      if (e >= 0) t.ok = false;
      e = static_cast<std::int32_t>(4 * q + k);
    }
  }
  for (std::size_t q = 0; q < s.quads.size(); ++q) {
    for (std::size_t k = 0; k < 4; ++k) {
      const std::size_t a = s.quads[q][k].index();
      const std::size_t b = s.quads[q][(k + 1) % 4].index();
      t.twin[4 * q + k] = at[b * n + a];
      if (t.twin[4 * q + k] < 0) t.ok = false;
    }
  }
  return t;
}

/// The same test as `is_strong_quadrangulation` (tests/support), with arrays instead of maps
/// (the closure at 20 quads asks it about two million times): four distinct nodes per quad, no
/// two quads on the same four nodes, every edge used once each way, every used node in at least
/// three quads, no two quads sharing two edges.
inline bool is_strong_fast(const stc::QuadSurface& s) {
  std::vector<std::array<std::uint32_t, 4>> keys;
  keys.reserve(s.quads.size());
  std::vector<int> valence(s.num_nodes, 0);
  for (const stc::Quad& q : s.quads) {
    std::array<std::uint32_t, 4> k{};
    for (std::size_t i = 0; i < 4; ++i) {
      k[i] = static_cast<std::uint32_t>(q[i].index());
      ++valence[q[i].index()];
    }
    std::sort(k.begin(), k.end());
    if (std::adjacent_find(k.begin(), k.end()) != k.end()) return false;
    keys.push_back(k);
  }
  std::sort(keys.begin(), keys.end());
  if (std::adjacent_find(keys.begin(), keys.end()) != keys.end()) return false;
  for (const int v : valence)
    if (v != 0 && v < 3) return false;
  const EdgeTwins t = edge_twins(s);
  if (!t.ok) return false;
  for (std::size_t q = 0; q < s.quads.size(); ++q) {
    for (std::size_t i = 0; i < 4; ++i) {
      const std::int32_t oi = t.twin[4 * q + i] / 4;
      for (std::size_t j = i + 1; j < 4; ++j)
        if (t.twin[4 * q + j] / 4 == oi) return false;
    }
  }
  return true;
}

/// `canonical_code` (sphere_quads.hpp) computed faster, with the same equivalence (equal codes
/// exactly when the maps are equal up to relabelling and rotation): arrays instead of maps, and
/// a breadth-first labelling abandoned as soon as its prefix exceeds the best one so far. The
/// codes differ from `canonical_code`'s but identify the same maps. Needs `s` strong.
inline std::vector<std::uint32_t> fast_code(const stc::QuadSurface& s) {
  const EdgeTwins t = edge_twins(s);
  const std::size_t nq = s.quads.size();
  std::vector<std::uint32_t> best;
  std::vector<std::uint32_t> code;
  std::vector<std::int32_t> label(s.num_nodes);
  std::vector<char> seen(nq);
  std::vector<std::pair<std::size_t, std::size_t>> queue;
  code.reserve(4 * nq);
  queue.reserve(nq);
  for (std::size_t q0 = 0; q0 < nq; ++q0) {
    for (std::size_t r0 = 0; r0 < 4; ++r0) {
      std::fill(label.begin(), label.end(), -1);
      std::fill(seen.begin(), seen.end(), 0);
      code.clear();
      queue.assign(1, {q0, r0});
      seen[q0] = 1;
      std::uint32_t next = 0;
      bool less = best.empty();  // the prefix so far is already below best's
      bool worse = false;
      for (std::size_t h = 0; h < queue.size() && !worse; ++h) {
        const auto [q, r] = queue[h];
        for (std::size_t u = 0; u < 4; ++u) {
          const std::size_t n = s.quads[q][(r + u) % 4].index();
          if (label[n] < 0) label[n] = static_cast<std::int32_t>(next++);
          const auto c = static_cast<std::uint32_t>(label[n]);
          if (!less) {
            const std::uint32_t b = best[code.size()];
            if (c > b) {
              worse = true;
              break;
            }
            less = c < b;
          }
          code.push_back(c);
        }
        for (std::size_t u = 0; u < 4 && !worse; ++u) {
          const std::size_t k = (r + u) % 4;
          const auto g = static_cast<std::size_t>(t.twin[4 * q + k]);
          if (seen[g / 4] != 0) continue;
          seen[g / 4] = 1;
          queue.emplace_back(g / 4, g % 4);
        }
      }
      if (!worse && less) best = code;
    }
  }
  return best;
}

/// For each count 6..`max_quads`, the distinct quadrangulations of the closure, in order of
/// discovery (deterministic).
inline std::map<std::size_t, std::vector<stc::QuadSurface>> sphere_closure(std::size_t max_quads) {
  std::map<std::size_t, std::vector<stc::QuadSurface>> by_count;
  std::map<std::size_t, std::set<std::vector<std::uint32_t>>> codes;
  const auto add = [&](stc::QuadSurface&& s) {
    const std::size_t n = s.quads.size();
    if (n > max_quads || !is_strong_fast(s)) return;
    if (codes[n].insert(fast_code(s)).second) by_count[n].push_back(std::move(s));
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
