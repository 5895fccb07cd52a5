/// `stcweave view HEX -o VIEW.html [--trace T.jsonl]`: the browser page of a hex mesh (one
/// self-contained HTML file, three.js inlined): the mesh drawn with WebGL, the replay of its
/// weave when the file carries the cell data `mesh` writes (creation_step, shrink, rule,
/// depth), colourings, sheet / chord picking, a clipping plane, the quality histogram.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/primal/mesh_data.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/hex_stc.hpp"
#include "stcweave/viewer/page.hpp"

namespace stcweave::cli {
namespace {

struct ViewArgs {
  std::string input;
  std::string output;
  std::string format = "auto";
  std::string trace;
  std::string title;
  bool quiet = false;
};

/// What a trace written by `mesh --trace` says of each shrink and hex: the selections, the
/// failed shrinks and the rule that made each hex (the last one for a hex id, as undone
/// shrinks make their ids again).
struct TraceFile {
  std::vector<primal::ShrinkRecord> shrinks;
  std::vector<NodeId> hex_nodes;
  std::vector<std::int32_t> hex_shrink;
  std::vector<std::string> hex_rule;
};

/// The integer of an id string such as "h12" or "n5" (-1 when it is not one).
std::int32_t id_value(const nlohmann::json& j) {
  if (!j.is_string()) return -1;
  const std::string s = j.get<std::string>();
  if (s.size() < 2) return -1;
  try {
    return static_cast<std::int32_t>(std::stol(s.substr(1)));
  } catch (const std::exception&) {
    return -1;
  }
}

TraceFile read_trace(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError("cannot open the trace " + path + "; check the path");
  TraceFile t;
  primal::TraceDigest digest;
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("event")) {
      throw InvalidInput(path + ":" + std::to_string(number) +
                         ": not a trace line of `stcweave mesh --trace` (JSON object with "
                         "\"event\"); give the trace of the weave that made the mesh");
    }
    weave::TraceEvent e;
    e.shrink = j.value("shrink", -1);
    const std::string event = j.value("event", "");
    if (event == "selection") {
      e.kind = weave::TraceEvent::Kind::Selection;
      e.decided_by = j.value("decided_by", "");
      if (j.contains("chosen") && j["chosen"].is_object()) {
        const auto& c = j["chosen"];
        weave::TraceCandidate cand;
        cand.loop = c.value("loop", -1);
        cand.side = c.value("side", "A") == "B" ? 1 : 0;
        cand.length = c.value("length", std::size_t{0});
        cand.depth = c.value("depth", 0);
        e.candidates.push_back(cand);
        e.chosen = 0;
      }
    } else if (event == "shrink_failed") {
      e.kind = weave::TraceEvent::Kind::ShrinkFailed;
    } else if (event == "rule") {
      e.kind = weave::TraceEvent::Kind::Rule;
      const std::int32_t hex = j.contains("hex") ? id_value(j["hex"]) : -1;
      const std::int32_t node = j.contains("node") ? id_value(j["node"]) : -1;
      e.hex = hex >= 0 ? HexId(hex) : HexId::invalid();
      e.node = node >= 0 ? NodeId(node) : NodeId::invalid();
      if (hex >= 0) {
        const auto h = static_cast<std::size_t>(hex);
        if (t.hex_shrink.size() <= h) {
          t.hex_shrink.resize(h + 1, -1);
          t.hex_rule.resize(h + 1);
        }
        t.hex_shrink[h] = e.shrink;
        t.hex_rule[h] = j.value("rule", "");
      }
    } else {
      continue;
    }
    digest.add(e);
  }
  t.shrinks = digest.shrinks();
  t.hex_nodes = digest.hex_nodes();
  return t;
}

