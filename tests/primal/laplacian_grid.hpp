#pragma once
/// \file
/// Graph Laplacians for the tests of primal/src/laplacian_solve.hpp and of the untangling's
/// preconditioned L-BFGS: an edge list's Laplacian, and the interior of a lattice with its
/// boundary fixed, with a right-hand side whose solution is a known linear field.

#include <algorithm>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "../../primal/src/laplacian_solve.hpp"

namespace stcweave::primal::test_grid {

/// The Laplacian of an edge list over `free` free nodes; `fixed_ties[i]` edges of node i go to
/// fixed nodes (they count in its degree only).
inline FreeLaplacian laplacian_of(std::size_t free,
                                  const std::set<std::pair<std::int32_t, std::int32_t>>& edges,
                                  const std::vector<int>& fixed_ties) {
  FreeLaplacian l;
  l.degree.assign(free, 0.0);
  for (std::size_t i = 0; i < free; ++i) l.degree[i] = fixed_ties[i];
  std::vector<std::vector<std::int32_t>> rows(free);
  for (const auto& [a, b] : edges) {
    rows[static_cast<std::size_t>(a)].push_back(b);
    rows[static_cast<std::size_t>(b)].push_back(a);
    l.degree[static_cast<std::size_t>(a)] += 1.0;
    l.degree[static_cast<std::size_t>(b)] += 1.0;
  }
  l.row_start.assign(free + 1, 0);
  for (std::size_t i = 0; i < free; ++i) {
    std::sort(rows[i].begin(), rows[i].end());
    l.row_start[i + 1] = l.row_start[i] + rows[i].size();
    l.neighbour.insert(l.neighbour.end(), rows[i].begin(), rows[i].end());
  }
  return l;
}

/// The interior nodes of the (k+1)^3 lattice with the boundary fixed, and the right-hand side
/// for boundary values f: the answer at the interior nodes is f when f is linear.
struct Grid {
  FreeLaplacian l;
  std::vector<Row3> b;
  std::vector<Row3> exact;
};

inline Grid grid(int k) {
  const int m = k - 1;  // interior nodes per axis
  const auto id = [m](int i, int j, int l) {
    return static_cast<std::int32_t>((i - 1) + m * ((j - 1) + m * (l - 1)));
  };
  const auto f = [](int i, int j, int l) {
    return Row3{1.0 * i + 0.5 * j, 2.0 * j - 0.25 * l, 0.75 * i + 1.5 * l};
  };
  const auto free_node = [k](int i, int j, int l) {
    return i > 0 && i < k && j > 0 && j < k && l > 0 && l < k;
  };
  const auto n =
      static_cast<std::size_t>(m) * static_cast<std::size_t>(m) * static_cast<std::size_t>(m);
  std::set<std::pair<std::int32_t, std::int32_t>> edges;
  std::vector<int> ties(n, 0);
  Grid g;
  g.b.assign(n, Row3{0.0, 0.0, 0.0});
  g.exact.assign(n, Row3{0.0, 0.0, 0.0});
  for (int l = 1; l < k; ++l) {
    for (int j = 1; j < k; ++j) {
      for (int i = 1; i < k; ++i) {
        const auto me = static_cast<std::size_t>(id(i, j, l));
        g.exact[me] = f(i, j, l);
        const int nb[6][3] = {{i - 1, j, l}, {i + 1, j, l}, {i, j - 1, l},
                              {i, j + 1, l}, {i, j, l - 1}, {i, j, l + 1}};
        for (const auto& q : nb) {
          if (free_node(q[0], q[1], q[2])) {
            const std::int32_t other = id(q[0], q[1], q[2]);
            if (static_cast<std::int32_t>(me) < other)
              edges.emplace(static_cast<std::int32_t>(me), other);
          } else {
            ++ties[me];
            const Row3 v = f(q[0], q[1], q[2]);
            for (std::size_t c = 0; c < 3; ++c) g.b[me][c] += v[c];
          }
        }
      }
    }
  }
  g.l = laplacian_of(n, edges, ties);
  return g;
}

}  // namespace stcweave::primal::test_grid
