/// \file
/// Pinched face pairs (docs/geometry.md "Repair"): two distinct quad faces of a hex complex
/// that share two consecutive edges at a node. No placement makes every hex around them
/// valid, so the positioning names them as topology instead of chasing them.
#include "position_pinch.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <tuple>
#include <vector>

namespace stcweave::primal {
namespace {

/// The 6 faces of a hex in VTK order (each a cycle of local nodes).
constexpr std::array<std::array<int, 4>, 6> kFaces = {
    {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};

}  // namespace

std::vector<PinchedFaces> pinched_faces(const stc::HexComplex& complex) {
  // Distinct faces (sorted node quadruples), each with its cycle.
  struct Face {
    std::array<std::int32_t, 4> key;
    std::array<std::int32_t, 4> cycle;
  };
  std::vector<Face> faces;
  faces.reserve(complex.hexes.size() * 6);
  for (const stc::Hex& h : complex.hexes) {
    for (const auto& f : kFaces) {
      Face face{};
      for (std::size_t i = 0; i < 4; ++i) face.cycle[i] = h[static_cast<std::size_t>(f[i])].value();
      face.key = face.cycle;
      std::sort(face.key.begin(), face.key.end());
      faces.push_back(face);
    }
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.key < b.key; });
  faces.erase(std::unique(faces.begin(), faces.end(),
                          [](const Face& a, const Face& b) { return a.key == b.key; }),
              faces.end());
  // Per face corner: (node, smaller neighbour, larger neighbour, face).
  std::vector<std::array<std::int32_t, 4>> corners;
  corners.reserve(faces.size() * 4);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& c = faces[f].cycle;
    for (std::size_t i = 0; i < 4; ++i) {
      const std::int32_t a = c[(i + 1) % 4];
      const std::int32_t b = c[(i + 3) % 4];
      corners.push_back({c[i], std::min(a, b), std::max(a, b), static_cast<std::int32_t>(f)});
    }
  }
  std::sort(corners.begin(), corners.end());
  std::vector<PinchedFaces> out;
  for (std::size_t i = 0; i + 1 < corners.size(); ++i) {
    const auto& x = corners[i];
    const auto& y = corners[i + 1];
    if (x[0] != y[0] || x[1] != y[1] || x[2] != y[2]) continue;
    PinchedFaces p;
    p.node = NodeId(x[0]);
    p.a = NodeId(x[1]);
    p.b = NodeId(x[2]);
    p.first = faces[static_cast<std::size_t>(x[3])].cycle;
    p.second = faces[static_cast<std::size_t>(y[3])].cycle;
    out.push_back(p);
  }
  return out;
}

}  // namespace stcweave::primal
