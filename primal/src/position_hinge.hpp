#pragma once
/// \file
/// Hinge untangling of a small mesh (internal to primal/src; used by the local untangling's
/// last phase, position_clusters.cpp; docs/geometry.md "Local untangling").

#include <cstddef>
#include <vector>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::primal {

/// What `hinge_untangle` did.
struct HingeOutcome {
  std::size_t iterations = 0;  ///< L-BFGS iterations over every stage
  std::size_t stages = 0;      ///< smoothing stages run
};

/// Moves the free nodes of `mesh` (`fixed[v]` false) to lower
///   sum over terms t of  sqrt((q_t - beta)^2 + delta^2) - (q_t - beta),
/// a smoothed 2 max(0, beta - q_t), for delta = `first_delta`, 0.3 times that, ... while
/// above 1e-6 (one L-BFGS run each, from where the last ended; from 0.1: 10 stages). The
/// terms are the 8 corners and the centre (principal axes, as `hex_scaled_jacobian` reads
/// them) of every hex with a free node, a corner only when one of its four nodes is free; q
/// is the mean-ratio measure of the corner's three edge vectors (or of the three axes),
/// 3 sqrt(3) det / (|a|^2 + |b|^2 + |c|^2)^(3/2), in
/// [-1, 1]. Only terms below `beta` pull; q, unlike the scaled Jacobian, stays smooth when
/// an edge gets short, where max-min formulations stall (docs/geometry.md).
/// At most `max_iterations` L-BFGS iterations in all (each stage at most 5000). A stage whose
/// line search fails keeps the better of its start and where it stopped. Deterministic.
HingeOutcome hinge_untangle(HexMesh& mesh, const std::vector<bool>& fixed, double beta,
                            std::size_t max_iterations, double first_delta = 0.1);

}  // namespace stcweave::primal
