/// `stcweave generate box A B C -o FILE [--hexes]` and `stcweave generate bar SHAPE -o FILE
/// [--hexes]`: write a generated shape (its quad surface, or with --hexes its natural hex
/// mesh, a reference for benchmarks). A thin shell over `primal/generate.hpp`.

#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "stcweave/primal/generate.hpp"
#include "stcweave/primal/io.hpp"

namespace stcweave::cli {
namespace {

struct GenerateArgs {
  int a = 1, b = 1, c = 1;
  std::string shape;
  std::string output;
  bool hexes = false;
  bool quiet = false;
};

int write_shape(const primal::HexMesh& mesh, const std::string& what, const GenerateArgs& g) {
  if (g.hexes) {
    primal::write_hex_mesh(mesh, g.output);
    if (!g.quiet)
      std::cout << what << ": " << mesh.complex.hexes.size() << " hexes -> " << g.output << "\n";
  } else {
    const primal::SurfaceMesh surface = primal::boundary_mesh(mesh);
    primal::write_surface(surface, g.output);
    if (!g.quiet)
      std::cout << what << ": " << surface.surface.quads.size() << " quads -> " << g.output << "\n";
  }
  return kSuccess;
}

void add_output_options(CLI::App* sub, GenerateArgs& g) {
  sub->add_option("-o,--output", g.output,
                  "output file; format from the extension (surface: .obj .off .vtk; with "
                  "--hexes: .vtk .vtu .msh .mesh .inp)")
      ->required();
  sub->add_flag("--hexes", g.hexes, "write the shape's hex mesh instead of its quad surface");
  sub->add_flag("-q,--quiet", g.quiet, "print nothing on success");
}

}  // namespace

Action add_generate_command(CLI::App& app) {
  auto box = std::make_shared<GenerateArgs>();
  auto bar = std::make_shared<GenerateArgs>();
  CLI::App* sub = app.add_subcommand(
      "generate", "Write a generated shape: a structured box or one of the seed's Fig. 5 bars.");
  sub->require_subcommand(1);

  CLI::App* box_cmd = sub->add_subcommand(
      "box",
      "The A x B x C box of unit cubes: its 2(AB+BC+CA) boundary quads, or with --hexes its "
      "A*B*C structured hexes.");
  box_cmd->add_option("A", box->a, "cubes along x")->required()->check(CLI::PositiveNumber);
  box_cmd->add_option("B", box->b, "cubes along y")->required()->check(CLI::PositiveNumber);
  box_cmd->add_option("C", box->c, "cubes along z")->required()->check(CLI::PositiveNumber);
  add_output_options(box_cmd, *box);

  std::string shapes;
  for (const std::string& n : primal::bar_shape_names()) shapes += (shapes.empty() ? "" : ", ") + n;
  CLI::App* bar_cmd = sub->add_subcommand(
      "bar",
      "A solid of the seed's Fig. 5: the 14-quad surface of a 1 x 1 x 3 bar on a straight, "
      "L-shaped or U-shaped bar or a thick plate (with --hexes: its 3 hexes).");
  bar_cmd->add_option("SHAPE", bar->shape, "one of: " + shapes)->required();
  add_output_options(bar_cmd, *bar);

  return [box_cmd, bar_cmd, box, bar]() -> int {
    if (box_cmd->parsed()) {
      const std::string what = "box " + std::to_string(box->a) + " x " + std::to_string(box->b) +
                               " x " + std::to_string(box->c);
      return write_shape(primal::box_hexes(box->a, box->b, box->c), what, *box);
    }
    if (bar_cmd->parsed())
      return write_shape(primal::bar_hexes(primal::bar_shape_from_name(bar->shape)),
                         "bar " + bar->shape, *bar);
    return kUsage;
  };
}

}  // namespace stcweave::cli
