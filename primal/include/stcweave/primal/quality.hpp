#pragma once
/// \file
/// Hex quality (Verdict definitions). The scaled Jacobian of a hex is the minimum, over its
/// 8 corners and its centre, of the determinant of the three unit edge vectors (at a corner:
/// its three edges, at the centre: the three principal axes). 1 for a cube, <= 0 for an
/// inverted corner. Like Verdict, the centre term is included.

#include <cstddef>
#include <vector>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::primal {

/// Verdict scaled Jacobian of hex `h` (8 corners + centre). A zero-length edge gives 0.
[[nodiscard]] double hex_scaled_jacobian(const Points& points, const stc::Hex& h);

/// Scaled Jacobian over the 8 corners only (no centre term).
[[nodiscard]] double hex_corner_scaled_jacobian(const Points& points, const stc::Hex& h);

struct QualitySummary {
  std::size_t hexes = 0;
  double min_scaled_jacobian = 0.0;
  double mean_scaled_jacobian = 0.0;
  std::size_t inverted = 0;     ///< scaled Jacobian <= 0
  std::size_t below_0_2 = 0;    ///< scaled Jacobian < 0.2
  std::vector<double> per_hex;  ///< scaled Jacobian of every hex
};

[[nodiscard]] QualitySummary summarize_quality(const HexMesh& mesh);

}  // namespace stcweave::primal
