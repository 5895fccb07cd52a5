#include "stcweave/primal/position.hpp"

#include <LBFGS.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <thread>
#include <tuple>
#include <utility>

#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/bucket_sort.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/hex_complex.hpp"

#include "laplacian_solve.hpp"
#include "node_hexes.hpp"
#include "position_lbfgs.hpp"
#include "position_pinch.hpp"

namespace stcweave::primal {
namespace {

using HexNodes = std::array<std::int32_t, 8>;

/// The regulariser chi(eps, d) = (d + sqrt(eps^2 + d^2)) / 2, written without
/// cancellation for d <= 0.
double chi(double eps, double d) {
  const double r = std::sqrt(eps * eps + d * d);
  return d > 0.0 ? 0.5 * (d + r) : 0.5 * eps * eps / (r - d);
}

/// d chi / d d.
double chi_derivative(double eps, double d) {
  return 0.5 + 0.5 * d / std::sqrt(eps * eps + d * d);
}

/// Energy of one corner with edge columns e (already divided by h); adds its gradient with
/// respect to the columns to g when g is not null. Returns +inf when not finite.
double corner_energy(const std::array<Eigen::Vector3d, 3>& e, double eps, double theta,
                     std::array<Eigen::Vector3d, 3>* g) {
  const std::array<Eigen::Vector3d, 3> cof = {e[1].cross(e[2]), e[2].cross(e[0]), e[0].cross(e[1])};
  const double d = e[0].dot(cof[0]);
  const double c = chi(eps, d);
  const double c23 = std::cbrt(c * c);
  const double frob = e[0].squaredNorm() + e[1].squaredNorm() + e[2].squaredNorm();
  const double f = frob / c23;
  const double vol = (1.0 + d * d) / c;
  const double energy = (1.0 - theta) * f + theta * vol;
  if (!std::isfinite(energy)) return std::numeric_limits<double>::infinity();
  if (g != nullptr) {
    const double dc = chi_derivative(eps, d);
    const double a = (1.0 - theta) * 2.0 / c23;
    const double b = -(1.0 - theta) * (2.0 / 3.0) * f * dc / c + theta * (2.0 * d - vol * dc) / c;
    for (std::size_t k = 0; k < 3; ++k) (*g)[k] = a * e[k] + b * cof[k];
  }
  return energy;
}

/// The Hessian of one corner's energy with respect to its edge columns (9 x 9, blocks in
/// the order e0, e1, e2), before any projection. Same notation as `corner_energy`:
/// E = (1 - theta) F phi(d) + theta psi(d) with F = |J|^2, phi = chi^(-2/3),
/// psi = (1 + d^2) / chi, so that
/// H = (1 - theta) [2 phi I + 2 phi' (e gd^T + gd e^T)] + E_dd gd gd^T + E_d D2d,
/// where gd = grad det = the cofactor columns, D2d the (constant-pattern) second
/// derivative of the determinant, E_d = (1 - theta) F phi' + theta psi' and
/// E_dd = (1 - theta) F phi'' + theta psi''.
Eigen::Matrix<double, 9, 9> corner_hessian(const std::array<Eigen::Vector3d, 3>& e, double eps,
                                           double theta) {
  const std::array<Eigen::Vector3d, 3> cof = {e[1].cross(e[2]), e[2].cross(e[0]), e[0].cross(e[1])};
  const double d = e[0].dot(cof[0]);
  const double r = std::sqrt(eps * eps + d * d);
  const double c = chi(eps, d);
  const double c1 = chi_derivative(eps, d);
  const double c2 = 0.5 * eps * eps / (r * r * r);
  const double frob = e[0].squaredNorm() + e[1].squaredNorm() + e[2].squaredNorm();
  const double phi = 1.0 / std::cbrt(c * c);
  const double phi1 = -(2.0 / 3.0) * phi / c * c1;
  const double phi2 = (10.0 / 9.0) * phi / (c * c) * c1 * c1 - (2.0 / 3.0) * phi / c * c2;
  const double q = 1.0 + d * d;
  const double psi1 = 2.0 * d / c - q * c1 / (c * c);
  const double psi2 =
      2.0 / c - 4.0 * d * c1 / (c * c) + 2.0 * q * c1 * c1 / (c * c * c) - q * c2 / (c * c);
  const double ed = (1.0 - theta) * frob * phi1 + theta * psi1;
  const double edd = (1.0 - theta) * frob * phi2 + theta * psi2;
  Eigen::Matrix<double, 9, 1> ev;
  Eigen::Matrix<double, 9, 1> gd;
  for (Eigen::Index k = 0; k < 3; ++k) {
    ev.segment<3>(3 * k) = e[static_cast<std::size_t>(k)];
    gd.segment<3>(3 * k) = cof[static_cast<std::size_t>(k)];
  }
  Eigen::Matrix<double, 9, 9> hess =
      (2.0 * (1.0 - theta) * phi) * Eigen::Matrix<double, 9, 9>::Identity();
  hess.noalias() += (2.0 * (1.0 - theta) * phi1) * (ev * gd.transpose() + gd * ev.transpose());
  hess.noalias() += edd * gd * gd.transpose();
  // d2 det / d e_a d e_b = -[e_c]x times the sign of the permutation (a, b, c): block (0, 1)
  // is -[e2]x, block (0, 2) is +[e1]x, block (1, 2) is -[e0]x, and the lower blocks their
  // transposes.
  const auto cross = [](const Eigen::Vector3d& v) {
    Eigen::Matrix3d m;
    m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
    return m;
  };
  const Eigen::Matrix3d x0 = ed * cross(e[0]);
  const Eigen::Matrix3d x1 = ed * cross(e[1]);
  const Eigen::Matrix3d x2 = ed * cross(e[2]);
  hess.block<3, 3>(0, 3) -= x2;
  hess.block<3, 3>(3, 0) += x2;
  hess.block<3, 3>(0, 6) += x1;
  hess.block<3, 3>(6, 0) -= x1;
  hess.block<3, 3>(3, 6) -= x0;
  hess.block<3, 3>(6, 3) += x0;
  return hess;
}

/// `m` with its negative eigenvalues set to zero (the nearest positive semi-definite
/// matrix in the Frobenius norm).
Eigen::Matrix<double, 9, 9> project_psd(const Eigen::Matrix<double, 9, 9>& m) {
  // Most corners of an untangled mesh are already definite: a Cholesky says so for a
  // fraction of the cost of the eigen-decomposition.
  if (Eigen::LLT<Eigen::Matrix<double, 9, 9>>(m).info() == Eigen::Success) return m;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(m);
  const Eigen::Matrix<double, 9, 1> lambda = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

/// Runs fn(first, last) on `parts` contiguous slices of 0 .. count-1, slice 0 on the calling
/// thread.
template <typename Fn>
void run_sliced(std::size_t count, std::size_t parts, const Fn& fn) {
  if (parts <= 1) {
    fn(std::size_t{0}, count);
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(parts - 1);
  for (std::size_t t = 1; t < parts; ++t)
    pool.emplace_back([&fn, t, parts, count] { fn(count * t / parts, count * (t + 1) / parts); });
  fn(std::size_t{0}, count / parts);
  for (std::thread& th : pool) th.join();
}

/// The state shared by the energy evaluations: hexes, which corners count, which nodes
/// move, and positions in units of h around the mesh's centre.
class Problem {
 public:
  Problem(const HexMesh& mesh, const std::vector<bool>& fixed, double theta)
      : theta_(theta), num_nodes_(static_cast<std::size_t>(mesh.points.rows())) {
    hexes_.reserve(mesh.complex.hexes.size());
    for (const stc::Hex& h : mesh.complex.hexes) {
      HexNodes n{};
      for (std::size_t i = 0; i < 8; ++i) {
        if (!h[i].is_valid() || h[i].index() >= num_nodes_) {
          throw InvalidInput("position_nodes: hex h" + std::to_string(hexes_.size()) +
                             " names node " + h[i].str() + " out of range (" +
                             std::to_string(num_nodes_) + " nodes)");
        }
        n[i] = h[i].value();
      }
      hexes_.push_back(n);
    }
    active_.assign(hexes_.size(), 0xFF);
    slot_.assign(num_nodes_, -1);
    std::vector<bool> used(num_nodes_, false);
    for (const HexNodes& n : hexes_)
      for (std::int32_t v : n) used[static_cast<std::size_t>(v)] = true;
    for (std::size_t v = 0; v < num_nodes_; ++v) {
      if (!fixed[v] && used[v]) {
        slot_[v] = static_cast<std::int32_t>(free_.size());
        free_.push_back(static_cast<std::int32_t>(v));
      }
    }
    // Node -> (hex, local) incidences of the free nodes, in increasing (hex, local) order,
    // so that gradients are gathered in a fixed order.
    offsets_.assign(free_.size() + 1, 0);
    for (const HexNodes& n : hexes_) {
      for (std::int32_t v : n)
        if (slot_[static_cast<std::size_t>(v)] >= 0)
          ++offsets_[slot_[static_cast<std::size_t>(v)] + 1];
    }
    for (std::size_t i = 0; i < free_.size(); ++i) offsets_[i + 1] += offsets_[i];
    incidences_.resize(offsets_.back());
    std::vector<std::size_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (std::size_t hx = 0; hx < hexes_.size(); ++hx) {
      for (std::size_t i = 0; i < 8; ++i) {
        const std::int32_t s = slot_[static_cast<std::size_t>(hexes_[hx][i])];
        if (s >= 0) incidences_[fill[static_cast<std::size_t>(s)]++] = hx * 8 + i;
      }
    }
    // Scale: the edge of a cube of the mean hex volume. The total volume only depends on
    // the boundary faces (interior faces cancel), so h does not change while optimising.
    centre_ = mesh.points.colwise().mean().transpose();
    double volume = 0.0;
    for (const HexNodes& n : hexes_) {
      for (const auto& face : stc::kHexFaces) {
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int k : face) c += point(mesh, n[static_cast<std::size_t>(k)]);
        c *= 0.25;
        for (std::size_t k = 0; k < 4; ++k) {
          const Eigen::Vector3d a = point(mesh, n[static_cast<std::size_t>(face[k])]);
          const Eigen::Vector3d b = point(mesh, n[static_cast<std::size_t>(face[(k + 1) % 4])]);
          volume += a.dot(b.cross(c)) / 6.0;
        }
      }
    }
    volume_ = volume;
    h_ = hexes_.empty() || volume <= 0.0 ? 1.0
                                         : std::cbrt(volume / static_cast<double>(hexes_.size()));
    positions_.resize(static_cast<Eigen::Index>(num_nodes_), 3);
    for (std::size_t v = 0; v < num_nodes_; ++v)
      positions_.row(static_cast<Eigen::Index>(v)) =
          (point(mesh, static_cast<std::int32_t>(v)) - centre_).transpose() / h_;
    hex_grad_.resize(hexes_.size() * 24);
    hex_energy_.resize(hexes_.size());
  }

  [[nodiscard]] double volume() const { return volume_; }
  /// The length unit h of the scaled positions.
  [[nodiscard]] double scale() const { return h_; }
  /// Whether hex_hessian projects each corner's Hessian (true but for inspection).
  void set_projection(bool project) { project_ = project; }
  [[nodiscard]] const std::vector<std::int32_t>& free_nodes() const { return free_; }
  [[nodiscard]] std::size_t num_free() const { return free_.size(); }
  [[nodiscard]] const std::vector<HexNodes>& hexes() const { return hexes_; }
  void deactivate(std::size_t hex, int corner) {
    active_[hex] = static_cast<std::uint8_t>(active_[hex] & ~(1u << corner));
  }
  void set_epsilon(double eps) { eps_ = eps; }

  /// The free coordinates (3 per free node, scaled).
  [[nodiscard]] Eigen::VectorXd variables() const {
    Eigen::VectorXd x(static_cast<Eigen::Index>(3 * free_.size()));
    for (std::size_t i = 0; i < free_.size(); ++i)
      for (int c = 0; c < 3; ++c) x(static_cast<Eigen::Index>(3 * i) + c) = positions_(free_[i], c);
    return x;
  }

  void set_variables(const Eigen::VectorXd& x) {
    for (std::size_t i = 0; i < free_.size(); ++i)
      for (int c = 0; c < 3; ++c) positions_(free_[i], c) = x(static_cast<Eigen::Index>(3 * i) + c);
  }

  /// Writes the free nodes back into `mesh` (fixed nodes are not touched).
  void store(HexMesh& mesh) const {
    for (std::int32_t v : free_)
      mesh.points.row(v) = (positions_.row(v).transpose() * h_ + centre_).transpose();
  }

  /// Smallest determinant over the active corners and the number of active corners <= 0.
  [[nodiscard]] std::pair<double, std::size_t> min_determinant() const {
    double best = std::numeric_limits<double>::infinity();
    std::size_t bad = 0;
    for (std::size_t hx = 0; hx < hexes_.size(); ++hx) {
      for (std::size_t k = 0; k < 8; ++k) {
        if ((active_[hx] & (1u << k)) == 0) continue;
        const std::array<Eigen::Vector3d, 3> e = edges(hx, k);
        const double d = e[0].dot(e[1].cross(e[2]));
        best = std::min(best, d);
        if (d <= 0.0) ++bad;
      }
    }
    return {best, bad};
  }

  /// Energy at the current positions; with `grad` (size 3 * free nodes) its gradient.
  /// Large meshes are evaluated by `threads_` threads on contiguous hex ranges; every hex
  /// writes its own energy and gradient slots, which are then summed in a fixed order, so
  /// the result does not depend on the number of threads.
  double evaluate(Eigen::VectorXd* grad) {
    const std::size_t m = hexes_.size();
    run_sliced(m, parts(m), [this, grad](std::size_t first, std::size_t last) {
      evaluate_hexes(first, last, grad != nullptr);
    });
    double total = 0.0;
    for (double e : hex_energy_) total += e;
    if (grad != nullptr) {
      grad->setZero(static_cast<Eigen::Index>(3 * free_.size()));
      for (std::size_t i = 0; i < free_.size(); ++i) {
        for (std::size_t q = offsets_[i]; q < offsets_[i + 1]; ++q) {
          const double* hg = hex_grad_.data() + 3 * incidences_[q];
          for (int a = 0; a < 3; ++a) (*grad)(static_cast<Eigen::Index>(3 * i) + a) += hg[a];
        }
      }
    }
    return std::isfinite(total) ? total : std::numeric_limits<double>::infinity();
  }

  void set_threads(std::size_t threads) { threads_ = std::max<std::size_t>(1, threads); }
  /// Threads for a job over `count` hexes.
  [[nodiscard]] std::size_t parts(std::size_t count) const {
    return count >= kParallelHexes ? threads_ : 1;
  }

  /// Free index of node v, or -1 when v is fixed.
  [[nodiscard]] std::int32_t slot(std::int32_t v) const {
    return slot_[static_cast<std::size_t>(v)];
  }

  /// The Hessian of hex hx's energy with respect to its 8 nodes (24 x 24, node-major, x y z),
  /// each corner's part projected to positive semi-definite before it is added.
  void hex_hessian(std::size_t hx, Eigen::Matrix<double, 24, 24>& out) const {
    out.setZero();
    for (std::size_t k = 0; k < 8; ++k) {
      if ((active_[hx] & (1u << k)) == 0) continue;
      const Eigen::Matrix<double, 9, 9> raw = corner_hessian(edges(hx, k), eps_, theta_);
      const Eigen::Matrix<double, 9, 9> h = project_ ? project_psd(raw) : raw;
      // e_j = x_{c[j+1]} - x_{c[0]}: the corner node's rows are minus the sum of the others.
      const auto& c = kHexCorners[k];
      Eigen::Matrix<double, 12, 12> lifted;
      const Eigen::Matrix<double, 9, 3> col_sum =
          h.block<9, 3>(0, 0) + h.block<9, 3>(0, 3) + h.block<9, 3>(0, 6);
      lifted.block<9, 9>(3, 3) = h;
      lifted.block<9, 3>(3, 0) = -col_sum;
      lifted.block<3, 9>(0, 3) = -col_sum.transpose();
      lifted.block<3, 3>(0, 0) =
          col_sum.block<3, 3>(0, 0) + col_sum.block<3, 3>(3, 0) + col_sum.block<3, 3>(6, 0);
      for (std::size_t a = 0; a < 4; ++a) {
        for (std::size_t b = 0; b < 4; ++b)
          out.block<3, 3>(3 * Eigen::Index{c[a]}, 3 * Eigen::Index{c[b]}) += lifted.block<3, 3>(
              static_cast<Eigen::Index>(3 * a), static_cast<Eigen::Index>(3 * b));
      }
    }
  }

 private:
  /// Below this many hexes one thread evaluates (thread start-up would dominate). 1024 (was
  /// 4096): measured faster on every mesh of 1,400 to 2,600 hexes tried (the positioning of
  /// `pmp/fandisk_quads`, 2,501 hexes, 59 -> 51 s; docs/geometry.md), and the same results.
  static constexpr std::size_t kParallelHexes = 1024;

  /// Energy (and gradient slots) of hexes first .. last-1.
  void evaluate_hexes(std::size_t first, std::size_t last, bool with_gradient) {
    std::array<Eigen::Vector3d, 3> g;
    for (std::size_t hx = first; hx < last; ++hx) {
      double* hg = hex_grad_.data() + hx * 24;
      if (with_gradient) std::fill(hg, hg + 24, 0.0);
      double energy = 0.0;
      for (std::size_t k = 0; k < 8; ++k) {
        if ((active_[hx] & (1u << k)) == 0) continue;
        const std::array<Eigen::Vector3d, 3> e = edges(hx, k);
        energy += corner_energy(e, eps_, theta_, with_gradient ? &g : nullptr);
        if (!with_gradient) continue;
        const auto& c = kHexCorners[k];
        for (std::size_t j = 0; j < 3; ++j) {
          double* to = hg + 3 * static_cast<std::size_t>(c[j + 1]);
          double* from = hg + 3 * static_cast<std::size_t>(c[0]);
          for (int a = 0; a < 3; ++a) {
            to[a] += g[j](a);
            from[a] -= g[j](a);
          }
        }
      }
      hex_energy_[hx] = energy;
    }
  }

  static Eigen::Vector3d point(const HexMesh& mesh, std::int32_t v) {
    return mesh.points.row(v).transpose();
  }

  [[nodiscard]] std::array<Eigen::Vector3d, 3> edges(std::size_t hx, std::size_t k) const {
    const HexNodes& n = hexes_[hx];
    const auto& c = kHexCorners[k];
    const Eigen::Vector3d o = positions_.row(n[static_cast<std::size_t>(c[0])]).transpose();
    return {positions_.row(n[static_cast<std::size_t>(c[1])]).transpose() - o,
            positions_.row(n[static_cast<std::size_t>(c[2])]).transpose() - o,
            positions_.row(n[static_cast<std::size_t>(c[3])]).transpose() - o};
  }

  double theta_;
  double eps_ = 1.0;
  std::size_t num_nodes_;
  std::vector<HexNodes> hexes_;
  std::vector<std::uint8_t> active_;
  std::vector<std::int32_t> slot_;  ///< node -> free index or -1
  std::vector<std::int32_t> free_;  ///< free index -> node
  std::vector<std::size_t> offsets_;
  std::vector<std::size_t> incidences_;  ///< hex * 8 + local
  Eigen::Vector3d centre_;
  double h_ = 1.0;
  bool project_ = true;
  double volume_ = 0.0;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> positions_;
  std::vector<double> hex_grad_;
  std::vector<double> hex_energy_;
  std::size_t threads_ = 1;
};

/// Two local nodes of a hex that no corner couples (the body diagonals).
bool body_diagonal(std::size_t a, std::size_t b) {
  return (a ^ b) == 6;
}

/// Projected Newton steps: the sparse system of the per-corner projected Hessians in the
/// free coordinates (lower triangle), its pattern and symbolic factorisation built once.
class NewtonSolver {
 public:
  using Matrix = Eigen::SparseMatrix<double>;

  explicit NewtonSolver(const Problem& problem) {
    const auto n = static_cast<Eigen::Index>(3 * problem.num_free());
    // The coupled free-node pairs (row >= column) first, each once: triplets per hex would
    // take about 5 kB a hex.
    std::vector<std::uint64_t> pairs;
    for (const HexNodes& h : problem.hexes()) {
      for (std::size_t a = 0; a < 8; ++a) {
        for (std::size_t b = 0; b < 8; ++b) {
          const std::int32_t sa = problem.slot(h[a]);
          const std::int32_t sb = problem.slot(h[b]);
          if (sa < 0 || sb < 0 || sa < sb || body_diagonal(a, b)) continue;
          pairs.push_back(static_cast<std::uint64_t>(sa) << 32 | static_cast<std::uint32_t>(sb));
        }
      }
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(pairs.size() * 9);
    for (const std::uint64_t key : pairs) {
      const auto sa = static_cast<Eigen::Index>(key >> 32);
      const auto sb = static_cast<Eigen::Index>(key & 0xFFFFFFFFu);
      for (Eigen::Index i = 0; i < 3; ++i)
        for (Eigen::Index j = 0; j < 3; ++j)
          if (sa > sb || i >= j) triplets.emplace_back(3 * sa + i, 3 * sb + j, 0.0);
    }
    matrix_.resize(n, n);
    matrix_.setFromTriplets(triplets.begin(), triplets.end());
    matrix_.makeCompressed();
  }

  /// The lower triangle of the Hessian at the problem's current positions.
  const Matrix& hessian(const Problem& problem) {
    assemble(problem);
    return matrix_;
  }

  /// Solves K dir = -grad with K the projected Hessian at the problem's current positions,
  /// shifted by a multiple of its mean diagonal. False when no shift up to 1e-2 gives a
  /// positive definite factorisation and a descent direction.
  bool direction(const Problem& problem, const Eigen::VectorXd& grad, Eigen::VectorXd& dir) {
    assemble(problem);
    double mean_diagonal = 0.0;
    for (Eigen::Index k = 0; k < matrix_.cols(); ++k) mean_diagonal += matrix_.coeff(k, k);
    mean_diagonal /= static_cast<double>(std::max<Eigen::Index>(1, matrix_.cols()));
    // Projection can leave K singular where every corner around a node is flat in some
    // direction. The LLT factorisation fails on a pivot <= 0 (an LDLT would not), and then
    // a larger shift is tried; so is one when rounding makes the direction uphill.
    if (!analysed_) {
      solver_.analyzePattern(matrix_);
      analysed_ = true;
    }
    for (double shift = 1e-8; shift <= 1e-2; shift *= 100.0) {
      solver_.setShift(shift * mean_diagonal);
      solver_.factorize(matrix_);
      if (solver_.info() != Eigen::Success) continue;
      dir = solver_.solve(-grad);
      if (dir.allFinite() && grad.dot(dir) < 0.0) return true;
    }
    return false;
  }

 private:
  static constexpr std::size_t kChunk = 4096;

  /// Fills the values of `matrix_`: hex blocks computed in parallel chunk by chunk, then
  /// added in hex order (so the sum does not depend on the thread count).
  void assemble(const Problem& problem) {
    std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
    const std::size_t m = problem.hexes().size();
    blocks_.resize(std::min(m, kChunk));
    for (std::size_t first = 0; first < m; first += kChunk) {
      const std::size_t count = std::min(kChunk, m - first);
      run_sliced(count, problem.parts(count), [&](std::size_t lo, std::size_t hi) {
        for (std::size_t i = lo; i < hi; ++i) problem.hex_hessian(first + i, blocks_[i]);
      });
      for (std::size_t i = 0; i < count; ++i)
        scatter(problem, problem.hexes()[first + i], blocks_[i]);
    }
  }

  void scatter(const Problem& problem, const HexNodes& h,
               const Eigen::Matrix<double, 24, 24>& block) {
    for (std::size_t a = 0; a < 8; ++a) {
      for (std::size_t b = 0; b < 8; ++b) {
        const std::int32_t sa = problem.slot(h[a]);
        const std::int32_t sb = problem.slot(h[b]);
        if (sa < 0 || sb < 0 || sa < sb || body_diagonal(a, b)) continue;
        for (int j = 0; j < 3; ++j) {
          // Column 3 sb + j holds rows 3 sa + i contiguously (sorted rows).
          const Eigen::Index col = 3 * sb + j;
          const Eigen::Index begin = matrix_.outerIndexPtr()[col];
          const Eigen::Index end = matrix_.outerIndexPtr()[col + 1];
          const int first_row = sa > sb ? 0 : j;
          const int* rows = matrix_.innerIndexPtr();
          const Eigen::Index at =
              std::lower_bound(rows + begin, rows + end, 3 * sa + first_row) - rows;
          for (int i = first_row; i < 3; ++i)
            matrix_.valuePtr()[at + i - first_row] +=
                block(static_cast<Eigen::Index>(3 * a) + i, static_cast<Eigen::Index>(3 * b) + j);
        }
      }
    }
  }

  Matrix matrix_;
  Eigen::SimplicialLLT<Matrix> solver_;
  bool analysed_ = false;
  std::vector<Eigen::Matrix<double, 24, 24>> blocks_;
};

/// The graph Laplacian of the hex edges over the free nodes of `problem`, in its variable
/// order (the preconditioner of position_lbfgs.hpp). Its free nodes are ascending, as
/// `edge_laplacian` needs.
FreeLaplacian free_laplacian(const HexMesh& mesh, const Problem& problem) {
  const std::vector<std::int32_t>& free = problem.free_nodes();
  std::vector<std::int32_t> slot(static_cast<std::size_t>(mesh.points.rows()), -1);
  for (std::size_t i = 0; i < free.size(); ++i)
    slot[static_cast<std::size_t>(free[i])] = static_cast<std::int32_t>(i);
  return edge_laplacian(stc::unique_edges(mesh.complex), slot, free.size());
}

/// The functor LBFGS++ minimises; it remembers the best point it evaluated, so that a
/// line-search failure never loses progress.
class Objective {
 public:
  explicit Objective(Problem& problem) : problem_(problem) {}

  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    problem_.set_variables(x);
    const double f = problem_.evaluate(&grad);
    if (!std::isfinite(f)) {
      grad.setZero(x.size());
      return std::numeric_limits<double>::infinity();
    }
    if (f < best_energy_) {
      best_energy_ = f;
      best_ = x;
    }
    return f;
  }

  void reset(const Eigen::VectorXd& x, double f) {
    best_ = x;
    best_energy_ = f;
  }
  [[nodiscard]] const Eigen::VectorXd& best() const { return best_; }
  [[nodiscard]] double best_energy() const { return best_energy_; }

 private:
  Problem& problem_;
  Eigen::VectorXd best_;
  double best_energy_ = std::numeric_limits<double>::infinity();
};

/// The harmonic placement of the hex-edge graph with the nodes of `fixed` held: each free
/// node at the mean of its edge neighbours (uniform weights). The graph Laplacian restricted
/// to the free nodes is SPD when every free component touches a fixed node; one sparse
/// Cholesky factorisation, three solves.
Points harmonic_start(const HexMesh& mesh, const std::vector<bool>& fixed) {
  const auto n = static_cast<std::size_t>(mesh.points.rows());
  std::vector<std::int32_t> slot(n, -1);
  std::vector<bool> used(n, false);
  for (const stc::Hex& h : mesh.complex.hexes)
    for (const NodeId v : h) used[v.index()] = true;
  std::int32_t free = 0;
  for (std::size_t v = 0; v < n; ++v)
    if (!fixed[v] && used[v]) slot[v] = free++;
  Points out = mesh.points;
  if (free == 0) return out;
  const auto edges = stc::unique_edges(mesh.complex);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(edges.size() * 4);
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(free, 3);
  for (const auto& [a, b] : edges) {
    const std::int32_t sa = slot[static_cast<std::size_t>(a)];
    const std::int32_t sb = slot[static_cast<std::size_t>(b)];
    if (sa >= 0) triplets.emplace_back(sa, sa, 1.0);
    if (sb >= 0) triplets.emplace_back(sb, sb, 1.0);
    if (sa >= 0 && sb >= 0) {
      triplets.emplace_back(sa, sb, -1.0);
      triplets.emplace_back(sb, sa, -1.0);
    } else if (sa >= 0) {
      rhs.row(sa) += mesh.points.row(b);
    } else if (sb >= 0) {
      rhs.row(sb) += mesh.points.row(a);
    }
  }
  Eigen::SparseMatrix<double> laplacian(free, free);
  laplacian.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(laplacian);
  if (solver.info() != Eigen::Success) {
    throw SolverError(
        "position_nodes: the harmonic start cannot be factorised: some free nodes are not "
        "connected by hex edges to any fixed node");
  }
  const Eigen::MatrixX3d x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite())
    throw SolverError("position_nodes: the harmonic start failed to solve");
  for (std::size_t v = 0; v < n; ++v)
    if (slot[v] >= 0) out.row(static_cast<Eigen::Index>(v)) = x.row(slot[v]);
  return out;
}

/// Projected Newton steps from x with Armijo backtracking, until the gradient norm is
/// below the tolerance, a step gains less than 1e-10 (relative), no descent step is found
/// or `max_newton_steps` are done. Returns the energy at the final x and the steps taken.
std::pair<double, int> newton_descent(Problem& problem, NewtonSolver& newton,
                                      const PositionOptions& options, Eigen::VectorXd& x,
                                      PositionReport& report) {
  int taken = 0;
  Eigen::VectorXd grad;
  Eigen::VectorXd dir;
  problem.set_variables(x);
  double energy = problem.evaluate(&grad);
  for (int step = 0; step < options.max_newton_steps; ++step) {
    if (!std::isfinite(energy) || grad.norm() <= options.gradient_tolerance) break;
    if (!newton.direction(problem, grad, dir)) break;
    const double slope = grad.dot(dir);
    if (!(slope < 0.0)) break;
    double t = 1.0;
    double trial = std::numeric_limits<double>::infinity();
    Eigen::VectorXd next;
    bool accepted = false;
    for (int k = 0; k < 40 && !accepted; ++k) {
      next = x + t * dir;
      problem.set_variables(next);
      trial = problem.evaluate(nullptr);
      accepted = trial <= energy + 1e-4 * t * slope;
      if (!accepted) t *= 0.5;
    }
    if (!accepted) break;
    ++report.newton_steps;
    ++taken;
    const double gain = (energy - trial) / std::max(1.0, std::abs(trial));
    x = next;
    problem.set_variables(x);
    energy = problem.evaluate(&grad);
    if (gain < 1e-10) break;
  }
  problem.set_variables(x);
  return {energy, taken};
}

}  // namespace

double winslow_corner_energy(const Eigen::Matrix3d& edges, double eps, double theta,
                             Eigen::Matrix<double, 9, 1>* gradient,
                             Eigen::Matrix<double, 9, 9>* hessian) {
  const std::array<Eigen::Vector3d, 3> e = {edges.col(0), edges.col(1), edges.col(2)};
  std::array<Eigen::Vector3d, 3> g;
  const double energy = corner_energy(e, eps, theta, gradient != nullptr ? &g : nullptr);
  if (!std::isfinite(energy)) {  // eps = 0 and det <= 0: no derivative either
    if (gradient != nullptr) gradient->setConstant(std::numeric_limits<double>::quiet_NaN());
    if (hessian != nullptr) hessian->setConstant(std::numeric_limits<double>::quiet_NaN());
    return energy;
  }
  if (gradient != nullptr)
    for (Eigen::Index k = 0; k < 3; ++k)
      gradient->segment<3>(3 * k) = g[static_cast<std::size_t>(k)];
  if (hessian != nullptr) *hessian = corner_hessian(e, eps, theta);
  return energy;
}

PositionEnergy position_energy(const HexMesh& mesh, const std::vector<bool>& fixed, double eps,
                               double theta, EnergyDerivatives derivatives, int threads) {
  if (fixed.size() != static_cast<std::size_t>(mesh.points.rows())) {
    throw InvalidInput("position_energy: the fixed mask has " + std::to_string(fixed.size()) +
                       " entries for " + std::to_string(mesh.points.rows()) + " nodes");
  }
  Problem problem(mesh, fixed, theta);
  problem.set_threads(threads > 0 ? static_cast<std::size_t>(threads)
                                  : std::max(1u, std::thread::hardware_concurrency()));
  problem.set_epsilon(eps);
  PositionEnergy out;
  for (const std::int32_t v : problem.free_nodes()) out.free_nodes.emplace_back(v);
  const double h = problem.scale();
  // Scaled positions are (p - centre) / h: a derivative in model units divides by h per order.
  out.energy = problem.evaluate(&out.gradient);
  out.gradient /= h;
  if (derivatives != EnergyDerivatives::Gradient && problem.num_free() > 0) {
    problem.set_projection(derivatives == EnergyDerivatives::ProjectedHessian);
    NewtonSolver assembler(problem);
    const Eigen::SparseMatrix<double>& lower = assembler.hessian(problem);
    out.hessian = lower.selfadjointView<Eigen::Lower>();
    out.hessian /= h * h;
  }
  return out;
}

std::vector<ImpossibleCorner> impossible_corners(const HexMesh& mesh,
                                                 const std::vector<bool>& fixed) {
  if (fixed.size() != static_cast<std::size_t>(mesh.points.rows()))
    throw InvalidInput("impossible_corners: the fixed mask has " + std::to_string(fixed.size()) +
                       " entries for " + std::to_string(mesh.points.rows()) + " nodes");
  std::vector<ImpossibleCorner> out;
  // Corner key: the corner node and its three edge neighbours sorted; the parity of the
  // sorting permutation is the orientation of the corner.
  struct Seen {
    std::array<std::int32_t, 4> key;  ///< corner node, then its sorted edge neighbours
    std::size_t hex_parity;           ///< hex * 2 + orientation parity
    int corner;
  };
  std::vector<Seen> seen;
  seen.reserve(mesh.complex.hexes.size() * 8);
  for (std::size_t hx = 0; hx < mesh.complex.hexes.size(); ++hx) {
    const stc::Hex& h = mesh.complex.hexes[hx];
    const std::array<double, 8> dets = hex_corner_jacobians(mesh.points, h);
    for (int k = 0; k < 8; ++k) {
      const auto& c = kHexCorners[static_cast<std::size_t>(k)];
      std::array<std::int32_t, 3> nb = {h[static_cast<std::size_t>(c[1])].value(),
                                        h[static_cast<std::size_t>(c[2])].value(),
                                        h[static_cast<std::size_t>(c[3])].value()};
      bool all_fixed = fixed[h[static_cast<std::size_t>(c[0])].index()];
      for (std::int32_t v : nb) all_fixed = all_fixed && fixed[static_cast<std::size_t>(v)];
      if (all_fixed && dets[static_cast<std::size_t>(k)] <= 0.0) {
        out.push_back({HexId(hx), k, HexId::invalid(),
                       "corner " + h[static_cast<std::size_t>(c[0])].str() + " of h" +
                           std::to_string(hx) + " has its four nodes fixed and det " +
                           std::to_string(dets[static_cast<std::size_t>(k)]) + " <= 0"});
        continue;
      }
      int parity = 0;
      for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b)
          if (nb[static_cast<std::size_t>(a)] > nb[static_cast<std::size_t>(b)]) parity ^= 1;
      std::sort(nb.begin(), nb.end());
      seen.push_back({{h[static_cast<std::size_t>(c[0])].value(), nb[0], nb[1], nb[2]},
                      hx * 2 + static_cast<std::size_t>(parity),
                      k});
    }
  }
  // Sorting groups equal corners (a sort of a flat vector: much faster than a map on
  // meshes of 10^5 hexes; bucketed by the corner node, then sorted within each).
  stc::sort_by_smallest_node(
      seen, [](const Seen& x) { return x.key[0]; },
      [](const Seen& x, const Seen& y) {
        return std::tie(x.key, x.hex_parity, x.corner) < std::tie(y.key, y.hex_parity, y.corner);
      });
  for (std::size_t first = 0, last = 0; first < seen.size(); first = last) {
    while (last < seen.size() && seen[last].key == seen[first].key) ++last;
    const auto& key = seen[first].key;
    for (std::size_t i = first; i < last; ++i) {
      for (std::size_t j = i + 1; j < last; ++j) {
        if ((seen[i].hex_parity & 1u) == (seen[j].hex_parity & 1u)) continue;
        const HexId a(seen[i].hex_parity / 2), b(seen[j].hex_parity / 2);
        const std::string msg = "hexes " + a.str() + " and " + b.str() + " share corner n" +
                                std::to_string(key[0]) + " with the same three edges (n" +
                                std::to_string(key[1]) + ", n" + std::to_string(key[2]) + ", n" +
                                std::to_string(key[3]) +
                                ") in opposite orientations: one of them is inverted there";
        out.push_back({a, seen[i].corner, b, msg});
        out.push_back({b, seen[j].corner, a, msg});
      }
    }
  }
  std::sort(out.begin(), out.end(), [](const ImpossibleCorner& x, const ImpossibleCorner& y) {
    return std::pair(x.hex, x.corner) < std::pair(y.hex, y.corner);
  });
  out.erase(std::unique(out.begin(), out.end(),
                        [](const ImpossibleCorner& x, const ImpossibleCorner& y) {
                          return x.hex == y.hex && x.corner == y.corner;
                        }),
            out.end());
  return out;
}

