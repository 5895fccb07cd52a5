#pragma once
/// \file
/// A hand-built hex complex with one pinched face pair (docs/geometry.md "Pinched faces"):
/// the 8 hexes around one node whose vertex link has two edges between the same two link
/// vertices. Shared by the stc (validate) and primal (unpinch) tests.

#include <Eigen/Core>
#include <array>
#include <utility>
#include <vector>

#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::test {

struct PinchedStar {
  stc::HexComplex complex;
  std::vector<std::array<double, 3>> points;  ///< one per node, a start for positioning
};

/// The hexes around one node n whose vertex link is a sphere triangulation with two
/// distinct edges between the link vertices a and b (the faces n-a-m1-b and n-a-m2-b):
/// each link triangle (p, q, r) is the hex corner at n with edge neighbours p, q, r.
/// Nodes: 6 link vertices (a, b, c, d, e, f = 0..5), 12 link edges (6..17), 8 triangle
/// centres (18..25), n = 26 (the only interior node, numbered last as the pipeline does).
inline PinchedStar pinched_star() {
  constexpr int a = 0, b = 1, c = 2, d = 3, e = 4, f = 5;
  // Edges of the link, the two a-b edges first (ab1 = 0, ab2 = 1).
  const std::array<std::pair<int, int>, 12> edges = {{{a, b},
                                                      {a, b},
                                                      {a, c},
                                                      {b, c},
                                                      {c, d},
                                                      {a, d},
                                                      {b, d},
                                                      {a, e},
                                                      {b, e},
                                                      {e, f},
                                                      {a, f},
                                                      {b, f}}};
  // Triangles, counter-clockwise seen from outside, with the edge of each side (p-q, q-r,
  // r-p). D1 (around +y) between ab1 and ab2 holds c, d; D2 (around -y) holds e, f.
  struct Triangle {
    std::array<int, 3> v;
    std::array<int, 3> e;
  };
  const std::array<Triangle, 8> triangles = {{{{a, b, c}, {0, 3, 2}},
                                              {{a, c, d}, {2, 4, 5}},
                                              {{c, b, d}, {3, 6, 4}},
                                              {{a, d, b}, {5, 6, 1}},
                                              {{a, b, e}, {1, 8, 7}},
                                              {{a, e, f}, {7, 9, 10}},
                                              {{e, b, f}, {8, 11, 9}},
                                              {{a, f, b}, {10, 11, 0}}}};
  const std::array<Eigen::RowVector3d, 6> dir = {
      Eigen::RowVector3d(0, 0, 1),    Eigen::RowVector3d(0, 0, -1),
      Eigen::RowVector3d(0, 1, 0.4),  Eigen::RowVector3d(0.2, 1, -0.4),
      Eigen::RowVector3d(0, -1, 0.4), Eigen::RowVector3d(-0.2, -1, -0.4)};
  constexpr int n = 26;
  PinchedStar m;
  std::vector<Eigen::RowVector3d> p(27, Eigen::RowVector3d::Zero());
  for (int v = 0; v < 6; ++v)
    p[static_cast<std::size_t>(v)] = dir[static_cast<std::size_t>(v)].normalized();
  for (int k = 0; k < 12; ++k) {
    const auto [x, y] = edges[static_cast<std::size_t>(k)];
    Eigen::RowVector3d mid = p[static_cast<std::size_t>(x)] + p[static_cast<std::size_t>(y)];
    if (k < 2) mid = Eigen::RowVector3d(k == 0 ? 1.0 : -1.0, 0, 0);
    p[static_cast<std::size_t>(6 + k)] = 1.4 * mid.normalized();
  }
  for (int t = 0; t < 8; ++t) {
    Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
    for (const int v : triangles[static_cast<std::size_t>(t)].v)
      centre += p[static_cast<std::size_t>(v)];
    p[static_cast<std::size_t>(18 + t)] = 1.7 * centre.normalized();
  }
  m.complex.num_nodes = 27;
  for (int t = 0; t < 8; ++t) {
    const Triangle& tr = triangles[static_cast<std::size_t>(t)];
    const auto node = [](int i) { return NodeId(i); };  // NOLINT
    // Corner 0 = n with neighbours 1 = p, 3 = q, 4 = r (VTK order).
    m.complex.hexes.push_back({node(n), node(tr.v[0]), node(6 + tr.e[0]), node(tr.v[1]),
                               node(tr.v[2]), node(6 + tr.e[2]), node(18 + t), node(6 + tr.e[1])});
  }
  for (const Eigen::RowVector3d& x : p) m.points.push_back({x(0), x(1), x(2)});
  return m;
}

}  // namespace stcweave::test
