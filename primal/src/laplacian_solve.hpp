#pragma once
/// \file
/// The solve behind the harmonic placement (recover.cpp): L x = b for the uniform graph
/// Laplacian of the hex edges restricted to the free nodes, three right-hand sides (x, y, z)
/// at once. Conjugate gradients preconditioned by one V-cycle of an aggregation multigrid
/// (docs/geometry.md, "The harmonic solve"): the iteration count then stays nearly flat as
/// the mesh grows, where Jacobi's grows with the mesh's diameter.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace stcweave::primal {

/// The graph Laplacian of the hex edges restricted to the free nodes, stored as neighbour
/// lists only: row i is degree[i] on the diagonal and -1 for each free neighbour. Every
/// off-diagonal entry is -1, so no value array is needed.
struct FreeLaplacian {
  std::vector<double> degree;           ///< edge count of free node i (fixed neighbours too)
  std::vector<std::size_t> row_start;   ///< CSR offsets into `neighbour`, size free + 1
  std::vector<std::int32_t> neighbour;  ///< free neighbours, as free indices, ascending
};

/// The Laplacian of `edges` (pairs a < b in increasing order, as `stc::unique_edges` gives
/// them) over the nodes v with `slot[v] >= 0`, row `slot[v]` of `free` rows. Slots must
/// increase with the node index, so that each row's neighbours come out ascending (row r first
/// receives the smaller neighbours of the edges (a, r), then the larger ones of (r, b)). An
/// edge to a node without a slot counts in the degree only.
FreeLaplacian edge_laplacian(const std::vector<std::pair<std::int32_t, std::int32_t>>& edges,
                             const std::vector<std::int32_t>& slot, std::size_t free);

using Row3 = std::array<double, 3>;

struct SolveOutcome {
  std::array<std::size_t, 3> iterations{0, 0, 0};
  Row3 relative_residual{0.0, 0.0, 0.0};
  std::array<bool, 3> converged{false, false, false};
  std::size_t levels = 1;  ///< levels of the multigrid (1: Jacobi preconditioning)
};

/// How the preconditioner is built.
struct LaplacianSolveOptions {
  /// Below this many unknowns a level is solved directly (dense Cholesky) and not coarsened.
  std::size_t coarsest = 400;
  /// Below this many free nodes the solve uses Jacobi preconditioning (no hierarchy): its
  /// cost is small there, and it keeps the placements (and the shape phase that starts from
  /// them, which is sensitive to rounding on symmetric meshes) those of earlier releases.
  std::size_t multigrid_from = 100000;
  /// The coarse correction is scaled by this (plain aggregation under-corrects).
  double coarse_scale = 1.8;
};

/// Solves the three systems L x_c = b_c to a relative residual below `tolerance` each,
/// starting from `x`. Each column stops on its own and is then left as it is, so the result
/// is that of three separate solves. Sequential sums in a fixed order: deterministic.
SolveOutcome solve_laplacian(const FreeLaplacian& l, const std::vector<Row3>& b,
                             std::vector<Row3>& x, double tolerance, std::size_t max_iterations,
                             const LaplacianSolveOptions& options = {});

/// One V-cycle of the multigrid above as an operator z = M^-1 r, symmetric positive definite,
/// for preconditioning other solvers (the untangling's L-BFGS, position_lbfgs.hpp). The
/// hierarchy is built at every size (below `coarsest` unknowns it is one level, solved
/// exactly); when coarsening stalls before a level small enough to factor, Jacobi (r / degree).
/// Sequential: deterministic.
class LaplacianPreconditioner {
 public:
  explicit LaplacianPreconditioner(const FreeLaplacian& l,
                                   const LaplacianSolveOptions& options = {});
  ~LaplacianPreconditioner();
  LaplacianPreconditioner(const LaplacianPreconditioner&) = delete;
  LaplacianPreconditioner& operator=(const LaplacianPreconditioner&) = delete;
  LaplacianPreconditioner(LaplacianPreconditioner&&) noexcept;
  LaplacianPreconditioner& operator=(LaplacianPreconditioner&&) noexcept;

  /// z = M^-1 r, three columns (x, y, z) per free node; `r` and `z` have one row per free node.
  void apply(const std::vector<Row3>& r, std::vector<Row3>& z);
  /// Unknowns (free nodes).
  [[nodiscard]] std::size_t size() const;
  /// Levels of the hierarchy (0: Jacobi).
  [[nodiscard]] std::size_t levels() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace stcweave::primal