namespace {

/// The local max-min sweeps of the shape phase (see `improve_shape`).
/// What the local max-min sweeps work for: raising the worst hexes of a valid mesh towards
/// `shape_target` (the shape phase), or raising inverted hexes above 0 (`repair_inverted`).
enum class LocalGoal { Shape, Repair };

/// Marks the free nodes within `rings` hex rings of the hexes with scaled Jacobian <= 0:
/// ring 0 is their own nodes, ring r + 1 adds the nodes of every hex around ring r.
std::vector<bool> near_inverted(const std::vector<stc::Hex>& hexes, const std::vector<double>& sj,
                                const NodeHexes& incidence, const std::vector<bool>& fixed,
                                int rings) {
  std::vector<bool> in(fixed.size(), false);
  std::vector<std::size_t> layer;
  for (std::size_t h = 0; h < hexes.size(); ++h) {
    if (!(sj[h] <= 0.0)) continue;
    for (const NodeId v : hexes[h]) {
      if (in[v.index()]) continue;
      in[v.index()] = true;
      layer.push_back(v.index());
    }
  }
  for (int r = 0; r < rings; ++r) {
    std::vector<std::size_t> next;
    for (const std::size_t v : layer) {
      for (std::size_t i = incidence.start[v]; i < incidence.start[v + 1]; ++i) {
        for (const NodeId w : hexes[incidence.around[i]]) {
          if (in[w.index()]) continue;
          in[w.index()] = true;
          next.push_back(w.index());
        }
      }
    }
    layer = std::move(next);
  }
  for (std::size_t v = 0; v < in.size(); ++v) in[v] = in[v] && !fixed[v];
  return in;
}

ShapeReport local_shape(HexMesh& mesh, const std::vector<bool>& fixed,
                        const PositionOptions& options, LocalGoal goal = LocalGoal::Shape) {
  const bool repair = goal == LocalGoal::Repair;
  ShapeReport report;
  const std::size_t n = static_cast<std::size_t>(mesh.points.rows());
  if (fixed.size() != n)
    throw InvalidInput("improve_shape: the fixed mask has " + std::to_string(fixed.size()) +
                       " entries for " + std::to_string(n) + " nodes");
  const std::vector<stc::Hex>& hexes = mesh.complex.hexes;
  std::vector<double> sj(hexes.size());
  for (std::size_t h = 0; h < hexes.size(); ++h) sj[h] = hex_scaled_jacobian(mesh.points, hexes[h]);
  const auto summary = [&](double& min, double& mean) {
    min = sj.empty() ? 0.0 : *std::min_element(sj.begin(), sj.end());
    double sum = 0.0;
    for (double v : sj) sum += v;
    mean = sj.empty() ? 0.0 : sum / static_cast<double>(sj.size());
  };
  summary(report.min_scaled_jacobian_before, report.mean_scaled_jacobian_before);
  report.min_scaled_jacobian_after = report.min_scaled_jacobian_before;
  report.mean_scaled_jacobian_after = report.mean_scaled_jacobian_before;
  const int max_sweeps = repair ? options.max_repair_sweeps : options.max_shape_sweeps;
  if (max_sweeps <= 0) {
    report.stop = "off";
    return report;
  }
  if (!repair && !hexes.empty() && !(report.min_scaled_jacobian_before > 0.0)) {
    report.stop = "inverted hexes: skipped";
    return report;
  }
  // Hexes around each node (CSR) and edge neighbours of each node.
  const NodeHexes incidence = node_hexes(hexes, n);
  const std::vector<std::size_t>& start = incidence.start;
  const std::vector<std::size_t>& around = incidence.around;
  const auto edges = stc::unique_edges(mesh.complex);
  std::vector<std::vector<std::int32_t>> neighbours(n);
  for (const auto& [a, b] : edges) {
    neighbours[static_cast<std::size_t>(a)].push_back(b);
    neighbours[static_cast<std::size_t>(b)].push_back(a);
  }
  bool any_free = false;
  for (std::size_t v = 0; v < n && !any_free; ++v) any_free = !fixed[v] && start[v + 1] > start[v];
  if (!any_free) {
    report.stop = "no free node";
    return report;
  }
  report.ran = true;
  // The hexes around node v: their smallest scaled Jacobian and their sum.
  struct Local {
    std::size_t inverted = 0;  ///< hexes with scaled Jacobian <= 0
    double min = std::numeric_limits<double>::infinity();
    double sum = 0.0;
  };
  const auto local = [&](std::size_t v) {
    Local q;
    for (std::size_t i = start[v]; i < start[v + 1]; ++i) {
      const double x = hex_scaled_jacobian(mesh.points, hexes[around[i]]);
      q.inverted += x <= 0.0 ? 1 : 0;
      q.min = std::min(q.min, x);
      q.sum += x;
    }
    return q;
  };
  // Better: fewer inverted hexes; with as many (never more), a larger minimum, or the same
  // minimum (never a smaller one) and a larger sum. On a valid mesh (the shape phase) no
  // hex is inverted before or after a move that keeps the minimum, so only the last two
  // count there.
  const auto better = [](const Local& a, const Local& b) {
    if (a.inverted != b.inverted) return a.inverted < b.inverted;
    return a.min > b.min + 1e-12 || (a.min >= b.min && a.sum > b.sum + 1e-9);
  };
  const auto at = [&](std::size_t v) -> Eigen::RowVector3d {
    return mesh.points.row(static_cast<Eigen::Index>(v));
  };
  const auto place = [&](std::size_t v, const Eigen::RowVector3d& p) {
    mesh.points.row(static_cast<Eigen::Index>(v)) = p;
  };
  // Tries p for node v: keeps it when it is better than `current`.
  const auto try_move = [&](std::size_t v, const Eigen::RowVector3d& p, Local& current) {
    const Eigen::RowVector3d old = at(v);
    place(v, p);
    const Local q = local(v);
    if (better(q, current)) {
      current = q;
      return true;
    }
    place(v, old);
    return false;
  };
  const auto shortfall = [&] {
    double sum = 0.0;
    for (double v : sj) sum += std::max(0.0, options.shape_target - v);
    return sum;
  };
  const auto count_inverted = [&] {
    return static_cast<std::size_t>(
        std::count_if(sj.begin(), sj.end(), [](double v) { return !(v > 0.0); }));
  };
  // The repair looks for much smaller gains than the shape phase: finer steps.
  const double smallest_step = repair ? 1e-6 : 1e-3;
  report.stop = "sweep limit";
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    const double min_before = report.min_scaled_jacobian_after;
    const double shortfall_before = shortfall();
    const std::size_t inverted_before = count_inverted();
    if (!repair && min_before >= options.shape_target) {
      report.stop = "target reached";
      break;
    }
    if (repair && min_before > 0.0) {
      report.stop = "repaired";
      break;
    }
    std::vector<bool> active(n, false);
    if (repair) {
      active = near_inverted(hexes, sj, incidence, fixed, options.repair_rings);
    } else {
      for (std::size_t h = 0; h < hexes.size(); ++h)
        if (sj[h] < options.shape_target)
          for (const NodeId v : hexes[h]) active[v.index()] = !fixed[v.index()];
    }
    // Worst first: the nodes of the poorest hexes are moved before their neighbours (ties in
    // node order, so the sweep is deterministic).
    std::vector<std::pair<double, std::size_t>> order;
    for (std::size_t v = 0; v < n; ++v) {
      if (!active[v]) continue;
      double worst = std::numeric_limits<double>::infinity();
      for (std::size_t i = start[v]; i < start[v + 1]; ++i) worst = std::min(worst, sj[around[i]]);
      order.emplace_back(worst, v);
    }
    std::sort(order.begin(), order.end());
    for (const auto& [worst_around, v] : order) {
      if (neighbours[v].empty()) continue;
      double length = 0.0;
      Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
      for (const std::int32_t w : neighbours[v]) {
        length += (at(static_cast<std::size_t>(w)) - at(v)).norm();
        centre += at(static_cast<std::size_t>(w));
      }
      length /= static_cast<double>(neighbours[v].size());
      centre /= static_cast<double>(neighbours[v].size());
      if (!(length > 0.0)) continue;
      Local current = local(v);
      bool moved = try_move(v, centre, current);
      // Ascent along the finite-difference gradients of the local minimum and of the local
      // sum, each with halving steps.
      const double delta = 1e-4 * length;
      const Eigen::RowVector3d p0 = at(v);
      Eigen::RowVector3d grad_min;
      Eigen::RowVector3d grad_sum;
      for (int c = 0; c < 3; ++c) {
        Eigen::RowVector3d p = p0;
        p(c) += delta;
        place(v, p);
        const Local up = local(v);
        p(c) = p0(c) - delta;
        place(v, p);
        const Local down = local(v);
        grad_min(c) = (up.min - down.min) / (2.0 * delta);
        grad_sum(c) = (up.sum - down.sum) / (2.0 * delta);
      }
      place(v, p0);
      for (const Eigen::RowVector3d& g : {grad_min, grad_sum}) {
        if (!(g.norm() > 0.0)) continue;
        const Eigen::RowVector3d direction = g.normalized();
        const Eigen::RowVector3d from = at(v);
        bool taken = false;
        for (double step = 0.2 * length; step > smallest_step * length && !taken; step *= 0.5)
          taken = try_move(v, from + step * direction, current);
        moved = moved || taken;
      }
      if (moved) {
        ++report.moves;
        for (std::size_t i = start[v]; i < start[v + 1]; ++i)
          sj[around[i]] = hex_scaled_jacobian(mesh.points, hexes[around[i]]);
      }
    }
    ++report.sweeps;
    summary(report.min_scaled_jacobian_after, report.mean_scaled_jacobian_after);
    if (options.progress) {
      PositionProgress p;
      p.phase = repair ? PositionProgress::Phase::Repair : PositionProgress::Phase::Shape;
      p.step = report.sweeps;
      p.limit = static_cast<std::size_t>(max_sweeps);
      p.inverted = count_inverted();
      p.min_scaled_jacobian = report.min_scaled_jacobian_after;
      options.progress(p);
    }
    if (repair) {
      if (report.min_scaled_jacobian_after > 0.0) {
        report.stop = "repaired";
        break;
      }
      // Settled: the sweep neither raised the worst hex nor lowered the inverted count.
      if (report.min_scaled_jacobian_after <= min_before + 1e-12 &&
          count_inverted() >= inverted_before) {
        report.stop = "settled";
        break;
      }
      continue;
    }
    if (report.min_scaled_jacobian_after >= options.shape_target) {
      report.stop = "target reached";
      break;
    }
    if (report.min_scaled_jacobian_after - min_before < options.shape_tolerance &&
        shortfall_before - shortfall() <= options.shape_tolerance * shortfall_before) {
      report.stop = "settled";
      break;
    }
  }
  return report;
}