int run_view(const ViewArgs& a) {
  if (!viewer::has_three_js()) {
    throw Unsupported(
        "view: this stcweave was built without three.js, so it cannot make the page; install "
        "Debian's libjs-three (./dev.sh installs it) and rebuild");
  }
  const primal::Format format = input_format(a.format);
  const primal::MeshFile file = primal::read_mesh(a.input, format);
  if (file.hexes.empty()) {
    throw InvalidInput("view: " + a.input + " has no hexahedra (" +
                       std::to_string(file.quads.size()) +
                       " quads); give a hex mesh, e.g. the output of `stcweave mesh`");
  }
  primal::HexMesh mesh;
  mesh.points = file.points;
  mesh.complex.num_nodes = static_cast<std::size_t>(file.points.rows());
  mesh.complex.hexes = file.hexes;
  const std::size_t m = mesh.complex.hexes.size();
  const stc::HexStc stc = stc::build_hex_stc(mesh.complex);
  primal::MeshData data = primal::hex_mesh_data(mesh, stc);
  // The weave's arrays, as `mesh` wrote them.
  const primal::MeshData stored = primal::read_mesh_data(a.input, format);
  for (const char* name : {"creation_step", "shrink", "rule", "depth"}) {
    const primal::DataArray* s = stored.cell(name);
    if (s == nullptr) continue;
    if (s->values.size() != m) {
      std::cerr << "stcweave: view: ignoring cell array '" << name << "' of " << a.input << " ("
                << s->values.size() << " values for " << m << " hexes)\n";
      continue;
    }
    data.cells.push_back(*s);
  }
  viewer::PageOptions options;
  options.title = a.title.empty() ? std::filesystem::path(a.input).filename().string() : a.title;
  if (!a.trace.empty()) {
    TraceFile t = read_trace(a.trace);
    options.shrinks = std::move(t.shrinks);
    options.hex_nodes = std::move(t.hex_nodes);
    options.hex_nodes.resize(m, NodeId::invalid());
    // A file without the weave's arrays (written with --no-cell-data) gets them from the
    // trace when it covers every hex.
    const bool covers =
        t.hex_shrink.size() == m && std::none_of(t.hex_shrink.begin(), t.hex_shrink.end(),
                                                 [](std::int32_t s) { return s < 0; });
    if (data.cell("creation_step") == nullptr && covers) {
      primal::WeaveHistory history;
      history.hex_shrink = t.hex_shrink;
      history.hex_rule = t.hex_rule;
      history.shrinks = options.shrinks;
      data = primal::hex_mesh_data(mesh, stc, &history);
    }
  }
  viewer::write_page(a.output, mesh, stc, data, options);
  if (!a.quiet) {
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(a.output, ec);
    std::cout << "page       " << a.output << ": " << m << " hexes, " << stc.sheets.size()
              << " sheets, " << stc.chords.size() << " chords, "
              << (data.cell("creation_step") != nullptr ? "weave replay" : "no weave data") << ", "
              << (ec ? 0 : bytes) << " bytes\n";
  }
  return kSuccess;
}

}  // namespace

Action add_view_command(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  CLI::App* sub = app.add_subcommand(
      "view",
      "Write the browser page of a hex mesh: one self-contained HTML file (three.js inlined, "
      "no network) that draws the mesh with WebGL and replays its weave (from the cell data "
      "`stcweave mesh` writes); open it in any browser.");
  sub->add_option("input", args->input, "hex mesh (VTK, VTU, MSH, MEDIT, INP, MFEM)")->required();
  sub->add_option("-o,--output", args->output, "the HTML page to write")->required();
  sub->add_option("--format", args->format, "input format name (default: auto)");
  sub->add_option("--trace", args->trace,
                  "the JSON-lines trace of the weave (`mesh --trace`): the replay then names the "
                  "loop each shrink chose");
  sub->add_option("--title", args->title, "the page's title (default: the input's file name)");
  sub->add_flag("-q,--quiet", args->quiet, "print nothing on success");
  return [args] { return run_view(*args); };
}

}  // namespace stcweave::cli
