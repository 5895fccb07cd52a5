// Local untangling of the clusters of hexes the global positioning leaves inverted
// (`untangle_clusters`, docs/geometry.md "Local untangling").
//
// Why: the untangling energy of `position_nodes` is minimised over every free node at once,
// with one eps schedule for the whole mesh; where a few corners stay negative it stalls, and
// the repair's max-min moves, one node at a time, stall too. The same energy minimised on a
// small sub-mesh around the stuck hexes, its boundary held, starts its own eps schedule from
// that sub-mesh's worst corner and often finds positions the global problem did not (measured:
// `pmp/fandisk_quads` with `extended` 23 -> 1 inverted hexes, `gmsh-quad/cylinder2_c3` 20 -> 0).
// Which sub-mesh works is not predictable (one ring more or less, the current positions or
// the harmonic ones), so a few are tried and the best kept; a sub-mesh's result is kept only
// when it has fewer inverted hexes (or as many and a better worst one), so the inverted count
// never rises.
#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include "node_hexes.hpp"
#include "position_hinge.hpp"
#include "stcweave/primal/position.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/hex_complex.hpp"
#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::primal {
namespace {

constexpr std::size_t kUnset = std::numeric_limits<std::size_t>::max();

/// The local untangling's judge: inverted hexes (scaled Jacobian <= 0), then the worst scaled
/// Jacobian; fewer inverted is better, then a larger worst.
struct Tally {
  std::size_t inverted = 0;
  double worst = std::numeric_limits<double>::infinity();

  static Tally of(const Points& points, const std::vector<stc::Hex>& hexes) {
    Tally t;
    for (const stc::Hex& h : hexes) {
      const double sj = hex_scaled_jacobian(points, h);
      t.inverted += sj <= 0.0 ? 1 : 0;
      t.worst = std::min(t.worst, sj);
    }
    return t;
  }
  [[nodiscard]] bool better_than(const Tally& b) const {
    return inverted < b.inverted || (inverted == b.inverted && worst > b.worst);
  }
};

/// The shape pass's judge (`raise_worst_by_hinges`): the scaled Jacobians, sorted; better when,
/// at the first place where the two sorted lists differ, the value is larger by at least
/// `kStep` (so raising a hex next to a worse one that no try can move still counts, and no hex
/// drops below the ones before it).
struct Leximin {
  static constexpr double kStep = 1e-4;
  std::vector<double> sorted;

