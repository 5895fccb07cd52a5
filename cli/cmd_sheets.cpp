/// `stcweave sheets FILE [--json] [--graphml OUT] [--dot OUT] [--graph WHICH] [--format NAME]`:
/// the Spatial Twist Continuum of a hex mesh (sheets, chords, blind chords, self-intersecting
/// sheets, STC vertices, boundary points) and export of its graphs. A thin shell over
/// `stc::build_hex_stc` and `stc::write_graph_file`.

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/graph_io.hpp"
#include "stcweave/stc/hex_stc.hpp"

namespace stcweave::cli {
namespace {

struct SheetsOptions {
  std::string file;
  std::string format = "auto";  ///< auto: from the extension
  bool json = false;
  std::string graphml;
  std::string dot;
  std::string graph = "sheet";
};

std::vector<stc::StcGraph> graphs_from_name(const std::string& name) {
  if (name == "sheet") return {stc::StcGraph::Sheet};
  if (name == "dual") return {stc::StcGraph::Dual};
  return {stc::StcGraph::Dual, stc::StcGraph::Sheet};  // "both" (CLI11 checks the name)
}

nlohmann::json to_json(const primal::MeshFile& file, const stc::HexStc& stc) {
  nlohmann::json sheets = nlohmann::json::array();
  for (std::size_t s = 0; s < stc.sheets.size(); ++s) {
    const stc::Sheet& sheet = stc.sheets[s];
    nlohmann::json loop_lengths = nlohmann::json::array();
    for (const auto& loop : sheet.boundary_loops) loop_lengths.push_back(loop.size());
    sheets.push_back({{"id", SheetId(s).str()},
                      {"hexes", sheet.hexes.size()},
                      {"loops", sheet.boundary_loops.size()},
                      {"loop_lengths", loop_lengths},
                      {"chords", sheet.chords.size()},
                      {"self_intersecting", sheet.self_intersecting}});
  }
  nlohmann::json blind = nlohmann::json::array();
  for (std::size_t c = 0; c < stc.chords.size(); ++c) {
    if (stc::is_blind(stc.chords[c])) {
      blind.push_back({{"id", ChordId(c).str()},
                       {"hexes", stc.chords[c].hexes.size()},
                       {"sheets", {stc.chords[c].sheets[0].str(), stc.chords[c].sheets[1].str()}}});
    }
  }
  return {{"file", file.path},
          {"format", file.format},
          {"hexes", stc.num_hexes()},
          {"sheets", stc.sheets.size()},
          {"blind_sheets", stc::num_blind_sheets(stc)},
          {"self_intersecting_sheets", stc::num_self_intersecting_sheets(stc)},
          {"chords", stc.chords.size()},
          {"blind_chords", stc::num_blind_chords(stc)},
          {"boundary_points", stc.boundary_points.size()},
          {"sheet_list", sheets},
          {"blind_chord_list", blind}};
}

void print_report(const primal::MeshFile& file, const stc::HexStc& stc, std::ostream& out) {
  out << "file: " << file.path << " (" << file.format << ")\n";
  out << "hexes (STC vertices): " << stc.num_hexes() << "\n";
  out << "boundary points: " << stc.boundary_points.size() << "\n";
  out << "sheets: " << stc.sheets.size() << " (" << stc::num_blind_sheets(stc) << " blind, "
      << stc::num_self_intersecting_sheets(stc) << " self-intersecting)\n";
  out << "chords: " << stc.chords.size() << " (" << stc::num_blind_chords(stc) << " blind)\n";
  out << "blind chords:";
  constexpr std::size_t kShown = 20;
  std::size_t shown = 0;
  for (std::size_t c = 0; c < stc.chords.size(); ++c) {
    if (!stc::is_blind(stc.chords[c])) continue;
    if (shown++ < kShown)
      out << " " << ChordId(c) << " (" << stc.chords[c].hexes.size() << " hexes)";
  }
  if (shown == 0) out << " none";
  if (shown > kShown) out << " ... (" << shown << " in all)";
  out << "\n";
  out << "self-intersecting sheets:";
  shown = 0;
  for (std::size_t s = 0; s < stc.sheets.size(); ++s)
    if (stc.sheets[s].self_intersecting && shown++ < kShown) out << " " << SheetId(s);
  if (shown == 0) out << " none";
  if (shown > kShown) out << " ... (" << shown << " in all)";
  out << "\n";
  out << "per sheet: id hexes loops chords\n";
  for (std::size_t s = 0; s < stc.sheets.size(); ++s) {
    const stc::Sheet& sheet = stc.sheets[s];
    out << "  " << SheetId(s) << " " << sheet.hexes.size() << " " << sheet.boundary_loops.size()
        << " " << sheet.chords.size();
    if (stc::is_blind(sheet)) out << " blind";
    if (sheet.self_intersecting) out << " self-intersecting";
    out << "\n";
  }
}

}  // namespace

Action add_sheets_command(CLI::App& app) {
  auto options = std::make_shared<SheetsOptions>();
  CLI::App* cmd = app.add_subcommand(
      "sheets",
      "Build the Spatial Twist Continuum of a hex mesh and print it: hexes (STC vertices), "
      "boundary points (one per boundary quad), sheets (hexes, boundary loops and chords of "
      "each; blind and self-intersecting ones), chords (blind ones: rings that never meet "
      "the boundary). Optionally writes the sheet graph (vertex = sheet, edge = chord) "
      "and/or the dual graph (vertex = hex or boundary point, edge = face) as GraphML or "
      "GraphViz DOT, elements named by id (h3, q5, s2, c7). The STC of a non-manifold hex "
      "complex (a face in three hexes, a hex repeating a node, two hexes sharing two faces) is "
      "undefined: such a file is refused (exit code 2).");
  cmd->add_option("FILE", options->file,
                  "Hex mesh file (vtk, vtu, msh, mesh, mfem, inp) holding hexahedra")
      ->required();
  cmd->add_flag("--json", options->json,
                "Print one JSON object: counts, per-sheet hexes/loops/chords, blind chords");
  cmd->add_option("--graphml", options->graphml,
                  "Write the graph(s) chosen by --graph to OUT as GraphML")
      ->type_name("OUT");
  cmd->add_option("--dot", options->dot,
                  "Write the graph(s) chosen by --graph to OUT as GraphViz DOT")
      ->type_name("OUT");
  cmd->add_option("--graph", options->graph,
                  "Which graph --graphml/--dot write: sheet (default), dual, or both")
      ->check(CLI::IsMember({"sheet", "dual", "both"}));
  cmd->add_option("--format", options->format,
                  "Read FILE as this format instead of guessing from its extension (auto, the "
                  "default): vtk, vtu, "
                  "msh, msh2, medit, mfem, inp");
  return [options] {
    const primal::Format format = input_format(options->format);
    const primal::MeshFile file = primal::read_mesh(options->file, format);
    if (file.hexes.empty()) {
      throw InvalidInput("sheets needs a hex mesh; " + options->file + " has none (" +
                         std::to_string(file.quads.size()) +
                         " quads): give a volume mesh with hexahedra");
    }
    stc::HexComplex complex;
    complex.hexes = file.hexes;
    complex.num_nodes = static_cast<std::size_t>(file.points.rows());
    const stc::HexStc stc = stc::build_hex_stc(complex);
    const std::vector<stc::StcGraph> graphs = graphs_from_name(options->graph);
    if (!options->graphml.empty())
      stc::write_graph_file(options->graphml, stc, graphs, stc::GraphFormat::GraphMl);
    if (!options->dot.empty())
      stc::write_graph_file(options->dot, stc, graphs, stc::GraphFormat::Dot);
    if (options->json)
      std::cout << to_json(file, stc).dump(1) << "\n";
    else
      print_report(file, stc, std::cout);
    return kSuccess;
  };
}

}  // namespace stcweave::cli
