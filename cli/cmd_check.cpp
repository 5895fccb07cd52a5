/// `stcweave check HEX [--boundary SURFACE]`: certifies a hex mesh against the hex-complex
/// invariants (DESIGN.md "Invariants"), optionally against an expected boundary surface
/// whose nodes are matched to the mesh's by coordinates. Reports inverted hexes as well.

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/validate.hpp"

namespace stcweave::cli {
namespace {

struct CheckArgs {
  std::string mesh;
  std::string boundary;
  std::string format = "auto";
  bool json = false;
};

/// The quads of `surface` expressed with the node ids of `mesh`, matching nodes whose
/// coordinates agree within 1e-9 of the mesh's bounding-box diagonal.
stc::QuadSurface match_boundary(const primal::HexMesh& mesh, const primal::SurfaceMesh& surface,
                                const std::string& name) {
  const Eigen::RowVector3d lo = mesh.points.colwise().minCoeff();
  const Eigen::RowVector3d hi = mesh.points.colwise().maxCoeff();
  const double tol = std::max(1e-300, 1e-9 * (hi - lo).norm());
  std::map<std::array<long long, 3>, std::vector<NodeId>> grid;
  const auto cell = [tol](const Eigen::RowVector3d& p) {
    return std::array<long long, 3>{static_cast<long long>(std::floor(p.x() / tol)),
                                    static_cast<long long>(std::floor(p.y() / tol)),
                                    static_cast<long long>(std::floor(p.z() / tol))};
  };
  for (Eigen::Index i = 0; i < mesh.points.rows(); ++i)
    grid[cell(mesh.points.row(i))].push_back(NodeId(static_cast<std::int32_t>(i)));
  std::vector<NodeId> map(static_cast<std::size_t>(surface.points.rows()), NodeId::invalid());
  for (Eigen::Index i = 0; i < surface.points.rows(); ++i) {
    const Eigen::RowVector3d p = surface.points.row(i);
    const auto c = cell(p);
    double best = tol;
    for (long long dx = -1; dx <= 1; ++dx) {
      for (long long dy = -1; dy <= 1; ++dy) {
        for (long long dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (NodeId n : it->second) {
            const double d = (mesh.points.row(n.value()) - p).norm();
            if (d <= best) {
              best = d;
              map[static_cast<std::size_t>(i)] = n;
            }
          }
        }
      }
    }
  }
  stc::QuadSurface out;
  out.num_nodes = mesh.complex.num_nodes;
  for (std::size_t q = 0; q < surface.surface.quads.size(); ++q) {
    stc::Quad quad{};
    for (std::size_t k = 0; k < 4; ++k) {
      const NodeId n = surface.surface.quads[q][k];
      quad[k] = map[n.index()];
      if (!quad[k].is_valid()) {
        throw InvalidInput(name + ": node " + n.str() + " of boundary quad " + QuadId(q).str() +
                           " matches no node of the hex mesh (coordinates differ by more than "
                           "1e-9 of the bounding box): is this the right boundary?");
      }
    }
    out.quads.push_back(quad);
  }
  return out;
}

int run_check(const CheckArgs& a) {
  const primal::MeshFile file = primal::read_mesh(a.mesh, input_format(a.format));
  if (file.hexes.empty())
    throw InvalidInput("check needs a hex mesh; " + a.mesh + " has no hexahedra");
  primal::require_finite_hex_nodes(file);
  primal::HexMesh mesh;
  mesh.points = file.points;
  mesh.complex.hexes = file.hexes;
  mesh.complex.num_nodes = static_cast<std::size_t>(file.points.rows());
  std::optional<stc::QuadSurface> expected;
  if (!a.boundary.empty()) {
    const primal::MeshFile bfile = primal::read_mesh(a.boundary);
    expected = match_boundary(mesh, primal::surface_of(bfile), a.boundary);
  }
  const stc::ValidationReport v =
      stc::validate_hex_complex(mesh.complex, expected ? &*expected : nullptr, false, true);
  const primal::QualitySummary q = primal::summarize_quality(mesh);
  if (a.json) {
    nlohmann::json j;
    j["file"] = a.mesh;
    j["hexes"] = mesh.complex.hexes.size();
    j["valid"] = v.valid;
    j["boundary_compared"] = v.boundary_compared;
    nlohmann::json violations = nlohmann::json::array();
    for (const auto& viol : v.violations) {
      violations.push_back({{"invariant", std::string(viol.name())},
                            {"count", viol.count},
                            {"examples", viol.examples}});
    }
    j["violations"] = violations;
    j["euler_volume"] = v.euler_volume;
    j["euler_boundary"] = v.euler_boundary;
    j["inverted_hexes"] = q.inverted;
    j["min_scaled_jacobian"] = q.min_scaled_jacobian;
    j["mean_scaled_jacobian"] = q.mean_scaled_jacobian;
    std::cout << j.dump(1) << "\n";
  } else {
    std::cout << a.mesh << ": " << mesh.complex.hexes.size() << " hexes, "
              << (v.valid ? "valid hex complex" : "INVALID: " + v.summary());
    if (v.boundary_compared) std::cout << (v.valid ? ", boundary matches " + a.boundary : "");
    std::cout << "\n  inverted hexes " << q.inverted << ", min scaled Jacobian "
              << q.min_scaled_jacobian << ", mean " << q.mean_scaled_jacobian << "\n";
  }
  return v.valid ? kSuccess : kInvalidInput;
}

}  // namespace

Action add_check_command(CLI::App& app) {
  auto args = std::make_shared<CheckArgs>();
  CLI::App* sub = app.add_subcommand(
      "check",
      "Certify a hex mesh: 8 distinct nodes per hex, faces in at most two hexes, two hexes "
      "share at most one face, two hexes sharing four or more nodes share exactly a face of both, "
      "one cycle (fan) of hexes around every interior (boundary) edge, "
      "vertex links, Euler characteristic; with --boundary, the faces used once must be "
      "exactly that surface's quads (nodes matched by coordinates). Exit code 0 when valid, "
      "2 when not.");
  sub->add_option("mesh", args->mesh, "hex mesh (VTK, VTU, MSH, MEDIT, MFEM, INP)")->required();
  sub->add_option("--boundary", args->boundary, "expected boundary quad surface");
  sub->add_option("--format", args->format, "mesh format name (default: auto)");
  sub->add_flag("--json", args->json, "print a JSON report");
  return [args] { return run_check(*args); };
}

}  // namespace stcweave::cli