/// When no hex is below `shape_target` at the start, the report of a shape phase with nothing
/// to raise ("target reached", nothing ran), found with one pass over the hexes; otherwise an
/// empty `stop`. Both orders of `improve_shape` would build their incidence tables and
/// evaluate every hex four times to reach the same verdict, which on a structured box of
/// 205,379 hexes cost 0.2 s of a 4 s run.
ShapeReport nothing_below_target(const HexMesh& mesh, const std::vector<bool>& fixed,
                                 const PositionOptions& options) {
  ShapeReport r;
  const std::vector<stc::Hex>& hexes = mesh.complex.hexes;
  if (options.barrier_rounds <= 0 || options.max_shape_sweeps <= 0 || hexes.empty() ||
      fixed.size() != static_cast<std::size_t>(mesh.points.rows()))
    return r;
  // Without a free node the phases say so ("no free node").
  const bool any_free = std::any_of(hexes.begin(), hexes.end(), [&](const stc::Hex& h) {
    return std::any_of(h.begin(), h.end(), [&](NodeId v) { return !fixed[v.index()]; });
  });
  if (!any_free) return r;
  double min = std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (const stc::Hex& h : hexes) {
    const double x = hex_scaled_jacobian(mesh.points, h);
    if (!(x >= options.shape_target)) return r;  // NaN included: the phases decide
    min = std::min(min, x);
    sum += x;
  }
  r.min_scaled_jacobian_before = r.min_scaled_jacobian_after = min;
  r.mean_scaled_jacobian_before = r.mean_scaled_jacobian_after =
      sum / static_cast<double>(hexes.size());
  r.barrier.min_scaled_jacobian_before = r.barrier.min_scaled_jacobian_after = min;
  r.barrier.stop = "target reached";
  r.stop = "target reached";
  return r;
}

