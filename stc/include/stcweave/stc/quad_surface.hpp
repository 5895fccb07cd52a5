#pragma once
/// \file
/// The two pure-topology containers of the project: a quad surface and a hex complex.
/// Neither knows coordinates (those live in `primal`).

#include <array>
#include <cstddef>
#include <vector>

#include "stcweave/stc/ids.hpp"

namespace stcweave::stc {

/// A quad: four node ids in cyclic order. Side i is the edge (q[i], q[(i+1)%4]).
using Quad = std::array<NodeId, 4>;

/// A hexahedron in VTK order: bottom face 0-1-2-3 whose right-hand normal points into the
/// hex, then the top face 4-5-6-7 with node i+4 above node i.
using Hex = std::array<NodeId, 8>;

/// The six faces of a VTK-ordered hex, each listed so that its right-hand normal points out
/// of a positively oriented hex.
inline constexpr std::array<std::array<int, 4>, 6> kHexFaces = {
    {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};

/// The twelve edges of a VTK-ordered hex.
inline constexpr std::array<std::array<int, 2>, 12> kHexEdges = {{{0, 1},
                                                                  {1, 2},
                                                                  {2, 3},
                                                                  {3, 0},
                                                                  {4, 5},
                                                                  {5, 6},
                                                                  {6, 7},
                                                                  {7, 4},
                                                                  {0, 4},
                                                                  {1, 5},
                                                                  {2, 6},
                                                                  {3, 7}}};

/// kHexLocalEdge[a][b]: the local edge (index into kHexEdges) joining local nodes a and b of a
/// hex, or -1 when they are not joined by an edge.
inline constexpr std::array<std::array<int, 8>, 8> kHexLocalEdge = [] {
  std::array<std::array<int, 8>, 8> t{};
  for (auto& row : t)
    for (int& v : row) v = -1;
  for (int k = 0; k < 12; ++k) {
    const auto& e = kHexEdges[static_cast<std::size_t>(k)];
    t[static_cast<std::size_t>(e[0])][static_cast<std::size_t>(e[1])] = k;
    t[static_cast<std::size_t>(e[1])][static_cast<std::size_t>(e[0])] = k;
  }
  return t;
}();

/// A quad surface: quads over nodes `0 .. num_nodes-1`. Nothing is assumed about it
/// (closedness, manifoldness, orientation are what `diagnose` finds out); functions that
/// need more say so in their `\pre`.
struct QuadSurface {
  std::vector<Quad> quads;
  std::size_t num_nodes = 0;

  [[nodiscard]] std::size_t num_quads() const { return quads.size(); }
  [[nodiscard]] const Quad& quad(QuadId q) const { return quads[q.index()]; }
};

/// A hex complex: hexes (VTK order) over nodes `0 .. num_nodes-1`.
struct HexComplex {
  std::vector<Hex> hexes;
  std::size_t num_nodes = 0;

  [[nodiscard]] std::size_t num_hexes() const { return hexes.size(); }
  [[nodiscard]] const Hex& hex(HexId h) const { return hexes[h.index()]; }
};

/// The quad `q` traversed the other way round (same first node).
[[nodiscard]] inline Quad reversed(const Quad& q) {
  return {q[0], q[3], q[2], q[1]};
}

/// Face `f` (0..5) of hex `h`, oriented outward for a positively oriented hex.
[[nodiscard]] inline Quad hex_face(const Hex& h, int f) {
  const auto& idx = kHexFaces[static_cast<std::size_t>(f)];
  return {h[static_cast<std::size_t>(idx[0])], h[static_cast<std::size_t>(idx[1])],
          h[static_cast<std::size_t>(idx[2])], h[static_cast<std::size_t>(idx[3])]};
}

}  // namespace stcweave::stc
