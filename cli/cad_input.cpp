#include "cad_input.hpp"

#include <iostream>

#include "commands.hpp"
#include "stcweave/primal/diagnose.hpp"

namespace stcweave::cli {

void add_cad_options(CLI::App* sub, CadArgs& args, const std::string& input) {
  const std::string group = "CAD input (STEP, BREP, IGES)";
  CLI::Option* size =
      sub->add_option("--size", args.size,
                      "CAD input: target edge length of the surface quads (default: a tenth of "
                      "the solid's bounding box diagonal)")
          ->check(kFinite)
          ->check(CLI::PositiveNumber)
          ->group(group);
  CLI::Option* recipe =
      sub->add_option("--cad-recipe", args.recipe,
                      "CAD input: auto (transfinite when every CAD face has 4 corners, mixed "
                      "when some have and the result is loop-clean, else triangle-split), "
                      "transfinite, triangle-split (Gmsh triangles, each split into 3 quads), "
                      "or mixed (4-cornered faces structured, the others split; checked "
                      "loop-clean, else triangle-split)")
          ->check(CLI::IsMember({"auto", "transfinite", "triangle-split", "mixed"}))
          ->capture_default_str()
          ->group(group);
  CLI::Option* algorithm =
      sub->add_option("--cad-triangles", args.triangle_algorithm,
                      "CAD input: Gmsh's triangle algorithm for the split faces: 1 MeshAdapt, "
                      "5 Delaunay, 6 Frontal-Delaunay")
          ->check(
              [](const std::string& value) -> std::string {
                if (value == "1" || value == "5" || value == "6") return {};
                return "must be 1 (MeshAdapt), 5 (Delaunay) or 6 (Frontal-Delaunay), not '" +
                       value + "'";
              },
              "1|5|6")
          ->capture_default_str()
          ->group(group);
  CLI::Option* no_split =
      sub->add_flag("--no-cad-split", args.no_split,
                    "CAD input: do not split a recognised solid (a cylinder, a sphere, a solid "
                    "of planar faces) into blocks whose faces all have four corners before "
                    "meshing its surface")
          ->group(group);
  sub->add_option("--surface-out", args.surface_out,
                  "write the quad surface that is woven (.obj, .off, .vtk): for a CAD input, "
                  "the surface Gmsh made")
      ->group(group);
  sub->parse_complete_callback([size, recipe, algorithm, no_split, &input] {
    if ((size->count() > 0 || recipe->count() > 0 || algorithm->count() > 0 ||
         no_split->count() > 0) &&
        !primal::is_cad_path(input)) {
      throw CLI::ValidationError("--size/--cad-recipe/--cad-triangles/--no-cad-split",
                                 "apply to CAD inputs only (.step, .stp, .brep, .iges, .igs), "
                                 "not to " +
                                     input);
    }
  });
}

InputSurface read_input(const std::string& input, primal::Format format, const CadArgs& args,
                        bool progress, bool quiet) {
  InputSurface in;
  if (primal::is_cad_path(input) && format == primal::Format::Auto) {
    primal::CadOptions options;
    options.size = args.size;
    options.recipe = primal::cad_recipe_from_name(args.recipe);
    options.triangle_algorithm = args.triangle_algorithm;
    options.verbose = progress;
    options.split = !args.no_split;
    primal::CadSurface cad = primal::mesh_cad_surface(input, options);
    in.file = std::move(cad.file);
    in.cad = std::move(cad.record);
    if (!quiet) {
      const primal::CadRecord& r = *in.cad;
      std::cout << "cad        " << r.volumes << " solid(s), " << r.faces
                << " faces: " << primal::cad_recipe_name(r.recipe) << " surface, size " << r.size
                << ", " << r.quads << " quads (" << r.reason << ")\n";
    }
  } else {
    in.file = primal::read_mesh(input, format);
  }
  if (!args.surface_out.empty()) {
    primal::SurfaceMesh surface = primal::surface_of(in.file);
    const primal::SurfaceDiagnosis d = primal::diagnose(in.file);
    if (d.closed && d.manifold && d.orientable.value_or(false)) primal::orient_outward(surface);
    primal::write_surface(surface, args.surface_out);
  }
  return in;
}

nlohmann::json cad_json(const primal::CadRecord& r) {
  return {{"path", r.path},
          {"format", r.format},
          {"gmsh_version", r.gmsh_version},
          {"recipe", primal::cad_recipe_name(r.recipe)},
          {"reason", r.reason},
          {"split", r.split},
          {"size", r.size},
          {"volumes", r.volumes},
          {"faces", r.faces},
          {"curves", r.curves},
          {"triangles", r.triangles},
          {"structured_faces", r.structured_faces},
          {"quads", r.quads},
          {"nodes", r.nodes},
          {"max_cad_distance", r.max_cad_distance},
          {"warnings", r.warnings},
          {"seconds", r.seconds}};
}

}  // namespace stcweave::cli
