#pragma once
// Small sphere quadrangulations for the weave tests, built in the test (no file): the
// 12-quad case of issue 11 and a seeded family grown from the cube by two expansions that
// keep a quadrangulation of the sphere (a vertex split, +1 quad; a quad cut into five, +4).
#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "stcweave/stc/loops.hpp"
#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::test {

/// The 12-quad sphere quadrangulation of issue 11 (three loops of length 8, each pair
/// crossing four times), 14 nodes, from its 1-based OBJ faces.
inline stc::QuadSurface issue11_twelve_quads() {
  const int faces[12][4] = {{4, 5, 2, 1},   {2, 9, 3, 1},    {3, 10, 4, 1},   {5, 11, 6, 2},
                            {6, 12, 7, 2},  {7, 13, 8, 2},   {8, 14, 9, 2},   {9, 14, 10, 3},
                            {10, 11, 5, 4}, {11, 10, 12, 6}, {12, 10, 13, 7}, {13, 10, 14, 8}};
  stc::QuadSurface s;
  s.num_nodes = 14;
  for (const auto& f : faces) {
    stc::Quad q{};
    for (std::size_t k = 0; k < 4; ++k) q[k] = NodeId(static_cast<std::size_t>(f[k] - 1));
    s.quads.push_back(q);
  }
  return s;
}

/// The cube's six quads, oriented consistently.
inline stc::QuadSurface cube_quads() {
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                           {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  stc::QuadSurface s;
  s.num_nodes = 8;
  for (const auto& f : faces) {
    stc::Quad q{};
    for (std::size_t k = 0; k < 4; ++k) q[k] = NodeId(static_cast<std::size_t>(f[k]));
    s.quads.push_back(q);
  }
  return s;
}

/// Splits node `v` into v and a new node: of the d quads around v, the `m` that follow its
/// neighbour number `i` (cyclically) move to the new node, and a new quad joins the two
/// along neighbours i and i+m. Needs 2 <= m <= d-2 (both keep at least three neighbours).
/// Returns false (nothing changed) when that does not hold.
inline bool split_node(stc::QuadSurface& s, std::size_t v, std::size_t i, std::size_t m) {
  // The quads around v in order: F_k = [v, a_k, x_k, b_k] with b_{k+1} = a_k.
  std::vector<std::pair<std::size_t, std::size_t>> at;  // (quad, position of v)
  for (std::size_t q = 0; q < s.quads.size(); ++q)
    for (std::size_t k = 0; k < 4; ++k)
      if (s.quads[q][k].index() == v) at.emplace_back(q, k);
  const std::size_t d = at.size();
  if (d < 4 || m < 2 || m + 2 > d) return false;
  const auto a_of = [&](std::pair<std::size_t, std::size_t> f) {
    return s.quads[f.first][(f.second + 1) % 4].index();
  };
  const auto b_of = [&](std::pair<std::size_t, std::size_t> f) {
    return s.quads[f.first][(f.second + 3) % 4].index();
  };
  std::vector<std::pair<std::size_t, std::size_t>> ring{at.front()};
  while (ring.size() < d) {
    const std::size_t a = a_of(ring.back());
    const auto next =
        std::find_if(at.begin(), at.end(), [&](const auto& f) { return b_of(f) == a; });
    if (next == at.end()) return false;
    ring.push_back(*next);
  }
  i %= d;
  const std::size_t ai = a_of(ring[i]);
  const std::size_t aj = a_of(ring[(i + m) % d]);
  const NodeId w(s.num_nodes++);
  for (std::size_t t = 1; t <= m; ++t) {
    const auto& f = ring[(i + t) % d];
    s.quads[f.first][f.second] = w;
  }
  s.quads.push_back({w, NodeId(ai), NodeId(v), NodeId(aj)});
  return true;
}

/// Cuts quad `q` into five: a smaller quad inside, joined to each side.
inline void cut_in_five(stc::QuadSurface& s, std::size_t q) {
  const stc::Quad o = s.quads[q];
  stc::Quad in{};
  for (auto& n : in) n = NodeId(s.num_nodes++);
  s.quads[q] = in;
  for (std::size_t k = 0; k < 4; ++k)
    s.quads.push_back({o[k], o[(k + 1) % 4], in[(k + 1) % 4], in[k]});
}

/// A canonical code of the quadrangulation (equal codes: the same map up to relabelling
/// and rotation; mirror images differ).
inline std::vector<std::uint32_t> canonical_code(const stc::QuadSurface& s) {
  std::map<std::pair<std::size_t, std::size_t>, std::pair<std::size_t, std::size_t>> edge;
  for (std::size_t q = 0; q < s.quads.size(); ++q)
    for (std::size_t k = 0; k < 4; ++k)
      edge[{s.quads[q][k].index(), s.quads[q][(k + 1) % 4].index()}] = {q, k};
  std::vector<std::uint32_t> best;
  for (std::size_t q0 = 0; q0 < s.quads.size(); ++q0) {
    for (std::size_t r0 = 0; r0 < 4; ++r0) {
      std::vector<std::uint32_t> code;
      std::vector<std::int64_t> label(s.num_nodes, -1);
      std::vector<bool> seen(s.quads.size(), false);
      std::vector<std::pair<std::size_t, std::size_t>> queue{{q0, r0}};
      seen[q0] = true;
      std::uint32_t next = 0;
      for (std::size_t h = 0; h < queue.size(); ++h) {
        const auto [q, r] = queue[h];
        for (std::size_t t = 0; t < 4; ++t) {
          const std::size_t n = s.quads[q][(r + t) % 4].index();
          if (label[n] < 0) label[n] = next++;
          code.push_back(static_cast<std::uint32_t>(label[n]));
        }
        for (std::size_t t = 0; t < 4; ++t) {
          const std::size_t k = (r + t) % 4;
          const auto g = edge.at({s.quads[q][(k + 1) % 4].index(), s.quads[q][k].index()});
          if (seen[g.first]) continue;
          seen[g.first] = true;
          queue.push_back(g);
        }
      }
      if (best.empty() || code < best) best = code;
    }
  }
  return best;
}

/// A seeded family: from the cube, random vertex splits and cuts in five until the count is
/// at least `quads`; kept when it has exactly `quads` quads and no self-intersecting loop,
/// each distinct map once. Deterministic (own draws from mt19937's raw output).
inline std::vector<stc::QuadSurface> seeded_family(std::size_t quads, std::size_t tries,
                                                   std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::set<std::vector<std::uint32_t>> codes;
  std::vector<stc::QuadSurface> out;
  for (std::size_t t = 0; t < tries; ++t) {
    stc::QuadSurface s = cube_quads();
    while (s.quads.size() < quads) {
      const bool five = s.quads.size() + 4 <= quads && rng() % 4 == 0;
      if (five) {
        cut_in_five(s, rng() % s.quads.size());
      } else {
        const std::size_t v = rng() % s.num_nodes;
        const std::size_t i = rng() % 8;
        const std::size_t m = 2 + rng() % 4;
        if (!split_node(s, v, i, m) && s.quads.size() + 4 <= quads)
          cut_in_five(s, rng() % s.quads.size());
        else if (s.quads.size() + 4 > quads && rng() % 64 == 0)
          break;
      }
    }
    if (s.quads.size() != quads) continue;
    if (stc::find_loops(s).num_self_intersecting() != 0) continue;
    if (codes.insert(canonical_code(s)).second) out.push_back(std::move(s));
  }
  return out;
}

}  // namespace stcweave::test