/// Adds the sweeps and moves of `more` to `into` and takes its figures "after".
void append_local(ShapeReport& into, const ShapeReport& more) {
  into.ran = into.ran || more.ran;
  into.sweeps += more.sweeps;
  into.moves += more.moves;
  into.min_scaled_jacobian_after = more.min_scaled_jacobian_after;
  into.mean_scaled_jacobian_after = more.mean_scaled_jacobian_after;
  into.stop = more.stop;
}

}  // namespace

ShapeReport improve_shape(HexMesh& mesh, const std::vector<bool>& fixed,
                          const PositionOptions& options) {
  if (options.barrier_rounds <= 0 || options.max_shape_sweeps <= 0) {
    ShapeReport r = local_shape(mesh, fixed, options);
    r.barrier.stop = "off";
    return r;
  }
  const Points start = mesh.points;
  // Candidate A: the barrier pass, then the local sweeps.
  ShapeReport a;
  a.barrier = raise_worst_corners(mesh, fixed, options);
  append_local(a, local_shape(mesh, fixed, options));
  a.order = "barrier first";
  a.ran = a.ran || a.barrier.ran;
  if (!a.ran) {
    // Nothing could move (inverted hexes, no free node, target reached at the start).
    a.min_scaled_jacobian_before = a.barrier.min_scaled_jacobian_before;
    return a;
  }
  // Candidate B: the local sweeps, the barrier pass, the local sweeps again. Neither order
  // is better on every mesh (docs/geometry.md); both only ever raise the minimum.
  const Points after_a = mesh.points;
  mesh.points = start;
  ShapeReport b = local_shape(mesh, fixed, options);
  b.barrier = raise_worst_corners(mesh, fixed, options);
  if (b.barrier.ran) append_local(b, local_shape(mesh, fixed, options));
  b.order = "local first";
  b.ran = b.ran || b.barrier.ran;
  // Figures "before" are those of the start (the first step's before).
  a.min_scaled_jacobian_before = b.min_scaled_jacobian_before;
  a.mean_scaled_jacobian_before = b.mean_scaled_jacobian_before;
  const bool take_b = b.min_scaled_jacobian_after > a.min_scaled_jacobian_after + 1e-12 ||
                      (b.min_scaled_jacobian_after >= a.min_scaled_jacobian_after - 1e-12 &&
                       b.mean_scaled_jacobian_after > a.mean_scaled_jacobian_after + 1e-12);
  if (take_b) return b;
  mesh.points = after_a;
  return a;
}