  static Leximin of(const Points& points, const std::vector<stc::Hex>& hexes) {
    Leximin l;
    l.sorted.reserve(hexes.size());
    for (const stc::Hex& h : hexes) l.sorted.push_back(hex_scaled_jacobian(points, h));
    std::sort(l.sorted.begin(), l.sorted.end());
    return l;
  }
  [[nodiscard]] bool better_than(const Leximin& b) const {
    for (std::size_t k = 0; k < sorted.size() && k < b.sorted.size(); ++k) {
      if (sorted[k] == b.sorted[k]) continue;
      return sorted[k] >= b.sorted[k] + kStep;
    }
    return false;
  }
  /// The worst scaled Jacobian (1 for no hex).
  [[nodiscard]] double worst() const { return sorted.empty() ? 1.0 : sorted.front(); }
};

/// The clusters of `inverted` (sorted hex ids): components under "shares a node", each listed
/// in increasing hex order, ordered by their smallest hex.
std::vector<std::vector<std::size_t>> clusters_of(const std::vector<std::size_t>& inverted,
                                                  const std::vector<stc::Hex>& hexes,
                                                  const NodeHexes& node_hexes) {
  std::vector<char> is_inverted(hexes.size(), 0);
  for (const std::size_t h : inverted) is_inverted[h] = 1;
  std::vector<char> seen(hexes.size(), 0);
  std::vector<std::vector<std::size_t>> out;
  for (const std::size_t s : inverted) {
    if (seen[s] != 0) continue;
    seen[s] = 1;
    std::vector<std::size_t> cluster{s};
    for (std::size_t k = 0; k < cluster.size(); ++k) {
      for (const NodeId v : hexes[cluster[k]]) {
        for (const std::size_t g : node_hexes.of(v.index())) {
          if (is_inverted[g] == 0 || seen[g] != 0) continue;
          seen[g] = 1;
          cluster.push_back(g);
        }
      }
    }
    std::sort(cluster.begin(), cluster.end());
    out.push_back(std::move(cluster));
  }
  return out;
}

/// `cluster` grown by 0, 1, ... `rings` layers of hexes sharing a node: entry r lists the
/// hexes within r layers, sorted. `mark` (one entry per hex, all 0) is left all 0.
std::vector<std::vector<std::size_t>> grown(const std::vector<std::size_t>& cluster, int rings,
                                            const std::vector<stc::Hex>& hexes,
                                            const NodeHexes& node_hexes, std::vector<char>& mark) {
  std::vector<std::size_t> out = cluster;
  for (const std::size_t h : out) mark[h] = 1;
  std::vector<std::vector<std::size_t>> layers;
  layers.push_back(out);
  std::size_t layer_start = 0;
  for (int r = 0; r < rings; ++r) {
    const std::size_t layer_end = out.size();
    for (std::size_t k = layer_start; k < layer_end; ++k) {
      for (const NodeId v : hexes[out[k]]) {
        for (const std::size_t g : node_hexes.of(v.index())) {
          if (mark[g] != 0) continue;
          mark[g] = 1;
          out.push_back(g);
        }
      }
    }
    layer_start = layer_end;
    layers.push_back(out);
    std::sort(layers.back().begin(), layers.back().end());
  }
  for (const std::size_t h : out) mark[h] = 0;
  return layers;
}

/// The sub-mesh of `hexes` (ids into `mesh`) over its own node ids, with its fixed mask: the
/// nodes fixed in `mesh`, the nodes on its boundary faces (faces of one sub-mesh hex) and any
/// node with a hex outside it (the same nodes on a manifold complex; more where a face has
/// three hexes or hex fans meet at a node), so that every node it may move has all its hexes
/// inside it. Without `with_fixed`, only the nodes and hexes.
struct SubMesh {
  HexMesh mesh;
  std::vector<bool> fixed;
  std::vector<NodeId> node_of;  ///< per local node, the node of the whole mesh
};

/// One sub-mesh positioned from one start: its positions, and the L-BFGS iterations it used
/// under its cap (`ok` false when the positioning refused the sub-mesh; `error` set when it
/// threw anything else, run on a thread of its own).
struct Try {
  SubMesh sub;
  bool ok = false;
  std::size_t iterations = 0;
  int cap = 0;
  std::exception_ptr error;
};

SubMesh sub_mesh(const HexMesh& mesh, const std::vector<bool>& fixed, const NodeHexes& node_hexes,
                 const std::vector<std::size_t>& hexes, bool with_fixed) {
  SubMesh s;
  std::map<std::int32_t, std::int32_t> local;
  for (const std::size_t h : hexes)
    for (const NodeId v : mesh.complex.hexes[h]) local.emplace(v.value(), 0);
  for (auto& [global, id] : local) {
    id = static_cast<std::int32_t>(s.node_of.size());
    s.node_of.emplace_back(global);
  }
  s.mesh.points.resize(static_cast<Eigen::Index>(s.node_of.size()), 3);
  for (std::size_t v = 0; v < s.node_of.size(); ++v)
    s.mesh.points.row(static_cast<Eigen::Index>(v)) = mesh.points.row(s.node_of[v].value());
  s.mesh.complex.num_nodes = s.node_of.size();
  for (const std::size_t h : hexes) {
    stc::Hex x = mesh.complex.hexes[h];
    for (NodeId& v : x) v = NodeId(local.at(v.value()));
    s.mesh.complex.hexes.push_back(x);
  }
  if (!with_fixed) return s;
  s.fixed.assign(s.node_of.size(), false);
  std::vector<std::size_t> inside(s.node_of.size(), 0);
  for (const stc::Hex& x : s.mesh.complex.hexes)
    for (const NodeId v : x) ++inside[v.index()];
  for (std::size_t v = 0; v < s.node_of.size(); ++v) {
    s.fixed[v] =
        fixed[s.node_of[v].index()] || inside[v] != node_hexes.of(s.node_of[v].index()).size();
  }
  for (const stc::Quad& q : stc::boundary_surface(s.mesh.complex).quads)
    for (const NodeId v : q) s.fixed[v.index()] = true;
  return s;
}

/// The hexes of `mesh` with a scaled Jacobian <= 0, in increasing order.
std::vector<std::size_t> inverted_hexes(const HexMesh& mesh) {
  std::vector<std::size_t> out;
  for (std::size_t h = 0; h < mesh.complex.hexes.size(); ++h)
    if (hex_scaled_jacobian(mesh.points, mesh.complex.hexes[h]) <= 0.0) out.push_back(h);
  return out;
}

/// Whether the sub-meshes' work has reached `cluster_max_work` (0: no bound).
bool work_spent(const PositionOptions& options, const ClusterReport& report) {
  return options.cluster_max_work > 0 && report.work >= options.cluster_max_work;
}

/// The L-BFGS iterations a sub-mesh of `hexes` hexes may use: what the work bound leaves (at
/// least 1), and at most `max_total_iterations` when that is set; with neither bound, the
/// largest value (no bound).
std::size_t iterations_left(const PositionOptions& options, const ClusterReport& report,
                            std::size_t hexes) {
  std::size_t left = std::numeric_limits<std::size_t>::max();
  if (options.cluster_max_work > 0) {
    left = std::max<std::size_t>(
        1, (options.cluster_max_work - report.work) / std::max<std::size_t>(1, hexes));
  }
  if (options.max_total_iterations > 0)
    left = std::min(left, static_cast<std::size_t>(options.max_total_iterations));
  return left;
}

/// A cluster's (or a seed's) widest sub-mesh, over which its tries are judged (its hexes are
/// all the hexes any try can change) by `Score` (`Tally` or `Leximin`). The best positions so
/// far are kept, and written back only when they beat the start.
template <class Score>
class WidestSubMesh {
 public:
  WidestSubMesh(const HexMesh& mesh, const std::vector<bool>& fixed, const NodeHexes& node_hexes,
                const std::vector<std::size_t>& hexes)
      : wide_(sub_mesh(mesh, fixed, node_hexes, hexes, false)) {
    for (std::size_t v = 0; v < wide_.node_of.size(); ++v)
      local_.emplace(wide_.node_of[v].value(), v);
    at_start_ = best_ = Score::of(wide_.mesh.points, wide_.mesh.complex.hexes);
  }

