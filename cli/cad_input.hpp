#pragma once
/// \file
/// The CAD front end of `stcweave mesh` (issue 15): `--size`, `--cad-recipe`,
/// `--cad-triangles`, `--no-cad-split` and `--surface-out`, and the reading of the input, a CAD
/// solid (STEP, BREP, IGES: meshed into a quad surface by `primal::mesh_cad_surface`) or any mesh
/// file
/// (`primal::read_mesh`).

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "stcweave/primal/cad.hpp"
#include "stcweave/primal/io.hpp"

namespace stcweave::cli {

struct CadArgs {
  double size = 0.0;            ///< --size (0: a tenth of the bounding box diagonal)
  std::string recipe = "auto";  ///< --cad-recipe
  int triangle_algorithm = primal::CadOptions{}.triangle_algorithm;  ///< --cad-triangles
  std::string surface_out;                                           ///< --surface-out
  bool no_split = false;                                             ///< --no-cad-split
};

/// Adds --size, --cad-recipe, --cad-triangles and --surface-out to `sub`, in an option group "CAD
/// input". `input` is the subcommand's input path: --size, --cad-recipe and --cad-triangles on a
/// non-CAD input are usage errors.
void add_cad_options(CLI::App* sub, CadArgs& args, const std::string& input);

/// The input as read, and what the CAD front end did when it was a CAD file.
struct InputSurface {
  primal::MeshFile file;
  std::optional<primal::CadRecord> cad;
};

/// Reads `input`: a CAD file through `primal::mesh_cad_surface` (Gmsh prints only with
/// `progress`; unless `quiet`, one line on stdout says the recipe and the quads), anything
/// else through `primal::read_mesh`. With --surface-out, writes the quad surface (oriented
/// outward when it is closed, manifold and orientable).
/// \throw as `primal::mesh_cad_surface` and `primal::read_mesh`.
[[nodiscard]] InputSurface read_input(const std::string& input, primal::Format format,
                                      const CadArgs& args, bool progress, bool quiet);

/// The CAD record as it appears under "cad" in the mesh report.
[[nodiscard]] nlohmann::json cad_json(const primal::CadRecord& record);

}  // namespace stcweave::cli