RepairReport repair_inverted(HexMesh& mesh, const std::vector<bool>& fixed,
                             const PositionOptions& options) {
  RepairReport r;
  const QualitySummary q = summarize_quality(mesh, 0);
  r.inverted_before = r.inverted_after = q.inverted;
  r.min_scaled_jacobian_before = r.min_scaled_jacobian_after = q.min_scaled_jacobian;
  if (options.max_repair_sweeps <= 0) {
    r.stop = "off";
    return r;
  }
  if (q.inverted == 0) {
    r.stop = "nothing inverted";
    return r;
  }
  const Points start = mesh.points;
  const ShapeReport local = local_shape(mesh, fixed, options, LocalGoal::Repair);
  r.stop = local.stop;
  if (!local.ran) return r;
  r.sweeps = local.sweeps;
  r.moves = local.moves;
  const QualitySummary after = summarize_quality(mesh, 0);
  if (after.inverted > q.inverted ||
      (after.inverted == q.inverted && after.min_scaled_jacobian < q.min_scaled_jacobian)) {
    // Cannot happen (a move changes only the hexes around its node, and is kept only when
    // they have fewer inverted hexes, or as many and a better worst one); a safety net so
    // that the repair never hands back a worse mesh than the untangling did.
    mesh.points = start;
    r.moves = 0;
    r.stop += "; undone (" + std::to_string(after.inverted) + " inverted, min " +
              std::to_string(after.min_scaled_jacobian) + ")";
    return r;
  }
  r.ran = true;
  r.inverted_after = after.inverted;
  r.min_scaled_jacobian_after = after.min_scaled_jacobian;
  return r;
}