  [[nodiscard]] const Score& at_start() const { return at_start_; }
  [[nodiscard]] const Score& best() const { return best_; }
  /// Whether a try judged so far beats the start.
  [[nodiscard]] bool improved() const { return best_.better_than(at_start_); }

  /// Judges the positions `sub` (a sub-mesh of this one) gives its nodes; kept when better
  /// than the best so far.
  void judge(const SubMesh& sub) {
    Points trial = wide_.mesh.points;
    for (std::size_t v = 0; v < sub.node_of.size(); ++v) {
      trial.row(static_cast<Eigen::Index>(local_.at(sub.node_of[v].value()))) =
          sub.mesh.points.row(static_cast<Eigen::Index>(v));
    }
    Score tried = Score::of(trial, wide_.mesh.complex.hexes);
    if (tried.better_than(best_)) {
      best_ = std::move(tried);
      best_points_ = std::move(trial);
    }
  }

  /// Writes the best positions into `mesh` when they beat the start: true then.
  bool keep_best(HexMesh& mesh) const {
    if (!improved()) return false;
    for (std::size_t v = 0; v < wide_.node_of.size(); ++v)
      mesh.points.row(wide_.node_of[v].value()) = best_points_.row(static_cast<Eigen::Index>(v));
    return true;
  }

