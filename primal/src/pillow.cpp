#include "stcweave/primal/pillow.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "shells.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/shared_nodes.hpp"

namespace stcweave::primal {
namespace {

/// Scaled Jacobian of corner `k` of hex `h`: det of the three unit edge vectors (0 when an
/// edge has zero length).
double corner_scaled_jacobian(const Points& p, const stc::Hex& h, int k) {
  const auto& c = kHexCorners[static_cast<std::size_t>(k)];
  const auto row = [&](int local) -> Eigen::Vector3d {
    return p.row(static_cast<Eigen::Index>(h[static_cast<std::size_t>(local)].index())).transpose();
  };
  const Eigen::Vector3d o = row(c[0]);
  const Eigen::Vector3d e1 = row(c[1]) - o;
  const Eigen::Vector3d e2 = row(c[2]) - o;
  const Eigen::Vector3d e3 = row(c[3]) - o;
  const double scale = e1.norm() * e2.norm() * e3.norm();
  if (!(scale > 0.0)) return 0.0;
  return e1.dot(e2.cross(e3)) / scale;
}

void check_nodes(const HexMesh& mesh) {
  const auto n = static_cast<std::size_t>(mesh.points.rows());
  if (n != mesh.complex.num_nodes) {
    throw InvalidInput("pillow: the point matrix has " + std::to_string(n) +
                       " rows for a complex of " + std::to_string(mesh.complex.num_nodes) +
                       " nodes");
  }
  for (std::size_t h = 0; h < mesh.complex.hexes.size(); ++h) {
    for (const NodeId v : mesh.complex.hexes[h]) {
      if (!v.is_valid() || v.index() >= n) {
        throw InvalidInput("pillow: hex " + HexId(h).str() + " names node " + v.str() +
                           ", outside the " + std::to_string(n) + " nodes");
      }
    }
  }
}

std::string format_value(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

/// For each shell, a pair of its boundary quads that share two nodes that are not an edge of
/// both (empty when none): their pillow hexes would share those two nodes and their two copies,
/// four nodes that are not a face, so the layer would not be a valid complex.
std::vector<std::string> diagonal_contacts(const stc::QuadSurface& boundary,
                                           const std::vector<int>& shell, std::size_t shells) {
  std::vector<std::string> found(shells);
  for (const stc::SharedNodesPair& p : stc::pairs_sharing_nodes(boundary.quads, 2)) {
    if (p.shared != 2) continue;
    const stc::Quad& qa = boundary.quads[p.first];
    const int sh = shell[qa[0].index()];
    if (stc::shares_a_side(qa, boundary.quads[p.second]) || sh < 0 ||
        !found[static_cast<std::size_t>(sh)].empty())
      continue;
    found[static_cast<std::size_t>(sh)] = QuadId(p.first).str() + " and " + QuadId(p.second).str();
  }
  return found;
}

}  // namespace

std::string to_string(PillowMode mode) {
  switch (mode) {
    case PillowMode::Auto:
      return "auto";
    case PillowMode::Always:
      return "always";
    case PillowMode::Never:
      return "never";
  }
  return "?";
}

PillowMode pillow_mode_from_name(const std::string& name) {
  if (name == "auto") return PillowMode::Auto;
  if (name == "always") return PillowMode::Always;
  if (name == "never") return PillowMode::Never;
  throw InvalidInput("unknown pillow mode '" + name + "': use auto, always or never");
}

PillowReport assess_pillow(const HexMesh& mesh, std::size_t num_boundary_nodes,
                           const PillowOptions& options) {
  check_nodes(mesh);
  PillowReport r;
  r.mode = options.mode;
  for (std::size_t h = 0; h < mesh.complex.hexes.size(); ++h) {
    const stc::Hex& x = mesh.complex.hexes[h];
    for (int k = 0; k < 8; ++k) {
      const auto& c = kHexCorners[static_cast<std::size_t>(k)];
      if (!std::all_of(c.begin(), c.end(), [&](int local) {
            return x[static_cast<std::size_t>(local)].index() < num_boundary_nodes;
          }))
        continue;
      ++r.fixed_corners;
      const double sj = corner_scaled_jacobian(mesh.points, x, k);
      if (sj < options.min_fixed_corner) ++r.bad_fixed_corners;
      if (sj < r.worst_fixed_corner || !r.worst_hex.is_valid()) {
        r.worst_fixed_corner = sj;
        r.worst_hex = HexId(h);
        r.worst_corner = k;
      }
    }
  }
  return r;
}

PillowReport pillow(HexMesh& mesh, const stc::QuadSurface& boundary, const PillowOptions& options) {
  check_nodes(mesh);
  if (!(options.offset > 0.0 && options.offset < 1.0))
    throw InvalidInput("pillow: offset " + format_value(options.offset) +
                       " is not in ]0, 1[ (a fraction of the mean boundary edge length)");
  const std::size_t nb = boundary.num_nodes;
  if (nb > mesh.complex.num_nodes)
    throw InvalidInput("pillow: the boundary has more nodes than the complex");
  for (std::size_t q = 0; q < boundary.quads.size(); ++q) {
    for (const NodeId v : boundary.quads[q]) {
      if (!v.is_valid() || v.index() >= nb) {
        throw InvalidInput("pillow: boundary quad " + QuadId(q).str() + " names node " + v.str() +
                           ", outside the boundary's " + std::to_string(nb) + " nodes");
      }
    }
  }

  PillowReport r = assess_pillow(mesh, nb, options);
  std::vector<int> shell = shell_of_nodes(boundary, &r.shells);

  // Which shells: all (Always), none (Never), those holding a bad fixed corner (Auto).
  std::vector<bool> selected(r.shells, options.mode == PillowMode::Always);
  if (options.mode == PillowMode::Auto) {
    for (const stc::Hex& x : mesh.complex.hexes) {
      for (int k = 0; k < 8; ++k) {
        const auto& c = kHexCorners[static_cast<std::size_t>(k)];
        // The shells of the corner's four nodes (a corner can join two shells: the column hex
        // of a cavity's cut, docs/topology.md); every one of them is selected by a bad corner.
        std::array<std::size_t, 4> shells{};
        bool fixed = true;
        for (std::size_t i = 0; i < 4 && fixed; ++i) {
          const NodeId v = x[static_cast<std::size_t>(c[i])];
          fixed = v.index() < nb && shell[v.index()] >= 0;
          if (fixed) shells[i] = static_cast<std::size_t>(shell[v.index()]);
        }
        if (!fixed ||
            std::all_of(shells.begin(), shells.end(), [&](std::size_t s) { return selected[s]; }))
          continue;
        if (corner_scaled_jacobian(mesh.points, x, k) < options.min_fixed_corner) {
          for (std::size_t s : shells) selected[s] = true;
        }
      }
    }
  }
  // A shell two of whose quads meet at two opposite nodes is not pillowed (the layer would
  // hold two hexes sharing four nodes off a face: not a valid complex).
  std::string skipped;
  const std::vector<std::string> diagonal = diagonal_contacts(boundary, shell, r.shells);
  for (std::size_t sh = 0; sh < r.shells; ++sh) {
    if (diagonal[sh].empty()) continue;
    r.unpillowable += (r.unpillowable.empty() ? "" : ", ") + diagonal[sh];
    if (!selected[sh]) continue;
    selected[sh] = false;
    skipped += (skipped.empty() ? "" : ", ") + diagonal[sh];
  }
  if (!skipped.empty()) {
    skipped =
        "; a shell left unpillowed because two of its quads share two nodes that are not "
        "an edge (" +
        skipped + "): their pillow hexes would share four nodes off a face";
  }
  r.shells_pillowed = static_cast<std::size_t>(std::count(selected.begin(), selected.end(), true));
  r.applied = r.shells_pillowed > 0;

  const std::string worst =
      r.fixed_corners == 0
          ? std::string("no hex corner has all four nodes on the boundary")
          : std::to_string(r.bad_fixed_corners) + " of " + std::to_string(r.fixed_corners) +
                " hex corners with all four nodes on the boundary have a scaled Jacobian below " +
                format_value(options.min_fixed_corner) + " (worst " +
                format_value(r.worst_fixed_corner) + " at " + r.worst_hex.str() + " corner " +
                std::to_string(r.worst_corner) + ")";
  switch (options.mode) {
    case PillowMode::Never:
      r.reason = "never: not pillowed (" + worst + ")";
      break;
    case PillowMode::Always:
      r.reason =
          (skipped.empty() ? "always: every shell pillowed (" : "always: pillowed (") + worst + ")";
      break;
    case PillowMode::Auto:
      r.reason = r.applied ? "auto: pillowed " + std::to_string(r.shells_pillowed) + " of " +
                                 std::to_string(r.shells) + " shells because " + worst +
                                 ": no placement of the interior nodes can raise those"
                           : "auto: not pillowed: " + worst;
      break;
  }
  r.reason += skipped;
  if (!r.applied) return r;

  // Interior copies of the boundary nodes of the selected shells, in node order.
  const std::size_t n0 = mesh.complex.num_nodes;
  std::vector<NodeId> copy(nb);
  std::size_t next = n0;
  for (std::size_t v = 0; v < nb; ++v)
    if (shell[v] >= 0 && selected[static_cast<std::size_t>(shell[v])]) copy[v] = NodeId(next++);
  r.nodes_added = next - n0;

  // Vertex normals (area-weighted: the cross product of the diagonals is twice the quad's
  // vector area, outward) and mean boundary edge lengths.
  Points normal = Points::Zero(static_cast<Eigen::Index>(nb), 3);
  std::vector<double> length(nb, 0.0);
  std::vector<int> sides(nb, 0);
  const auto at = [&](NodeId v) -> Eigen::RowVector3d {
    return mesh.points.row(static_cast<Eigen::Index>(v.index()));
  };
  for (const auto& q : boundary.quads) {
    const Eigen::Vector3d d1 = (at(q[2]) - at(q[0])).transpose();
    const Eigen::Vector3d d2 = (at(q[3]) - at(q[1])).transpose();
    const Eigen::RowVector3d area = d1.cross(d2).transpose();
    for (int i = 0; i < 4; ++i) {
      const NodeId a = q[static_cast<std::size_t>(i)];
      const NodeId b = q[static_cast<std::size_t>((i + 1) % 4)];
      normal.row(static_cast<Eigen::Index>(a.index())) += area;
      const double l = (at(b) - at(a)).norm();
      length[a.index()] += l;
      length[b.index()] += l;
      sides[a.index()] += 1;
      sides[b.index()] += 1;
    }
  }
  // Centroid per shell: the fallback direction for a node whose normal vanishes.
  std::vector<Eigen::RowVector3d> centre(r.shells, Eigen::RowVector3d::Zero());
  std::vector<int> members(r.shells, 0);
  for (std::size_t v = 0; v < nb; ++v) {
    if (shell[v] < 0) continue;
    centre[static_cast<std::size_t>(shell[v])] += at(NodeId(v));
    ++members[static_cast<std::size_t>(shell[v])];
  }
  for (std::size_t s = 0; s < r.shells; ++s)
    if (members[s] > 0) centre[s] /= members[s];

  mesh.points.conservativeResize(static_cast<Eigen::Index>(next), 3);
  for (std::size_t v = 0; v < nb; ++v) {
    if (!copy[v].is_valid()) continue;
    const Eigen::RowVector3d p = at(NodeId(v));
    Eigen::RowVector3d inward = -normal.row(static_cast<Eigen::Index>(v));
    if (!(inward.norm() > 0.0)) inward = centre[static_cast<std::size_t>(shell[v])] - p;
    if (inward.norm() > 0.0) inward.normalize();
    const double step = sides[v] > 0 ? options.offset * length[v] / sides[v] : 0.0;
    mesh.points.row(static_cast<Eigen::Index>(copy[v].index())) = p + step * inward;
  }

  // Woven hexes move to the copies; one new hex per boundary quad of a pillowed shell, in
  // VTK order with the quad as its outward face 0 (kHexFaces: 0-3-2-1) and the copy on top.
  for (stc::Hex& x : mesh.complex.hexes)
    for (NodeId& v : x)
      if (v.index() < nb && copy[v.index()].is_valid()) v = copy[v.index()];
  for (const auto& q : boundary.quads) {
    if (!copy[q[0].index()].is_valid()) continue;
    mesh.complex.hexes.push_back({q[0], q[3], q[2], q[1], copy[q[0].index()], copy[q[3].index()],
                                  copy[q[2].index()], copy[q[1].index()]});
    ++r.hexes_added;
  }
  mesh.complex.num_nodes = next;
  return r;
}

}  // namespace stcweave::primal