const char* phase_name(PositionProgress::Phase phase) {
  switch (phase) {
    case PositionProgress::Phase::Untangle:
      return "untangle";
    case PositionProgress::Phase::Repair:
      return "repair";
    case PositionProgress::Phase::Shape:
      return "shape";
    case PositionProgress::Phase::Clusters:
      return "clusters";
  }
  return "?";
}

PositionReport position_nodes(HexMesh& mesh, const PositionOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  PositionReport report;
  const std::size_t n = static_cast<std::size_t>(mesh.points.rows());
  if (!options.fixed.empty() && options.fixed.size() != n) {
    throw InvalidInput("position_nodes: the fixed mask has " +
                       std::to_string(options.fixed.size()) + " entries for " + std::to_string(n) +
                       " nodes");
  }
  if (options.max_total_iterations < 0) {
    throw InvalidInput("position_nodes: max_total_iterations is " +
                       std::to_string(options.max_total_iterations) +
                       "; give 0 (no bound) or a positive count");
  }
  // NaN passes every comparison-based range check: each real option is tested as a range.
  const auto require_in = [](const char* name, double value, double lo, double hi,
                             const char* meaning) {
    if (value >= lo && value <= hi) return;
    throw InvalidInput(std::string("position_nodes: ") + name + " is " + short_number(value) +
                       ": it must lie in [" + short_number(lo) + ", " + short_number(hi) + "] (" +
                       meaning + ")");
  };
  require_in("stall_fraction", options.stall_fraction, 0.0, 1.0,
             "0: any drop of the inverted corners counts");
  require_in("theta", options.theta, 0.0, 1.0, "the weight of the volume term");
  require_in("shape_target", options.shape_target, 0.0, 1.0, "a scaled Jacobian");
  require_in("good_start", options.good_start, 0.0, 2.0, "a scaled Jacobian; above 1: never");
  require_in("good_start_mean", options.good_start_mean, 0.0, 2.0,
             "a scaled Jacobian; above 1: never");
  std::vector<bool> fixed(n, false);
  for (std::size_t v = 0; v < n; ++v)
    fixed[v] = v < options.num_fixed || (!options.fixed.empty() && options.fixed[v]);

  if (options.start != StartPosition::Keep) {
    const Points harmonic = harmonic_start(mesh, fixed);
    bool take = options.start == StartPosition::Harmonic;
    if (!take) {
      HexMesh trial{harmonic, {}};
      const auto count = [](const Points& points, const HexMesh& m) {
        std::size_t bad = 0;
        for (const stc::Hex& h : m.complex.hexes)
          for (double d : hex_corner_jacobians(points, h)) bad += d <= 0.0;
        return bad;
      };
      take = count(harmonic, mesh) < count(mesh.points, mesh);
    }
    if (take) {
      mesh.points = harmonic;
      report.harmonic_start = true;
    }
  }

  const QualitySummary before = summarize_quality(mesh, 0);
  // The start, exactly: kept or repaired instead of the optimised positions (below).
  const Points start_points = mesh.points;
  report.inverted_before = before.inverted;
  report.min_scaled_jacobian_before = before.min_scaled_jacobian;
  report.mean_scaled_jacobian_before = before.mean_scaled_jacobian;
  for (const stc::Hex& h : mesh.complex.hexes)
    for (double d : hex_corner_jacobians(mesh.points, h))
      report.corners_inverted_before += d <= 0.0;

  Problem problem(mesh, fixed, options.theta);
  problem.set_threads(options.threads > 0 ? static_cast<std::size_t>(options.threads)
                                          : std::max(1u, std::thread::hardware_concurrency()));
  if (!mesh.complex.hexes.empty() && !(problem.volume() > 0.0)) {
    const double volume = problem.volume();
    if (!std::isfinite(volume)) {
      throw InvalidInput(
          "position_nodes: the hexes' total volume is not a finite number: the coordinates are "
          "not finite or too large for the arithmetic (cubes overflow); rescale the model");
    }
    const Eigen::RowVector3d lo = mesh.points.colwise().minCoeff();
    const Eigen::RowVector3d hi = mesh.points.colwise().maxCoeff();
    const double box = std::pow((hi - lo).norm(), 3);
    if (volume == 0.0 || std::abs(volume) <= 1e-12 * box) {
      throw InvalidInput(
          "position_nodes: the hexes enclose no volume (total 0 to rounding): the boundary is "
          "flat or its nodes coincide, or the coordinates are too small for the arithmetic; "
          "check the geometry or rescale the model");
    }
    throw InvalidInput("position_nodes: the hexes enclose a negative total volume (" +
                       short_number(volume) +
                       "): their node order is mirrored (swap nodes 1-3 and 5-7)");
  }
  report.free_nodes = problem.num_free();
  report.impossible = impossible_corners(mesh, fixed);
  for (const ImpossibleCorner& c : report.impossible) problem.deactivate(c.hex.index(), c.corner);

  Eigen::VectorXd x = problem.variables();
  auto [dmin, bad] = problem.min_determinant();
  double eps = dmin > 0.0 ? 1e-6 : 1.0;
  problem.set_epsilon(eps);
  const Eigen::VectorXd start_positions = x;
  report.stop = "no free node";

  // Early stop: a valid start that is already good is kept (the untangling energy evens the
  // corners out but was measured to lower the worst scaled Jacobian of such starts).
  report.good_start = problem.num_free() > 0 && !mesh.complex.hexes.empty() &&
                      before.inverted == 0 && report.corners_inverted_before == 0 &&
                      before.min_scaled_jacobian >= options.good_start &&
                      before.mean_scaled_jacobian >= options.good_start_mean;
  if (report.good_start) {
    report.converged = true;
    report.stop = "good start: no inverted corner, min scaled Jacobian " +
                  std::to_string(before.min_scaled_jacobian) +
                  " >= " + std::to_string(options.good_start) + ", mean " +
                  std::to_string(before.mean_scaled_jacobian) +
                  " >= " + std::to_string(options.good_start_mean) + ": kept";
  }

  if (problem.num_free() > 0 && !mesh.complex.hexes.empty() && !report.good_start) {
    LBFGSpp::LBFGSParam<double> param;
    param.m = options.memory;
    param.epsilon = options.gradient_tolerance;
    param.epsilon_rel = 0.0;
    param.past = 1;
    param.delta = 1e-10;
    param.max_iterations = options.newton_after > 0
                               ? std::min(options.newton_after, options.max_inner_iterations)
                               : options.max_inner_iterations;
    param.max_linesearch = 100;
    param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_WOLFE;
    std::optional<LaplacianPreconditioner> laplacian;
    if (options.precondition) laplacian.emplace(free_laplacian(mesh, problem));
    Objective objective(problem);
    // L-BFGS from x with parameters p: preconditioned when asked, else LBFGS++'s own. Its
    // iterations are added to the report's, also when its line search fails (then it throws,
    // and LBFGS++'s own solver, which does not say how far it got, is charged its limit): the
    // total bound counts every iteration.
    const auto lbfgs = [&](const LBFGSpp::LBFGSParam<double>& p, Eigen::VectorXd& at, double& f) {
      int used = 0;
      if (laplacian) {
        PreconditionedLbfgs solver(p, *laplacian);
        try {
          used = solver.minimize(objective, at, f);
        } catch (const std::runtime_error&) {
          report.iterations += static_cast<std::size_t>(solver.iterations());
          throw;
        }
      } else {
        try {
          used = LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchBacktracking>(p).minimize(
              objective, at, f);
        } catch (const std::runtime_error&) {
          report.iterations += static_cast<std::size_t>(p.max_iterations);
          throw;
        }
      }
      report.iterations += static_cast<std::size_t>(used);
      return used;
    };
    std::optional<NewtonSolver> newton;
    // No energy before the first round: "settled" needs two rounds (their eps may differ,
    // so a round that only lowered eps is not mistaken for convergence).
    double previous = std::numeric_limits<double>::infinity();
    std::size_t best_bad = bad;
    int stalled = 0;
    report.stop = "iteration limit";
    double used_eps = eps;
    // What the total bound leaves of the iterations (the bound itself when there is none).
    const auto total = static_cast<std::size_t>(options.max_total_iterations);
    const auto budget_left = [&]() -> int {
      if (total == 0) return std::numeric_limits<int>::max();
      return report.iterations >= total ? 0 : static_cast<int>(total - report.iterations);
    };
    // (`inverted` passed in: clang 14 cannot capture a structured binding.)
    const auto budget_spent = [total](std::size_t inverted) {
      return "iteration budget (" + std::to_string(total) + " L-BFGS iterations): " +
             (inverted > 0 ? std::to_string(inverted) + " corners still inverted"
                           : std::string("no corner inverted, the energy still falling"));
    };
    for (int outer = 0; outer < options.max_outer_iterations; ++outer) {
      if (budget_left() == 0) {
        report.stop = budget_spent(bad);
        break;
      }
      LBFGSpp::LBFGSParam<double> round_param = param;
      round_param.max_iterations = std::min(param.max_iterations, budget_left());
      problem.set_epsilon(eps);
      used_eps = eps;
      problem.set_variables(x);
      const double start = problem.evaluate(nullptr);
      objective.reset(x, start);
      double fx = start;
      int used = 0;
      bool line_search_failed = false;
      try {
        used = lbfgs(round_param, x, fx);
      } catch (const std::runtime_error&) {
        // A line search that cannot progress ends L-BFGS; the best point is kept.
        line_search_failed = true;
      }
      x = objective.best();
      double energy = objective.best_energy();
      // (Not when the total bound cut the round: it is spent.)
      if (options.newton_after > 0 && (line_search_failed || used >= param.max_iterations) &&
          budget_left() > 0) {
        if (!newton) newton.emplace(problem);
        int taken = 0;
        std::tie(energy, taken) = newton_descent(problem, *newton, options, x, report);
        const int left = std::min(options.max_inner_iterations - used, budget_left());
        if (taken == 0 && !line_search_failed && left > 0) {
          // Newton found no step: L-BFGS goes on with the rest of the round's budget.
          LBFGSpp::LBFGSParam<double> rest_param = param;
          rest_param.max_iterations = left;
          objective.reset(x, energy);
          fx = energy;
          try {
            (void)lbfgs(rest_param, x, fx);
          } catch (const std::runtime_error&) {
          }
          x = objective.best();
          energy = objective.best_energy();
        }
      }
      problem.set_variables(x);
      ++report.outer_iterations;
      std::tie(dmin, bad) = problem.min_determinant();
      // The next round's eps: a fifth of the worst corner's depth.
      const double next_eps = std::sqrt(1e-12 + 0.04 * std::min(dmin, 0.0) * std::min(dmin, 0.0));
      if (options.progress) {
        PositionProgress p;
        p.phase = PositionProgress::Phase::Untangle;
        p.step = report.outer_iterations;
        p.limit = static_cast<std::size_t>(options.max_outer_iterations);
        p.inverted = bad;
        p.iterations = report.iterations;
        p.epsilon = used_eps;
        p.next_epsilon = next_eps;
        options.progress(p);
      }
      // Progress: inverted corners down by more than `stall_fraction` of the count at the
      // last progress (a tail of rounds that each remove a handful of thousands is a stall).
      // A round without it counts toward the stall only when eps no longer falls by more
      // than that fraction: a round that only raised the worst corner leaves a sharper energy
      // for the next (the first rounds, whose eps is large, untangle little).
      if (static_cast<double>(bad) <
          (1.0 - options.stall_fraction) * static_cast<double>(best_bad)) {
        best_bad = bad;
        stalled = 0;
      } else if (bad > 0 && next_eps >= (1.0 - options.stall_fraction) * used_eps) {
        ++stalled;
      }
      const bool settled =
          std::abs(previous - energy) <= options.energy_tolerance * std::abs(energy);
      previous = energy;
      report.energy_after = energy;
      if (dmin > 0.0 && settled) {
        report.converged = true;
        report.stop = "converged";
        break;
      }
      if (bad > 0 && stalled >= options.stall_iterations) {
        report.stop = "stalled: " + std::to_string(bad) + " corners still inverted";
        break;
      }
      eps = next_eps;
    }
    if (report.stop == "iteration limit" && total > 0 && report.iterations >= total) {
      // The last round allowed also spent the total: say so.
      report.stop = budget_spent(bad);
    }
    report.epsilon = used_eps;
    // Both energies with the last round's eps, so that they compare.
    problem.set_epsilon(report.epsilon);
    problem.set_variables(start_positions);
    report.energy_before = problem.evaluate(nullptr);
    problem.set_variables(x);
    report.energy_after = problem.evaluate(nullptr);
    problem.store(mesh);
  } else {
    report.epsilon = eps;
    report.energy_before = report.energy_after = problem.evaluate(nullptr);
  }
  if (!report.impossible.empty())
    report.stop += "; " + std::to_string(report.impossible.size()) + " impossible corners left out";

  // A good start is kept untouched: its figures are those measured before.
  QualitySummary after = report.good_start ? before : summarize_quality(mesh, 0);
  if (after.inverted > before.inverted && report.free_nodes > 0) {
    // The energy counts corners; a user counts hexes. Never hand back more inverted hexes
    // than we were given: keep the start instead.
    mesh.points = start_points;
    report.stop += "; kept the start (" + std::to_string(after.inverted) +
                   " inverted hexes after optimisation against " + std::to_string(before.inverted) +
                   " before)";
    report.kept_start = true;
    after = summarize_quality(mesh, 0);
  }
  if (!report.kept_start && report.free_nodes > 0 && before.inverted == 0 &&
      report.corners_inverted_before == 0 &&
      after.min_scaled_jacobian < before.min_scaled_jacobian) {
    // A valid start had a better worst hex than the optimised positions: keep the start.
    mesh.points = start_points;
    report.stop += "; kept the valid start (min scaled Jacobian " +
                   std::to_string(before.min_scaled_jacobian) + " against " +
                   std::to_string(after.min_scaled_jacobian) + " optimised)";
    report.kept_start = true;
    after = summarize_quality(mesh, 0);
  }
  if (after.inverted > 0 && report.free_nodes > 0) {
    report.repaired_from = report.kept_start ? "start" : "untangled";
    report.repair = repair_inverted(mesh, fixed, options);
    if (report.repair.moves > 0) {
      after = summarize_quality(mesh, 0);
      report.stop += "; repair: " + std::to_string(report.repair.inverted_before) + " -> " +
                     std::to_string(report.repair.inverted_after) + " inverted hexes (" +
                     report.repair.stop + ")";
    }
    // Hexes left inverted from the untangling's positions: the start is repaired too and
    // the better kept (fewer inverted hexes, then the larger minimum; a tie keeps the
    // untangled positions). The untangling lowers the inverted corners but can leave hexes
    // the repair cannot reach (gmsh/part_a6_trisubdiv_coarse, reliable: 91 inverted from
    // the untangled positions, 25 from the start). Only when rounds ran (else both are
    // one), the repair is on, and the start was not kept already: then the guard above
    // found the untangled positions worse, and repairing them too was measured to cost a
    // minute for nothing (real/pmp/fandisk_quads: 714 inverted against the start's 97).
    if (after.inverted > 0 && report.outer_iterations > 0 && options.max_repair_sweeps > 0 &&
        !report.kept_start) {
      Points first = mesh.points;
      mesh.points = start_points;
      report.other_repair = repair_inverted(mesh, fixed, options);
      const QualitySummary other = summarize_quality(mesh, 0);
      const bool better = other.inverted < after.inverted ||
                          (other.inverted == after.inverted &&
                           other.min_scaled_jacobian > after.min_scaled_jacobian);
      report.stop += "; repair of the start positions: " +
                     std::to_string(report.other_repair.inverted_before) + " -> " +
                     std::to_string(report.other_repair.inverted_after) + " inverted hexes (" +
                     report.other_repair.stop + "), " + (better ? "kept" : "not kept");
      if (better) {
        after = other;
        report.repaired_from = "start";
        std::swap(report.repair, report.other_repair);
        report.kept_start = true;
      } else {
        mesh.points = std::move(first);
      }
    }
  } else {
    report.repair.stop = report.free_nodes > 0 ? "nothing inverted" : "no free node";
  }
  if (after.inverted > 0 && report.free_nodes > 0 && options.cluster_passes > 0) {
    report.clusters = untangle_clusters(mesh, fixed, options);
    if (report.clusters.accepted > 0) after = summarize_quality(mesh, 0);
    report.stop += "; local untangling: " + std::to_string(report.clusters.inverted_before) +
                   " -> " + std::to_string(report.clusters.inverted_after) + " inverted hexes (" +
                   std::to_string(report.clusters.sub_problems) + " sub-meshes, " +
                   report.clusters.stop + ")";
  } else {
    report.clusters.stop = options.cluster_passes <= 0 ? "off"
                           : report.free_nodes > 0     ? "nothing inverted"
                                                       : "no free node";
  }
  report.min_scaled_jacobian_untangled = after.min_scaled_jacobian;
  report.mean_scaled_jacobian_untangled = after.mean_scaled_jacobian;
  // (Options and node ids were checked above; `improve_shape` checks them for its own callers.)
  report.shape = nothing_below_target(mesh, fixed, options);
  if (report.shape.stop.empty()) report.shape = improve_shape(mesh, fixed, options);
  if (report.shape.moves > 0 || report.shape.barrier.ran) after = summarize_quality(mesh, 0);
  if (after.inverted == 0 && report.free_nodes > 0 && options.hinge_shape_below > 0.0 &&
      after.min_scaled_jacobian < options.hinge_shape_below) {
    report.shape.hinge = raise_worst_by_hinges(mesh, fixed, options);
    if (report.shape.hinge.accepted > 0) {
      after = summarize_quality(mesh, 0);
      report.shape.min_scaled_jacobian_after = after.min_scaled_jacobian;
      report.shape.mean_scaled_jacobian_after = after.mean_scaled_jacobian;
    }
  } else {
    // The pass's own verdicts, without its tables: it would stop at once.
    report.shape.hinge.stop = !(options.hinge_shape_below > 0.0) ? "off"
                              : after.inverted > 0               ? "inverted hexes: skipped"
                                                                 : "nothing below";
    report.shape.hinge.min_scaled_jacobian_before = after.min_scaled_jacobian;
    report.shape.hinge.min_scaled_jacobian_after = after.min_scaled_jacobian;
  }
  report.inverted_after = after.inverted;
  report.min_scaled_jacobian_after = after.min_scaled_jacobian;
  report.mean_scaled_jacobian_after = after.mean_scaled_jacobian;
  // Nothing moved since the corners were counted (a good start the shape phase left alone):
  // the count stands.
  const bool unmoved = report.good_start && report.shape.moves == 0 && !report.shape.barrier.ran;
  if (unmoved) report.corners_inverted_after = report.corners_inverted_before;
  for (std::size_t hx = 0; hx < mesh.complex.hexes.size(); ++hx) {
    if (!unmoved) {
      for (double d : hex_corner_jacobians(mesh.points, mesh.complex.hexes[hx]))
        report.corners_inverted_after += d <= 0.0;
    }
    if (after.per_hex[hx] <= 0.0) report.inverted.emplace_back(hx);
  }
  report.untangled = report.inverted_after == 0 && report.corners_inverted_after == 0;
  if (report.inverted_after > 0) {
    // Name the topology no placement can fix (docs/geometry.md "Repair").
    const std::vector<PinchedFaces> pinched = pinched_faces(mesh.complex);
    if (!pinched.empty()) {
      const PinchedFaces& p = pinched.front();
      report.stop += "; " + std::to_string(pinched.size()) +
                     " pinched face pairs (two faces share two edges at a node, e.g. n" +
                     std::to_string(p.a.value()) + "-" + p.node.str() + "-n" +
                     std::to_string(p.b.value()) +
                     ": a corner there is flat whatever the positions; topology)";
    }
  }
  report.validity.reserve(mesh.complex.hexes.size());
  for (const stc::Hex& h : mesh.complex.hexes) {
    const Validity v = hex_bezier_validity(mesh.points, h, options.certify_depth);
    report.validity.push_back(v);
    report.certified.valid += v == Validity::Valid;
    report.certified.invalid += v == Validity::Invalid;
    report.certified.uncertain += v == Validity::Uncertain;
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace stcweave::primal
