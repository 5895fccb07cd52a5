/// `stcweave loops FILE [--json] [--format NAME]`: the diagnosis of a quad surface (or of a
/// hex mesh's boundary) and of its loops. A thin shell over `primal::diagnose`.

#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::cli {
namespace {

struct LoopsOptions {
  std::string file;
  std::string format = "auto";  ///< auto: from the extension
  bool json = false;
};

std::string yes_no(bool b) {
  return b ? "yes" : "no";
}

template <class T>
std::string or_none(const std::optional<T>& v) {
  return v ? std::to_string(*v) : std::string("undefined");
}

/// One line per figure.
void print_report(const primal::SurfaceDiagnosis& d, std::ostream& out) {
  out << "file: " << d.path << " (" << d.format << ")\n";
  if (d.from_hexes)
    out << "source: boundary of " << d.hexes << " hexes\n";
  else
    out << "source: quads of the file\n";
  if (d.triangles + d.tetrahedra + d.other_cells > 0)
    out << "other cells: " << d.triangles << " triangles, " << d.tetrahedra << " tetrahedra, "
        << d.other_cells << " other\n";
  out << "quads: " << d.quads << " (" << (d.has_even_quads() ? "even" : "odd") << ")\n";
  out << "nodes: " << d.nodes << "\n";
  out << "components: " << d.components << "\n";
  out << "closed: " << yes_no(d.closed) << " (" << d.open_edges << " open edges)\n";
  out << "manifold: " << yes_no(d.manifold) << " (" << d.nonmanifold_edges
      << " non-manifold edges, " << d.nonmanifold_nodes << " non-manifold nodes)\n";
  out << "consistently oriented: " << yes_no(d.consistently_oriented) << " ("
      << d.inconsistent_edges << " edges traversed twice the same way)\n";
  out << "orientable: "
      << (d.orientable ? yes_no(*d.orientable) : std::string("not checked (hex mesh)")) << "\n";
  out << "euler characteristic: " << d.euler_characteristic << "\n";
  out << "genus: " << or_none(d.genus);
  if (d.genus_per_component.size() > 1) {
    out << " (per component:";
    for (const auto& g : d.genus_per_component) out << " " << or_none(g);
    out << ")";
  }
  out << "\n";
  out << "degenerate quads: " << d.degenerate_quads << "\n";
  out << "duplicate quads: " << d.duplicate_quads << "\n";
  out << "non-finite nodes: " << d.nonfinite_nodes << "\n";
  out << "quad pairs crossing each other: " << or_none(d.crossing_quad_pairs) << "\n";
  out << "coincident nodes: " << d.coincident_nodes << "\n";
  if (d.loops) {
    out << "loops: " << *d.loops << ", longest " << *d.longest_loop;
    if (*d.open_loops > 0) out << ", " << *d.open_loops << " open";
    out << "\n";
    out << "self-intersecting loops: " << *d.self_intersecting_loops << " ("
        << *d.self_crossing_quads << " quads crossed twice)\n";
    for (const primal::SelfIntersection& s : d.sites.self_intersecting_loops) {
      out << "  " << s.loop << " (" << s.length << " quads) crosses itself in";
      constexpr std::size_t kShown = 10;
      for (std::size_t i = 0; i < s.quads.size() && i < kShown; ++i) out << " " << s.quads[i];
      if (s.quads.size() > kShown) out << " ... (" << s.quads.size() << " quads)";
      out << "\n";
    }
  } else {
    out << "loops: undefined (non-manifold edges)\n";
  }
  if (d.handles) {
    const primal::HandleDiagnosis& h = *d.handles;
    if (!h.decided) {
      out << "handles: undecided (" << h.undecided_reason << ")\n";
    } else {
      out << "handles: " << h.genus << " (cycles that bound inside the solid, by linking "
          << "numbers; " << (h.all_even() ? "all even" : "one is odd: no hex mesh exists") << ")\n";
      for (const primal::HandleCycle& c : h.handles) {
        out << "  " << c.component << ": " << c.length() << " edges ("
            << (c.is_even() ? "even" : "odd") << "): ";
        constexpr std::size_t kShown = 24;
        if (c.length() <= kShown) {
          out << primal::cycle_name(c);
        } else {
          primal::HandleCycle first = c;
          first.nodes.resize(kShown);
          out << primal::cycle_name(first) << "-...";
        }
        out << "\n";
      }
      for (std::size_t len : h.combined_lengths)
        out << "  over several shells: " << len << " edges (" << (len % 2 == 0 ? "even" : "odd")
            << ")\n";
    }
  }
  if (const std::string crossing = primal::crossing_warning(d); !crossing.empty())
    out << "warning: " << crossing << "\n";
  try {
    primal::require_weavable(d);
    out << "weavable: yes\n";
  } catch (const TopologyError& e) {
    out << "weavable: no: " << e.what() << "\n";
  }
}

}  // namespace

Action add_loops_command(CLI::App& app) {
  auto options = std::make_shared<LoopsOptions>();
  CLI::App* cmd = app.add_subcommand(
      "loops",
      "Diagnose a quad surface (or the boundary of a hex mesh) and its loops: quads, nodes, "
      "components, closed, manifold, orientation, Euler characteristic, genus, loops "
      "(count, longest, self-intersecting ones with the quads where they cross themselves), "
      "handles (per handle a cycle that bounds inside the solid, with its length), "
      "open and non-manifold edges, coincident nodes, and whether the surface can be woven. "
      "Exit code 0 whatever the diagnosis (2 when the file cannot be read).");
  cmd->add_option("FILE", options->file, "Mesh file (obj, off, vtk, vtu, msh, mesh, mfem, inp)")
      ->required();
  cmd->add_flag("--json", options->json,
                "Print one JSON object (keys as in shared/data/expected.json, plus details)");
  cmd->add_option("--format", options->format,
                  "Read FILE as this format instead of guessing from its extension (auto, the "
                  "default): obj, off, "
                  "vtk, vtu, msh, msh2, medit, mfem, inp");
  return [options] {
    const primal::Format format = input_format(options->format);
    const primal::MeshFile file = primal::read_mesh(options->file, format);
    const primal::SurfaceDiagnosis diagnosis = primal::diagnose(file);
    if (options->json)
      std::cout << primal::to_json(diagnosis).dump(1) << "\n";
    else
      print_report(diagnosis, std::cout);
    return kSuccess;
  };
}

}  // namespace stcweave::cli