 private:
  SubMesh wide_;
  std::map<std::int32_t, std::size_t> local_;
  Score at_start_;
  Score best_;
  Points best_points_;
};

/// The hinge phase: for each cluster still inverted, the hinge untangling
/// (position_hinge.hpp) of the free nodes of the cluster grown by 1 .. `cluster_max_rings`
/// rings (the sub-mesh of one ring more, its outer nodes held, so every hex they touch is
/// weighed), with beta 0.02 then 0.05, in that order, until one leaves none inverted among the
/// widest sub-mesh's hexes; the best is kept when it beats the current positions, as above.
/// Under the same work bound. Updates `inverted` and `report`.
void hinge_phase(HexMesh& mesh, const std::vector<bool>& fixed, const NodeHexes& node_hexes,
                 const PositionOptions& options, std::vector<std::size_t>& inverted,
                 ClusterReport& report) {
  const std::vector<stc::Hex>& hexes = mesh.complex.hexes;
  std::vector<char> mark(hexes.size(), 0);
  const std::vector<std::vector<std::size_t>> clusters = clusters_of(inverted, hexes, node_hexes);
  bool work_bound = false;
  for (std::size_t c = 0; c < clusters.size() && !work_bound; ++c) {
    const std::vector<std::vector<std::size_t>> layers =
        grown(clusters[c], options.cluster_max_rings + 1, hexes, node_hexes, mark);
    WidestSubMesh<Tally> wide(mesh, fixed, node_hexes, layers.back());
    if (wide.at_start().inverted == 0) continue;
    ++report.hinge_clusters;
    for (int rings = 1;
         rings <= options.cluster_max_rings && wide.best().inverted > 0 && !work_bound; ++rings) {
      const std::vector<std::size_t>& hexes_in = layers[static_cast<std::size_t>(rings) + 1];
      if (hexes_in.size() > options.cluster_max_hexes) break;
      for (const double beta : {0.02, 0.05}) {
        if (wide.best().inverted == 0) break;
        if (work_spent(options, report)) {
          work_bound = true;
          break;
        }
        SubMesh sub = sub_mesh(mesh, fixed, node_hexes, hexes_in, true);
        const HingeOutcome run = hinge_untangle(sub.mesh, sub.fixed, beta,
                                                iterations_left(options, report, hexes_in.size()));
        ++report.hinge_tries;
        report.work += hexes_in.size() * std::max<std::size_t>(1, run.iterations);
        wide.judge(sub);
      }
    }
    if (wide.keep_best(mesh)) {
      ++report.hinge_accepted;
      ++report.accepted;
    }
    if (options.progress) {
      PositionProgress p;
      p.phase = PositionProgress::Phase::Clusters;
      p.step = c + 1;
      p.limit = clusters.size();
      p.pass = report.passes + 1;
      p.inverted = inverted.size() - wide.at_start().inverted + wide.best().inverted;
      options.progress(p);
    }
  }
  inverted = inverted_hexes(mesh);
  report.inverted_after = inverted.size();
  if (inverted.empty()) {
    report.stop = "untangled by the hinge phase";
  } else if (work_bound) {
    report.stop = "work bound (hinge phase)";
  } else {
    report.stop += "; hinge phase: " + std::to_string(inverted.size()) + " left";
  }
}

/// Refuses (InvalidInput, naming `who`) a fixed mask of the wrong size or a hex naming a node
/// that `mesh` does not have.
void check_arguments(const char* who, const HexMesh& mesh, const std::vector<bool>& fixed) {
  const auto num_nodes = static_cast<std::size_t>(mesh.points.rows());
  if (fixed.size() != num_nodes) {
    throw InvalidInput(std::string(who) + ": the fixed mask has " + std::to_string(fixed.size()) +
                       " entries for " + std::to_string(num_nodes) + " nodes");
  }
  const std::vector<stc::Hex>& hexes = mesh.complex.hexes;
  for (std::size_t h = 0; h < hexes.size(); ++h) {
    for (const NodeId v : hexes[h]) {
      if (!v.is_valid() || v.index() >= num_nodes) {
        throw InvalidInput(std::string(who) + ": hex h" + std::to_string(h) + " names node " +
                           v.str() + " out of range (" + std::to_string(num_nodes) + " nodes)");
      }
    }
  }
}

}  // namespace

