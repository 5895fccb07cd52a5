#include "side_parity.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "front_tree.hpp"

namespace stcweave::weave {

namespace {

constexpr std::size_t kWord = 64;

bool bit(std::span<const std::uint64_t> bits, std::size_t i) {
  return ((bits[i / kWord] >> (i % kWord)) & 1U) != 0U;
}

}  // namespace

SideNonconvex side_nonconvex(const Front& front, const FaceTable& table, const FrontLoops& loops,
                             const FrontComponents& components,
                             std::span<const std::size_t> component_faces,
                             const std::vector<char>& self_intersecting, double flat) {
  const std::size_t num_loops = loops.strips.size();
  SideNonconvex out;
  out.known.assign(num_loops, 0);
  out.has.assign(num_loops, {0, 0});
  if (num_loops == 0) return out;
  const std::size_t words = (num_loops + kWord - 1) / kWord;
  const std::size_t num_nodes = front.num_nodes();

  // Spheres: nodes - faces = 2 per component (every edge in two quads: E = 2F).
  std::vector<char> sphere(components.size.size(), 0);
  for (std::size_t c = 0; c < sphere.size(); ++c)
    sphere[c] = components.size[c] == component_faces[c] + 2 ? 1 : 0;

  // The nodes whose bit vectors are read: the ends of non-convex edges and one side-A corner
  // per loop (the corner at its first step's entry).
  std::vector<std::int64_t> offset(num_nodes, -1);
  std::size_t stored = 0;
  const auto need = [&](NodeId v) {
    if (offset[v.index()] < 0) offset[v.index()] = static_cast<std::int64_t>(stored++ * words);
  };
  for (std::size_t i = 0; i < front.face_capacity(); ++i) {
    const auto f = static_cast<FaceIndex>(i);
    if (!front.is_alive(f)) continue;
    const stc::Quad& n = table.nodes_of(f);
    for (int k = 0; k < 4; ++k) {
      if (table.angle_of(f, k) <= flat) continue;
      need(quad_at(n, k));
      need(quad_at(n, k + 1));
    }
  }
  std::vector<NodeId> corner_a(num_loops);
  for (std::size_t l = 0; l < num_loops; ++l) {
    const stc::StripStep& p = loops.strips[l].front();
    corner_a[l] = quad_at(table.nodes_of(face_of(p)), p.entry);
    need(corner_a[l]);
  }
  std::vector<std::uint64_t> pool(stored * words, 0);

  // One depth-first tree per component; `cur` holds the parities of the path to the node
  // being entered or left (a tree edge flips the bit of the loop that crosses it).
  std::vector<std::uint64_t> cur(words, 0);
  std::vector<char> visited(num_nodes, 0);
  const auto flip = [&](std::int32_t l) {
    const auto u = static_cast<std::size_t>(l);
    cur[u / kWord] ^= std::uint64_t{1} << (u % kWord);
  };
  const bool walked = walk_front_trees(
      front, table, loops, [&](NodeId v) { return visited[v.index()] != 0; },
      [&](NodeId v, std::int32_t l) {
        if (l >= 0) flip(l);
        visited[v.index()] = 1;
        if (offset[v.index()] >= 0)
          std::copy(cur.begin(), cur.end(),
                    pool.begin() + static_cast<std::ptrdiff_t>(offset[v.index()]));
      },
      [&](NodeId /*v*/, NodeId /*parent*/, std::int32_t l) {
        if (l >= 0) flip(l);
      });
  if (!walked) return out;  // an edge no loop crosses: not a front this reads; flood instead

  // Per sphere component, the loops some non-convex edge (not crossed by the loop) has its
  // ends on the odd side of (`odd`), or on the even side of (`even`).
  std::vector<std::vector<std::uint64_t>> odd(sphere.size()), even(sphere.size());
  for (std::size_t i = 0; i < front.face_capacity(); ++i) {
    const auto f = static_cast<FaceIndex>(i);
    if (!front.is_alive(f)) continue;
    const stc::Quad& n = table.nodes_of(f);
    const std::size_t c = components.component_of[n[0].index()];
    if (sphere[c] == 0) continue;
    for (int k = 0; k < 4; ++k) {
      if (table.angle_of(f, k) <= flat) continue;
      const std::uint64_t* a = pool.data() + offset[quad_at(n, k).index()];
      const std::uint64_t* b = pool.data() + offset[quad_at(n, k + 1).index()];
      if (odd[c].empty()) {
        odd[c].assign(words, 0);
        even[c].assign(words, 0);
      }
      for (std::size_t j = 0; j < words; ++j) {
        const std::uint64_t same = ~(a[j] ^ b[j]);  // every loop but the one crossing the edge
        odd[c][j] |= same & a[j];
        even[c][j] |= same & ~a[j];
      }
    }
  }
  for (std::size_t l = 0; l < num_loops; ++l) {
    const std::size_t c = components.component_of[corner_a[l].index()];
    if (self_intersecting[l] != 0 || sphere[c] == 0) continue;
    out.known[l] = 1;
    if (odd[c].empty()) continue;  // no non-convex edge on the component
    const std::span<const std::uint64_t> parity_a(pool.data() + offset[corner_a[l].index()], words);
    const bool a_odd = bit(parity_a, l);
    const bool any_odd = bit(odd[c], l), any_even = bit(even[c], l);
    out.has[l][0] = (a_odd ? any_odd : any_even) ? 1 : 0;
    out.has[l][1] = (a_odd ? any_even : any_odd) ? 1 : 0;
  }
  return out;
}

}  // namespace stcweave::weave
