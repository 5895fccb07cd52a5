/// `stcweave quality HEX [--json]`: the Verdict quality figures of a hex mesh: scaled
/// Jacobian (min, mean, quantiles, histogram, counts below 0 and 0.2, worst hexes), Jacobian,
/// edge ratio, maximum aspect Frobenius (condition), and optionally the Bézier validity
/// certification of every hex. A report only: the exit code is 0 whatever the quality.

#include <array>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "commands.hpp"
#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::cli {
namespace {

struct QualityArgs {
  std::string mesh;
  std::string format = "auto";
  bool json = false;
  std::size_t worst = 10;
  int certify_depth = -1;  ///< < 0: no certification
};

/// A number for JSON: DBL_MAX and infinities (Verdict's "undefined") become null.
nlohmann::json finite_or_null(double v) {
  if (!std::isfinite(v) || v >= std::numeric_limits<double>::max()) return nullptr;
  return v;
}

std::string bin_label(std::size_t i) {
  std::array<char, 32> buf{};
  const double lo = -1.0 + 0.1 * static_cast<double>(i);
  std::snprintf(buf.data(), buf.size(), "[%+.1f, %+.1f%c", lo, lo + 0.1, i == 19 ? ']' : ')');
  return buf.data();
}

int run_quality(const QualityArgs& a) {
  const primal::MeshFile file = primal::read_mesh(a.mesh, input_format(a.format));
  if (file.hexes.empty())
    throw InvalidInput("quality needs a hex mesh; " + a.mesh +
                       " has no hexahedra (a surface? mesh it first with `stcweave mesh`)");
  primal::require_finite_hex_nodes(file);
  primal::HexMesh mesh;
  mesh.points = file.points;
  mesh.complex.hexes = file.hexes;
  mesh.complex.num_nodes = static_cast<std::size_t>(file.points.rows());
  const primal::QualitySummary q = primal::summarize_quality(mesh, a.worst);
  std::optional<primal::ValidityCounts> certified;
  if (a.certify_depth >= 0) certified = primal::count_bezier_validity(mesh, a.certify_depth);

  if (a.json) {
    nlohmann::json j;
    j["file"] = a.mesh;
    j["hexes"] = q.hexes;
    j["nodes"] = mesh.points.rows();
    nlohmann::json quantiles = nlohmann::json::object();
    for (std::size_t i = 0; i < q.quantiles.size(); ++i) {
      std::ostringstream key;
      key << primal::QualitySummary::kQuantileLevels[i];
      quantiles[key.str()] = q.quantiles[i];
    }
    nlohmann::json histogram = nlohmann::json::array();
    for (std::size_t i = 0; i < q.histogram.size(); ++i) {
      histogram.push_back({{"from", -1.0 + 0.1 * static_cast<double>(i)},
                           {"to", -0.9 + 0.1 * static_cast<double>(i)},
                           {"count", q.histogram[i]}});
    }
    nlohmann::json worst = nlohmann::json::array();
    for (const HexId h : q.worst)
      worst.push_back({{"hex", h.str()}, {"scaled_jacobian", q.per_hex[h.index()]}});
    j["scaled_jacobian"] = {{"includes_centre", true},        {"min", q.min_scaled_jacobian},
                            {"mean", q.mean_scaled_jacobian}, {"quantiles", quantiles},
                            {"histogram", histogram},         {"inverted", q.inverted},
                            {"below_0", q.negative},          {"below_0_2", q.below_0_2},
                            {"below_0_5", q.below_0_5},       {"worst", worst}};
    j["corner_inverted"] = q.corner_inverted;
    j["min_jacobian"] = q.min_jacobian;
    j["max_edge_ratio"] = finite_or_null(q.max_edge_ratio);
    j["max_aspect_frobenius"] = finite_or_null(q.max_aspect_frobenius);
    if (certified) {
      j["bezier"] = {{"depth", a.certify_depth},
                     {"valid", certified->valid},
                     {"invalid", certified->invalid},
                     {"uncertain", certified->uncertain}};
    }
    std::cout << j.dump(1) << "\n";
    return kSuccess;
  }

  std::cout << a.mesh << ": " << q.hexes << " hexes, " << mesh.points.rows() << " nodes\n";
  std::cout << "scaled Jacobian (Verdict, 8 corners + centre)\n";
  std::cout << "  min " << q.min_scaled_jacobian << ", mean " << q.mean_scaled_jacobian << "\n";
  std::cout << "  quantiles";
  for (std::size_t i = 0; i < q.quantiles.size(); ++i)
    std::cout << "  " << primal::QualitySummary::kQuantileLevels[i] << ": " << q.quantiles[i];
  std::cout << "\n  <= 0 (inverted) " << q.inverted << ", < 0 " << q.negative << ", < 0.2 "
            << q.below_0_2 << ", < 0.5 " << q.below_0_5 << "\n";
  std::cout << "  histogram\n";
  for (std::size_t i = 0; i < q.histogram.size(); ++i)
    if (q.histogram[i] > 0)
      std::cout << "    " << bin_label(i) << " " << std::setw(8) << q.histogram[i] << "\n";
  std::cout << "  worst";
  for (const HexId h : q.worst) std::cout << " " << h.str() << " (" << q.per_hex[h.index()] << ")";
  std::cout << "\n";
  std::cout << "hexes with a corner determinant <= 0 " << q.corner_inverted << "\n";
  std::cout << "min Jacobian " << q.min_jacobian << "\n";
  const auto show = [](double v) {
    return std::isfinite(v) && v < std::numeric_limits<double>::max() ? std::to_string(v)
                                                                      : std::string("undefined");
  };
  std::cout << "max edge ratio " << show(q.max_edge_ratio) << "\n";
  std::cout << "max aspect Frobenius (condition) " << show(q.max_aspect_frobenius)
            << (q.corner_inverted > 0 ? " (undefined on inverted corners)" : "") << "\n";
  if (certified) {
    std::cout << "Bezier certification (depth " << a.certify_depth << "): valid "
              << certified->valid << ", invalid " << certified->invalid << ", undecided "
              << certified->uncertain << "\n";
  }
  return kSuccess;
}

}  // namespace

Action add_quality_command(CLI::App& app) {
  auto args = std::make_shared<QualityArgs>();
  CLI::App* sub = app.add_subcommand(
      "quality",
      "Report the quality of a hex mesh with the Verdict definitions: scaled Jacobian (min, "
      "mean, quantiles, histogram, counts below 0 and 0.2, worst hexes), Jacobian, edge "
      "ratio, maximum aspect Frobenius; --certify adds the exact (Bezier) validity test. Exit "
      "code 0 whatever the quality, 2 when the file cannot be used.");
  sub->add_option("mesh", args->mesh, "hex mesh (VTK, VTU, MSH, MEDIT, MFEM, INP)")->required();
  sub->add_option("--format", args->format, "mesh format name (default: auto)");
  sub->add_flag("--json", args->json, "print a JSON report");
  sub->add_option("--worst", args->worst, "how many of the worst hexes to list")
      ->capture_default_str();
  sub->add_option("--certify", args->certify_depth,
                  "certify every hex with the Bezier test, subdividing up to this depth")
      ->check(CLI::Range(0, 8));
  return [args] { return run_quality(*args); };
}

}  // namespace stcweave::cli