ClusterReport untangle_clusters(HexMesh& mesh, const std::vector<bool>& fixed,
                                const PositionOptions& options) {
  ClusterReport report;
  check_arguments("untangle_clusters", mesh, fixed);
  const std::vector<stc::Hex>& hexes = mesh.complex.hexes;
  const auto num_nodes = static_cast<std::size_t>(mesh.points.rows());
  const NodeHexes node_hexes = primal::node_hexes(hexes, num_nodes);
  std::vector<std::size_t> inverted = inverted_hexes(mesh);
  report.inverted_before = report.inverted_after = inverted.size();
  if (options.cluster_passes <= 0) {
    report.stop = "off";
    return report;
  }
  if (inverted.empty()) {
    report.stop = "nothing inverted";
    return report;
  }
  report.ran = true;
  // The sub-problems: the global untangling's settings, without the shape phase (run on the
  // whole mesh afterwards), this pass, progress or certification.
  PositionOptions sub_options = options;
  sub_options.cluster_passes = 0;
  sub_options.max_shape_sweeps = 0;
  sub_options.hinge_shape_below = 0.0;
  sub_options.barrier_rounds = 0;
  sub_options.certify_depth = 0;
  sub_options.num_fixed = 0;
  sub_options.progress = nullptr;
  sub_options.good_start = 2.0;  // never kept as a "good start": always untangled
  // The two starts of a sub-mesh run side by side when a second hardware thread is there and
  // the caller did not ask for one thread; the result is the sequential order's either way.
  const bool speculate = options.threads != 1 && std::thread::hardware_concurrency() > 1;
  report.stop = "pass limit";
  std::vector<char> mark(hexes.size(), 0);
  bool work_bound = false;
  for (int pass = 0; pass < options.cluster_passes; ++pass) {
    if (work_spent(options, report)) {
      work_bound = true;
      break;
    }
    ++report.passes;
    const std::size_t at_pass_start = inverted.size();
    std::size_t inverted_now = at_pass_start;
    const std::vector<std::vector<std::size_t>> clusters = clusters_of(inverted, hexes, node_hexes);
    for (std::size_t c = 0; c < clusters.size() && !work_bound; ++c) {
      // The sub-meshes tried for this cluster lie inside the widest one: each is judged by
      // the hexes of that one (all the hexes any of them can change), and the best kept.
      const std::vector<std::vector<std::size_t>> layers =
          grown(clusters[c], options.cluster_max_rings, hexes, node_hexes, mark);
      WidestSubMesh<Tally> wide(mesh, fixed, node_hexes, layers.back());
      // An earlier cluster's sub-mesh may have untangled it.
      if (wide.at_start().inverted == 0) continue;
      ++report.clusters;
      // In order, and no further once a sub-mesh leaves none of them inverted.
      for (int rings = 1;
           rings <= options.cluster_max_rings && wide.best().inverted > 0 && !work_bound; ++rings) {
        const std::vector<std::size_t>& hexes_in = layers[static_cast<std::size_t>(rings)];
        if (hexes_in.size() > options.cluster_max_hexes) break;
        const SubMesh base = sub_mesh(mesh, fixed, node_hexes, hexes_in, true);
        // The iteration cap of a sub-mesh's untangling (0: none, as `max_total_iterations`).
        const auto cap_now = [&]() -> int {
          const std::size_t left = iterations_left(options, report, hexes_in.size());
          if (left == std::numeric_limits<std::size_t>::max()) return 0;
          return static_cast<int>(std::min<std::size_t>(
              left, static_cast<std::size_t>(std::numeric_limits<int>::max())));
        };
        const auto run = [&](StartPosition start, int cap) {
          Try t;
          t.sub = base;
          PositionOptions o = sub_options;
          o.fixed = t.sub.fixed;
          o.start = start;
          o.max_total_iterations = cap;
          t.cap = cap;
          try {
            t.iterations = position_nodes(t.sub.mesh, o).iterations;
            t.ok = true;
          } catch (const InvalidInput&) {
            // a sub-mesh whose total volume is not positive: too tangled here
          } catch (const SolverError&) {
            // a harmonic start with a free node cut off from the fixed ones
          } catch (const std::logic_error&) {
            // LBFGSpp's line search on an ascent direction (plain L-BFGS)
          }
          return t;
        };
        // The harmonic start's try, run beside the first one (`speculate`): its cap is the one
        // the first leaves it only when the first adds no work, so it is kept only when it
        // stopped below the cap the sequential order gives it, and run again otherwise.
        std::optional<Try> harmonic;
        for (const StartPosition start : {StartPosition::Keep, StartPosition::Harmonic}) {
          if (wide.best().inverted == 0) break;
          if (work_spent(options, report)) {
            work_bound = true;
            break;
          }
          const int cap = cap_now();
          std::thread beside;
          if (start == StartPosition::Keep && speculate) {
            harmonic.emplace();
            harmonic->cap = cap;
            beside = std::thread([&, cap] {
              try {
                *harmonic = run(StartPosition::Harmonic, cap);
              } catch (...) {
                harmonic->error = std::current_exception();
              }
            });
          }
          Try t;
          try {
            if (start == StartPosition::Harmonic && harmonic &&
                (harmonic->cap == cap ||
                 (harmonic->ok && harmonic->iterations < static_cast<std::size_t>(cap)))) {
              if (harmonic->error) std::rethrow_exception(harmonic->error);
              t = std::move(*harmonic);
            } else {
              t = run(start, cap);
            }
          } catch (...) {
            if (beside.joinable()) beside.join();
            throw;
          }
          if (beside.joinable()) beside.join();
          ++report.sub_problems;
          if (!t.ok) continue;
          report.work += t.sub.mesh.complex.hexes.size() * std::max<std::size_t>(1, t.iterations);
          wide.judge(t.sub);
        }
      }
      if (wide.keep_best(mesh)) {
        ++report.accepted;
        inverted_now = inverted_now - wide.at_start().inverted + wide.best().inverted;
      }
      if (options.progress) {
        PositionProgress p;
        p.phase = PositionProgress::Phase::Clusters;
        p.step = c + 1;
        p.limit = clusters.size();
        p.pass = report.passes;
        p.inverted = inverted_now;
        options.progress(p);
      }
    }
    inverted = inverted_hexes(mesh);
    report.inverted_after = inverted.size();
    if (inverted.empty()) {
      report.stop = "untangled";
      return report;
    }
    if (work_bound) break;
    if (inverted.size() >= at_pass_start) {
      report.stop = "settled";
      break;
    }
  }
  if (work_bound) {
    report.stop = "work bound";
    return report;
  }
  if (options.cluster_hinge) hinge_phase(mesh, fixed, node_hexes, options, inverted, report);
  return report;
}

HingeShapeReport raise_worst_by_hinges(HexMesh& mesh, const std::vector<bool>& fixed,
                                       const PositionOptions& options) {
  HingeShapeReport report;
  check_arguments("raise_worst_by_hinges", mesh, fixed);
  const std::vector<stc::Hex>& hexes = mesh.complex.hexes;
  const auto num_nodes = static_cast<std::size_t>(mesh.points.rows());
  if (!(options.hinge_shape_below > 0.0)) {
    report.stop = "off";
    return report;
  }
  // Hexes of fixed nodes only cannot change; a hex whose try was not kept is not tried again.
  std::vector<char> skip(hexes.size(), 0);
  for (std::size_t h = 0; h < hexes.size(); ++h) {
    skip[h] =
        std::all_of(hexes[h].begin(), hexes[h].end(), [&](NodeId v) { return fixed[v.index()]; })
            ? 1
            : 0;
  }
  const NodeHexes node_hexes = primal::node_hexes(hexes, num_nodes);
  const auto spent = [&] {
    return options.hinge_shape_max_work > 0 && report.work >= options.hinge_shape_max_work;
  };
  std::vector<char> mark(hexes.size(), 0);
  // Every hex's scaled Jacobian, brought up to date where a kept try moved nodes.
  std::vector<double> sj(hexes.size());
  for (std::size_t h = 0; h < hexes.size(); ++h) sj[h] = hex_scaled_jacobian(mesh.points, hexes[h]);
  bool first = true;
  for (;;) {
    // The worst hex (ties: the smallest id) and the mesh's minimum.
    double worst = std::numeric_limits<double>::infinity();
    double worst_open = worst;
    std::size_t seed = kUnset;
    for (std::size_t h = 0; h < hexes.size(); ++h) {
      worst = std::min(worst, sj[h]);
      if (skip[h] == 0 && sj[h] < worst_open) {
        worst_open = sj[h];
        seed = h;
      }
    }
    if (first) report.min_scaled_jacobian_before = worst;
    report.min_scaled_jacobian_after = worst;
    if (worst <= 0.0) {
      report.stop = "inverted hexes: skipped";
      return report;
    }
    if (seed == kUnset || !(worst_open < options.hinge_shape_below)) {
      report.stop = first ? "nothing below" : "done";
      return report;
    }
    first = false;
    if (spent()) {
      report.stop = "work bound";
      return report;
    }
    report.ran = true;
    const std::vector<std::vector<std::size_t>> layers =
        grown({seed}, options.cluster_max_rings + 1, hexes, node_hexes, mark);
    WidestSubMesh<Leximin> wide(mesh, fixed, node_hexes, layers.back());
    ++report.seeds;
    // Rings in order, until a try is better than the start.
    for (int rings = 1; rings <= options.cluster_max_rings && !spent() && !wide.improved();
         ++rings) {
      const std::vector<std::size_t>& hexes_in = layers[static_cast<std::size_t>(rings) + 1];
      if (hexes_in.size() > options.cluster_max_hexes) break;
      // Pull up the corners below 1.5 times the worst hex there (at least 0.0075), the
      // smoothing starting at beta (only those corners pull) or, when that is not better, at
      // 0.1 (every corner nearby pulls at first).
      const double beta = 1.5 * std::max(0.005, wide.best().worst());
      for (const double first_delta : {beta, 0.1}) {
        if (spent() || wide.improved()) break;
        SubMesh sub = sub_mesh(mesh, fixed, node_hexes, hexes_in, true);
        std::size_t cap = options.hinge_shape_iterations;
        if (options.hinge_shape_max_work > 0) {
          cap =
              std::min(cap, std::max<std::size_t>(
                                1, (options.hinge_shape_max_work - report.work) / hexes_in.size()));
        }
        const HingeOutcome run = hinge_untangle(sub.mesh, sub.fixed, beta, cap, first_delta);
        ++report.tries;
        report.work += hexes_in.size() * std::max<std::size_t>(1, run.iterations);
        wide.judge(sub);
      }
    }
    if (wide.keep_best(mesh)) {
      ++report.accepted;
      // Only the nodes of the widest sub-mesh's inner hexes moved: its hexes are all that
      // changed.
      for (const std::size_t h : layers.back()) sj[h] = hex_scaled_jacobian(mesh.points, hexes[h]);
    } else {
      skip[seed] = 1;
    }
  }
}

}  // namespace stcweave::primal
