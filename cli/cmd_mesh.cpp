/// `stcweave mesh IN -o OUT`: the main job. Reads a quad surface (or a hex mesh, whose
/// boundary is taken), weaves it, validates the complex (an invalid one is never written
/// unless --keep-invalid), places the interior nodes and writes the hex mesh.

#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cad_input.hpp"
#include "commands.hpp"
#include "stcweave/primal/beside.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/primal/mesh_data.hpp"
#include "stcweave/primal/pipeline.hpp"
#include "stcweave/primal/valence_stats.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/hex_stc.hpp"
#include "stcweave/stc/loop_moves.hpp"
#include "stcweave/viewer/page.hpp"
#include "weave_options.hpp"

namespace stcweave::cli {
namespace {

struct MeshArgs {
  std::string input;
  std::string output;
  std::string input_format = "auto";
  std::string output_format = "auto";
  WeaveArgs weave;
  std::string report;
  std::string trace;
  bool check = false;
  bool keep_invalid = false;
  bool fail_on_inverted = false;
  bool quiet = false;
  bool progress = false;
  // Positioning (untangling) of the interior nodes.
  bool no_untangle = false;
  std::string start = "harmonic";
  std::string pillow = "auto";
  std::string interior = "auto";
  double tet_growth = primal::TetInteriorOptions{}.growth;
  std::string tet_flips = "1";
  int position_rounds = 100;
  int position_iterations = 3000;
  int position_total_iterations = 30000;
  int position_newton_after = primal::PositionOptions{}.newton_after;
  bool position_precondition = primal::PositionOptions{}.precondition;
  int position_newton_steps = primal::PositionOptions{}.max_newton_steps;
  double position_theta = 0.5;
  int shape_sweeps = primal::PositionOptions{}.max_shape_sweeps;
  int cluster_passes = primal::PositionOptions{}.cluster_passes;
  bool no_cluster_hinge = false;
  int threads = primal::PositionOptions{}.threads;
  double shape_target = primal::PositionOptions{}.shape_target;
  double shape_hinges_below = primal::PositionOptions{}.hinge_shape_below;
  double good_start = primal::PositionOptions{}.good_start;
  int certify_depth = 4;
  CadArgs cad;  // CAD input: --size, --cad-recipe, --surface-out
  // Cell data and the browser page (issue 16).
  bool no_cell_data = false;
  std::string html;
  // Surfaces whose loops cross themselves (docs/self-intersecting-loops.md).
  bool no_loop_moves = false;
  std::string front_on_failure;  ///< default: OUT.front.obj
  std::size_t loop_moves_max = primal::SelfCrossingOptions{}.search.max_moves;
  std::size_t loop_moves_beam_depth = primal::SelfCrossingOptions{}.search.beam_depth;
  std::size_t loop_moves_beam_width = primal::SelfCrossingOptions{}.search.beam_width;
  std::size_t loop_moves_evaluations = primal::SelfCrossingOptions{}.search.max_evaluations;
  std::size_t loop_moves_work = primal::SelfCrossingOptions{}.search.max_work;
  std::size_t loop_moves_tiny_depth = primal::SelfCrossingOptions{}.search.tiny_depth;
  bool depth_filter_always = false;
};

nlohmann::json self_crossing_json(const primal::SelfCrossingReport& s) {
  nlohmann::json moves = nlohmann::json::object();
  for (const auto& m : s.moves.moves)
    moves[stc::to_string(m.move)] = moves.value(stc::to_string(m.move), 0) + 1;
  return {{"self_crossing_quads_before", s.moves.self_crossing_quads_before},
          {"self_crossing_quads_after", s.moves.self_crossing_quads_after},
          {"attached_hexes", s.attached_hexes},
          {"moves", moves},
          {"evaluations", s.moves.evaluations},
          {"beam_searches", s.moves.beam_searches},
          {"tunnels", s.moves.tunnels},
          {"front_quads", s.moves.front.quads.size()},
          {"pillowed", s.pillowed},
          {"pillow_hexes", s.pillow_hexes},
          {"woven_hexes", s.woven_hexes},
          {"direct_join_violation", s.direct_join_violation},
          {"free_nodes", s.free_nodes},
          {"front_pillows", s.front_pillows},
          {"filled", s.filled},
          {"fill_residual", s.fill_residual},
          {"reliable_fallback", s.reliable_fallback},
          {"after_block", s.after_block},
          {"seconds",
           {{"search", s.search_seconds}, {"weave", s.weave_seconds}, {"join", s.join_seconds}}}};
}

/// A repair report as JSON (the `repair` and `other_repair` objects of the position report).
nlohmann::json repair_json(const primal::RepairReport& r) {
  return {{"ran", r.ran},
          {"sweeps", r.sweeps},
          {"moves", r.moves},
          {"inverted_before", r.inverted_before},
          {"inverted_after", r.inverted_after},
          {"min_scaled_jacobian_before", r.min_scaled_jacobian_before},
          {"min_scaled_jacobian_after", r.min_scaled_jacobian_after},
          {"stop", r.stop}};
}

/// The position report as JSON (hex ids as "h12").
nlohmann::json position_json(const primal::PositionReport& p) {
  nlohmann::json impossible = nlohmann::json::array();
  for (const auto& c : p.impossible)
    impossible.push_back({{"hex", c.hex.str()}, {"corner", c.corner}, {"reason", c.reason}});
  nlohmann::json inverted = nlohmann::json::array();
  for (const HexId h : p.inverted) inverted.push_back(h.str());
  nlohmann::json uncertified = nlohmann::json::array();
  for (std::size_t h = 0; h < p.validity.size(); ++h) {
    if (p.validity[h] != primal::Validity::Valid) {
      uncertified.push_back(
          {{"hex", HexId(h).str()},
           {"bezier", p.validity[h] == primal::Validity::Invalid ? "invalid" : "undecided"}});
    }
  }
  return {{"free_nodes", p.free_nodes},
          {"rounds", p.outer_iterations},
          {"iterations", p.iterations},
          {"newton_steps", p.newton_steps},
          {"energy_before", p.energy_before},
          {"energy_after", p.energy_after},
          {"epsilon", p.epsilon},
          {"inverted_before", p.inverted_before},
          {"inverted_after", p.inverted_after},
          {"corners_inverted_before", p.corners_inverted_before},
          {"corners_inverted_after", p.corners_inverted_after},
          {"min_scaled_jacobian_before", p.min_scaled_jacobian_before},
          {"min_scaled_jacobian_after", p.min_scaled_jacobian_after},
          {"mean_scaled_jacobian_before", p.mean_scaled_jacobian_before},
          {"mean_scaled_jacobian_after", p.mean_scaled_jacobian_after},
          {"certified_valid", p.certified.valid},
          {"certified_invalid", p.certified.invalid},
          {"certified_uncertain", p.certified.uncertain},
          {"not_certified_hexes", uncertified},
          {"converged", p.converged},
          {"stop", p.stop},
          {"impossible_corners", impossible},
          {"inverted_hexes", inverted},
          {"good_start", p.good_start},
          {"min_scaled_jacobian_untangled", p.min_scaled_jacobian_untangled},
          {"mean_scaled_jacobian_untangled", p.mean_scaled_jacobian_untangled},
          {"repair", repair_json(p.repair)},
          {"repaired_from", p.repaired_from},
          {"other_repair", repair_json(p.other_repair)},
          {"clusters",
           {{"ran", p.clusters.ran},
            {"passes", p.clusters.passes},
            {"clusters", p.clusters.clusters},
            {"sub_meshes", p.clusters.sub_problems},
            {"accepted", p.clusters.accepted},
            {"work", p.clusters.work},
            {"inverted_before", p.clusters.inverted_before},
            {"inverted_after", p.clusters.inverted_after},
            {"hinge_clusters", p.clusters.hinge_clusters},
            {"hinge_tries", p.clusters.hinge_tries},
            {"hinge_accepted", p.clusters.hinge_accepted},
            {"stop", p.clusters.stop}}},
          {"shape",
           {{"ran", p.shape.ran},
            {"sweeps", p.shape.sweeps},
            {"moves", p.shape.moves},
            {"min_scaled_jacobian_before", p.shape.min_scaled_jacobian_before},
            {"min_scaled_jacobian_after", p.shape.min_scaled_jacobian_after},
            {"mean_scaled_jacobian_before", p.shape.mean_scaled_jacobian_before},
            {"mean_scaled_jacobian_after", p.shape.mean_scaled_jacobian_after},
            {"stop", p.shape.stop},
            {"order", p.shape.order},
            {"barrier",
             {{"ran", p.shape.barrier.ran},
              {"rounds", p.shape.barrier.rounds},
              {"iterations", p.shape.barrier.iterations},
              {"min_corner_before", p.shape.barrier.min_corner_before},
              {"min_corner_after", p.shape.barrier.min_corner_after},
              {"min_scaled_jacobian_before", p.shape.barrier.min_scaled_jacobian_before},
              {"min_scaled_jacobian_after", p.shape.barrier.min_scaled_jacobian_after},
              {"stop", p.shape.barrier.stop}}},
            {"hinge",
             {{"ran", p.shape.hinge.ran},
              {"seeds", p.shape.hinge.seeds},
              {"tries", p.shape.hinge.tries},
              {"accepted", p.shape.hinge.accepted},
              {"work", p.shape.hinge.work},
              {"min_scaled_jacobian_before", p.shape.hinge.min_scaled_jacobian_before},
              {"min_scaled_jacobian_after", p.shape.hinge.min_scaled_jacobian_after},
              {"stop", p.shape.hinge.stop}}}}},
          {"seconds", p.seconds}};
}

nlohmann::json trace_json(const weave::TraceEvent& e) {
  nlohmann::json j;
  j["step"] = e.step;
  j["shrink"] = e.shrink;
  switch (e.kind) {
    case weave::TraceEvent::Kind::Selection: {
      j["event"] = "selection";
      j["reason"] = e.reason;
      nlohmann::json cands = nlohmann::json::array();
      for (const auto& c : e.candidates) {
        cands.push_back({{"loop", c.loop},
                         {"side", c.side == 0 ? "A" : "B"},
                         {"length", c.length},
                         {"strictly_on_side", c.strictly_on_side},
                         {"on_strip", c.on_strip},
                         {"weight", c.weight},
                         {"self_intersecting", c.self_intersecting},
                         {"faces_collapsed", c.faces_collapsed},
                         {"depth", c.depth},
                         {"crossed_sharp", c.crossed_sharp},
                         {"side_sharp", c.side_sharp},
                         {"nonconvex_on_side", c.nonconvex_on_side},
                         {"parallel_to", c.parallel_to}});
      }
      j["decided_by"] = e.decided_by;
      j["filters"] = e.filters;
      j["chosen"] = cands.at(static_cast<std::size_t>(e.chosen));
      j["candidates"] = cands;
      break;
    }
    case weave::TraceEvent::Kind::Rule:
      j["event"] = "rule";
      j["rule"] = e.rule;
      j["node"] = e.node.str();
      j["faces"] = e.faces;
      j["hex"] = e.hex.is_valid() ? nlohmann::json(e.hex.str()) : nlohmann::json(nullptr);
      break;
    case weave::TraceEvent::Kind::ShrinkFailed:
      j["event"] = "shrink_failed";
      j["reason"] = e.reason;
      break;
  }
  return j;
}

int run_mesh(const MeshArgs& a) {
  primal::MeshOptions options;
  apply_weave_options(a.weave, options.weave);
  options.depth_filter_after_block = !a.depth_filter_always;
  options.weave.check = a.check;
  // The trace is streamed, so that a failed weave still leaves its trace behind.
  auto trace_text = std::make_shared<std::string>();
  if (!a.trace.empty()) {
    options.weave.on_trace = [trace_text](const weave::TraceEvent& e) {
      *trace_text += trace_json(e).dump() + "\n";
    };
  }
  options.keep_invalid = a.keep_invalid;
  options.untangle = !a.no_untangle;
  if (a.start != "layers" && a.start != "harmonic")
    throw InvalidInput("--start must be layers or harmonic, not '" + a.start + "'");
  options.layer_start = a.start == "layers";
  options.pillow.mode = primal::pillow_mode_from_name(a.pillow);
  options.interior.mode = primal::interior_mode_from_name(a.interior);
  options.interior.growth = a.tet_growth;
  options.interior.flips = a.tet_flips != "off";
  if (options.interior.flips) options.interior.flip_floor = std::stod(a.tet_flips);

  options.position.max_outer_iterations = a.position_rounds;
  options.position.max_inner_iterations = a.position_iterations;
  options.position.max_total_iterations = a.position_total_iterations;
  options.position.theta = a.position_theta;
  options.position.max_shape_sweeps = a.shape_sweeps;
  options.position.cluster_passes = a.cluster_passes;
  options.position.cluster_hinge = !a.no_cluster_hinge;
  options.position.threads = a.threads;
  options.build_stc = true;  // the report's sheets and chords, the cell data
  options.position.shape_target = a.shape_target;
  options.position.hinge_shape_below = a.shape_hinges_below;
  options.position.good_start = a.good_start;
  options.position.newton_after = a.position_newton_after;
  options.position.precondition = a.position_precondition;
  options.position.max_newton_steps = a.position_newton_steps;
  options.position.certify_depth = a.certify_depth;
  options.self_crossing_moves = !a.no_loop_moves;
  options.self_crossing.front_on_failure =
      a.front_on_failure.empty() ? a.output + ".front.obj" : a.front_on_failure;
  options.self_crossing.search.max_moves = a.loop_moves_max;
  options.self_crossing.search.beam_depth = a.loop_moves_beam_depth;
  options.self_crossing.search.beam_width = a.loop_moves_beam_width;
  options.self_crossing.search.max_evaluations = a.loop_moves_evaluations;
  options.self_crossing.search.max_work = a.loop_moves_work;
  options.self_crossing.search.tiny_depth = a.loop_moves_tiny_depth;
  options.self_crossing.undo_seam_blocking_shrinks = a.weave.undo_seam_blocking_shrinks;
  const bool show_progress = a.progress || (!a.quiet && isatty(STDERR_FILENO) != 0);
  if (show_progress) {
    options.on_stage = [](const std::string& s) { std::cerr << "stcweave: " << s << "...\n"; };
    options.weave.progress = [](const weave::WeaveProgress& p) {
      std::cerr << "stcweave: weaving: " << p.hexes << " hexes, " << p.front_faces
                << " front faces left, " << p.loops_shrunk << " loops shrunk\n";
    };
    // The search for front moves (surfaces whose loops cross themselves): every 10th hex it
    // attaches and every 50,000 moves it evaluates.
    options.self_crossing.search.progress = [](const stc::LoopMoveProgress& p) {
      std::cerr << "stcweave: front moves (" << (p.filling ? "filling" : "untangling")
                << "): " << p.hexes << " hexes attached, " << p.self_crossing_quads
                << " self-crossing quads left, " << p.front_faces << " front faces, "
                << p.evaluations << " moves evaluated\n";
    };
    // Every untangling round (each can take seconds); the first sweep of the local phases
    // and every tenth (a sweep is short, and there are up to a hundred).
    options.position.progress = [](const primal::PositionProgress& p) {
      using Phase = primal::PositionProgress::Phase;
      if (p.phase == Phase::Clusters) {
        std::cerr << "stcweave: positioning: local untangling, pass " << p.pass << ", cluster "
                  << p.step << " of " << p.limit << ": " << p.inverted << " hexes inverted\n";
        return;
      }
      if (p.phase != Phase::Untangle && p.step != 1 && p.step % 10 != 0) return;
      std::cerr << "stcweave: positioning: " << primal::phase_name(p.phase)
                << (p.phase == Phase::Untangle ? " round " : " sweep ") << p.step << " of at most "
                << p.limit << ": " << p.inverted
                << (p.phase == Phase::Untangle ? " corners" : " hexes") << " inverted";
      if (p.phase == Phase::Untangle) {
        std::cerr << ", " << p.iterations << " L-BFGS iterations, eps " << p.epsilon << "\n";
      } else {
        std::cerr << ", min scaled Jacobian " << p.min_scaled_jacobian << "\n";
      }
    };
  }
  const primal::Format out_format = a.output_format == "auto"
                                        ? primal::format_from_path(a.output)
                                        : primal::format_from_name(a.output_format);
  // Cell data and the browser page show the weave's history (`WeaveResult::shrinks`,
  // `hex_node`), which the weave records without a trace.
  if (!a.html.empty() && !viewer::has_three_js()) {
    throw Unsupported(
        "--html: this stcweave was built without three.js, so it cannot make the "
        "page; install Debian's libjs-three (./dev.sh installs it) and rebuild");
  }
  const bool format_has_data =
      out_format == primal::Format::Vtk || out_format == primal::Format::Vtu ||
      out_format == primal::Format::Msh || out_format == primal::Format::Msh2;
  const bool want_cell_data = (!a.no_cell_data && format_has_data) || !a.html.empty();
  // A CAD input is meshed into a quad surface first (cad_input.hpp); any other is read.
  const InputSurface input =
      read_input(a.input, input_format(a.input_format), a.cad, a.progress, a.quiet);
  const primal::MeshFile& file = input.file;
  const primal::MeshResult r = [&] {
    try {
      return primal::mesh_file(file, options);
    } catch (const Error&) {
      if (!a.trace.empty()) primal::write_text_file(a.trace, *trace_text);
      throw;
    }
  }();
  // The pipeline built the mesh's STC (sheet and chord counts, the cell data), beside the
  // positioning when a second thread may be used.
  const stc::HexStc& stc = *r.stc;
  std::size_t blind_chords = 0;
  for (const auto& c : stc.chords) blind_chords += stc::is_blind(c) ? 1 : 0;

  // With --fail-on-inverted a mesh that still has inverted hexes is unusable for the caller:
  // like an invalid complex, it is written only with --keep-invalid.
  const bool inverted_left = a.fail_on_inverted && r.quality.inverted > 0;
  const bool write_mesh = !inverted_left || a.keep_invalid;
  const auto t1 = std::chrono::steady_clock::now();
  // The valence statistics (for the report) beside the weave history, cell data and writing.
  primal::Beside<primal::ValenceStats> counting(
      primal::second_thread(a.threads), [&] { return primal::valence_stats(r.mesh.complex); });
  primal::WeaveHistory history = primal::weave_history(r.woven);
  // The pillow stage appends its hexes after the woven ones.
  if (r.pillow.applied || r.pillow.unpinch_blocks > 0)
    primal::append_hexes(history, r.mesh.complex.hexes.size(), "pillow");
  const primal::MeshData cell_data =
      want_cell_data ? primal::hex_mesh_data(r.mesh, stc, &history) : primal::MeshData{};
  if (write_mesh)
    primal::write_hex_mesh(r.mesh, a.no_cell_data ? primal::MeshData{} : cell_data, a.output,
                           out_format);
  if (!a.html.empty()) {
    viewer::PageOptions page;
    page.title = std::filesystem::path(a.input).filename().string();
    page.shrinks = history.shrinks;
    page.hex_nodes = history.hex_node;
    viewer::write_page(a.html, r.mesh, stc, cell_data, page);
  }
  const primal::ValenceStats valence = counting.get();
  const double write_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();

  nlohmann::json report;
  report["input"] = a.input;
  report["output"] = write_mesh ? nlohmann::json(a.output) : nlohmann::json(nullptr);
  report["cad"] = input.cad ? cad_json(*input.cad) : nlohmann::json(nullptr);
  report["rules"] = a.weave.rules;
  report["weave_options"] = weave_options_json(options.weave);
  report["weave_options"]["depth_filter_after_block"] = options.depth_filter_after_block;
  report["depth_filter_retry"] =
      r.depth_filter_retry.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.depth_filter_retry);
  report["quads"] = r.surface.surface.quads.size();
  report["hexes"] = r.mesh.complex.hexes.size();
  report["nodes"] = r.mesh.complex.num_nodes;
  report["interior_nodes"] = r.mesh.complex.num_nodes - r.woven.num_input_nodes;
  report["valid"] = r.validation.valid;
  report["validation"] = r.validation.summary();
  report["shared_nodes_not_a_face"] = {{"count", r.shared_nodes.count},
                                       {"examples", r.shared_nodes.examples}};
  report["sheets"] = stc.sheets.size();
  report["chords"] = stc.chords.size();
  report["blind_chords"] = blind_chords;
  report["flipped_quads"] = r.orientation.flipped_quads;
  report["valence"] = primal::valence_json(valence);
  report["quality"] = {{"min_scaled_jacobian", r.quality.min_scaled_jacobian},
                       {"mean_scaled_jacobian", r.quality.mean_scaled_jacobian},
                       {"inverted", r.quality.inverted},
                       {"below_0_2", r.quality.below_0_2}};
  report["interior"] = {{"mode", a.interior},
                        {"triangle_split", r.interior.triangle_split},
                        {"used", r.interior.used ? "tets" : "woven"},
                        {"compared", r.interior.compared},
                        {"reason", r.interior.reason}};
  if (r.interior.tets > 0) {
    report["interior"]["triangles"] = r.interior.triangles;
    report["interior"]["tets"] = r.interior.tets;
    report["interior"]["flips"] = r.interior.flips;
    report["interior"]["interior_vertices"] = r.interior.interior_vertices;
    report["interior"]["seconds"] = r.interior.seconds;
  }
  report["pillow"] = {{"mode", primal::to_string(r.pillow.mode)},
                      {"applied", r.pillow.applied},
                      {"reason", r.pillow.reason},
                      {"shells", r.pillow.shells},
                      {"shells_pillowed", r.pillow.shells_pillowed},
                      {"fixed_corners", r.pillow.fixed_corners},
                      {"bad_fixed_corners", r.pillow.bad_fixed_corners},
                      {"worst_fixed_corner", r.pillow.worst_fixed_corner},
                      {"nodes_added", r.pillow.nodes_added},
                      {"hexes_added", r.pillow.hexes_added},
                      {"compared", r.pillow.compared}};
  if (r.pillow.pinched_pairs > 0) {
    report["pillow"]["pinched_pairs"] = r.pillow.pinched_pairs;
    report["pillow"]["unpinch_blocks"] = r.pillow.unpinch_blocks;
    report["pillow"]["unpinch_hexes"] = r.pillow.unpinch_hexes;
    report["pillow"]["pinched_left"] = r.pillow.pinched_left;
  }
  // The harmonic placement of the interior nodes (recovery): the start of the positioning.
  report["harmonic"] = {{"free_nodes", r.harmonic.free_nodes},
                        {"iterations", r.harmonic.iterations},
                        {"residual", r.harmonic.residual},
                        {"levels", r.harmonic.levels}};
  report["untangled"] = options.untangle;
  if (options.untangle) report["position"] = position_json(r.position);
  const auto& s = r.woven.stats;
  report["weave"] = {{"selections", s.selections},
                     {"shrinks", s.shrinks},
                     {"failed_shrinks", s.failed_shrinks},
                     {"seams", s.seams},
                     {"coincident_glues", s.coincident_glues},
                     {"crosses", s.crosses},
                     {"blind_chords", s.blind_chords},
                     {"blocked_seams", s.blocked_seams},
                     {"relaxed_preconditions", s.relaxed_preconditions},
                     {"rolled_back_shrinks", s.rolled_back_shrinks},
                     {"parallel_merges", s.parallel_merges},
                     {"nonconvexity_seams", s.nonconvexity_seams},
                     {"recoveries", s.recoveries},
                     {"recovery_trials", s.recovery_trials},
                     {"seam_undo_retries", s.seam_undo_retries},
                     {"fill_hexes", s.fill_hexes},
                     {"reliable_from_start", s.reliable_from_start}};
  {
    // The block recovery (docs/weave-recovery.md): where each kept pillow went.
    nlohmann::json recoveries = nlohmann::json::array();
    for (const weave::Recovery& rec : r.woven.recoveries) {
      recoveries.push_back(
          {{"hexes_before", rec.hexes_before},
           {"front_faces", rec.front_faces},
           {"pillowed", rec.pillowed},
           {"node", rec.node.is_valid() ? nlohmann::json(rec.node.str()) : nlohmann::json(nullptr)},
           {"why", rec.why}});
    }
    report["weave"]["recovered"] = recoveries;
  }
  if (r.self_crossing.used) report["self_crossing"] = self_crossing_json(r.self_crossing);
  report["seconds"] = {{"diagnose", r.seconds.diagnose},
                       {"orient", r.seconds.orient},
                       {"weave", r.seconds.weave},
                       {"validate", r.seconds.validate},
                       {"recover", r.seconds.recover},
                       {"pillow", r.seconds.pillow},
                       {"position", r.seconds.position},
                       {"quality", r.seconds.quality},
                       {"other_interior", r.seconds.other_interior},
                       {"overlap", r.seconds.overlap},
                       {"stc", r.seconds.stc},
                       {"write", write_seconds},
                       {"total", r.seconds.total() + write_seconds}};

  {
    // Shells woven separately and handle cuts (issue 12); `weave` seconds above include them.
    nlohmann::json cuts = nlohmann::json::array();
    for (const primal::HandleCut& c : r.solids.cuts) {
      cuts.push_back({{"cycle_edges", c.cycle.size()}, {"disc", c.disc}, {"attempts", c.attempts}});
    }
    report["solids"] = {{"solids", r.solids.solids},
                        {"cuts", cuts},
                        {"cut_seconds", r.solids.cut_seconds},
                        {"ball_weave_seconds", r.solids.weave_seconds},
                        {"glue_seconds", r.solids.glue_seconds}};
  }
  if (!a.report.empty()) primal::write_text_file(a.report, report.dump(1) + "\n");
  if (!a.trace.empty()) primal::write_text_file(a.trace, *trace_text);
  if (!a.quiet) {
    std::cout << "input      " << a.input << ": " << r.surface.surface.quads.size() << " quads";
    if (r.orientation.flipped_quads > 0)
      std::cout << " (" << r.orientation.flipped_quads << " quads re-oriented outward)";
    std::cout << "\nhexes      " << r.mesh.complex.hexes.size() << " (" << report["interior_nodes"]
              << " interior nodes, " << stc.sheets.size() << " sheets, " << stc.chords.size()
              << " chords, " << blind_chords << " blind)\n";
    if (s.seam_undo_retries > 0) {
      std::cout << "retry      " << s.seam_undo_retries << " weave"
                << (s.seam_undo_retries == 1 ? "" : "s")
                << " blocked keeping the shrinks that leave a seam blocked; woven again undoing "
                   "them\n";
    }
    if (s.fill_hexes > 0) {
      std::cout << "fill       the weave blocked; " << s.fill_hexes << " hex"
                << (s.fill_hexes == 1 ? "" : "es")
                << " attached by front moves filled its first blocked front\n";
    }
    if (s.reliable_from_start > 0) {
      std::cout << "fallback   the extended weave blocked in every way; woven with the reliable "
                   "rules from the start\n";
    }
    if (s.recoveries > 0) {
      std::cout << "recovery   the weave blocked; " << s.recoveries << " pillow"
                << (s.recoveries == 1 ? "" : "s") << " of blocked front faces let it complete ("
                << s.recovery_trials << " trials";
      // The self-crossing and solid stages sum the counts but may not carry the records.
      if (!r.woven.recoveries.empty())
        std::cout << "; first after " << r.woven.recoveries.front().hexes_before << " hexes";
      std::cout << ")\n";
    }
    if (!r.depth_filter_retry.empty()) {
      std::cout << "depth      the weave without the depth filter blocked; woven again with it ("
                << r.depth_filter_retry.substr(0, 160)
                << (r.depth_filter_retry.size() > 160 ? "..." : "") << ")\n";
    }
    if (!r.self_crossing.after_block.empty()) {
      const primal::SelfCrossingReport& x = r.self_crossing;
      std::string way = "the weave of the front with its nodes fixed";
      if (x.filled) {
        way = "the fill by front moves alone";
      } else if (x.fill_residual > 0) {
        way = "the fill by front moves, the " + std::to_string(x.fill_residual) +
              "-face front it left meshed apart";
      } else if (x.free_nodes) {
        way = "the weave with recovery pillows of blocked nodes (" +
              std::to_string(x.front_pillows) + " used)";
      }
      std::cout << "rescue     the weave blocked even with the block recovery; woven instead by "
                << way << (x.reliable_fallback ? " with the reliable rules" : "") << "\n";
    }
    std::cout << "valence    at most " << valence.max_hexes_at_interior_edge
              << " hexes around an interior edge (" << valence.interior_edges_over_4
              << " edges over 4), at most " << valence.max_hexes_at_interior_node
              << " at an interior node (" << valence.interior_nodes_over_8 << " nodes over 8)\n";
    if (r.interior.triangle_split) {
      std::cout << "interior   " << r.interior.reason;
      if (r.interior.tets > 0) {
        std::cout << "; " << r.interior.tets << " tets, " << r.interior.flips
                  << " removed by 3-2 flips";
      }
      std::cout << "\n";
    }
    std::cout << "pillow     " << r.pillow.reason << "\n";
    std::cout << "valid      " << (r.validation.valid ? "yes" : "NO: " + r.validation.summary());
    std::cout << "\n";
    std::cout << "quality    min scaled Jacobian " << r.quality.min_scaled_jacobian << ", mean "
              << r.quality.mean_scaled_jacobian << ", inverted " << r.quality.inverted;
    if (options.untangle) {
      std::cout << " (after untangling; " << r.position.inverted_before << " before; "
                << r.position.stop << ")\n";
    } else {
      std::cout << (r.interior.used ? " (the tet split's placement, not untangled)\n"
                                    : " (harmonic placement, not untangled)\n");
    }
    if (options.untangle) {
      std::cout << "shape      min scaled Jacobian " << r.position.min_scaled_jacobian_before
                << " at the start, " << r.position.min_scaled_jacobian_untangled << " untangled, "
                << r.position.min_scaled_jacobian_after << " after the shape phase (mean "
                << r.position.mean_scaled_jacobian_before << ", "
                << r.position.mean_scaled_jacobian_untangled << ", "
                << r.position.mean_scaled_jacobian_after << "; " << r.position.shape.stop;
      const primal::HingeShapeReport& hinge = r.position.shape.hinge;
      if (hinge.ran) {
        std::cout << "; hinges: " << hinge.accepted << " of " << hinge.seeds
                  << " worst hexes raised, " << hinge.min_scaled_jacobian_before << " -> "
                  << hinge.min_scaled_jacobian_after << ", " << hinge.stop;
      }
      std::cout << ")\n";
    }
    std::cout << "time       " << r.seconds.total() + write_seconds << " s (weave "
              << r.seconds.weave << " s)\n";
    std::cout << "output     " << (write_mesh ? a.output : "not written (--fail-on-inverted)")
              << "\n";
  }
  if (!r.validation.valid) return kInternal;
  if (const std::string crossing = primal::crossing_warning(r.diagnosis); !crossing.empty()) {
    std::cerr << "stcweave: warning: " << crossing
              << (input.cad ? " (here the quad surface stcweave made from the CAD solid: another "
                              "--size may avoid the fold)"
                            : "")
              << "\n";
  }
  if (!a.fail_on_inverted && r.quality.inverted > 0) {
    // Not an error without --fail-on-inverted, but never silent: a solver rejects the mesh.
    std::cerr << "stcweave: warning: " << r.quality.inverted << " of "
              << r.mesh.complex.hexes.size()
              << " hexes are still inverted after untangling (scaled Jacobian <= 0; "
              << (options.untangle ? r.position.stop : std::string("--no-untangle"))
              << "); the mesh was written; add --fail-on-inverted to make this an error"
              << (r.pillow.applied || r.pillow.mode == primal::PillowMode::Always
                      ? std::string()
                      : std::string(", or try --pillow always"))
              << "\n";
  }
  if (inverted_left) {
    std::string ids;
    const std::vector<HexId>& bad = r.position.inverted;
    for (std::size_t i = 0; i < std::min<std::size_t>(bad.size(), 5); ++i)
      ids += (i > 0 ? ", " : "") + bad[i].str();
    if (bad.size() > 5) ids += ", ...";
    std::cerr << "stcweave: " << r.quality.inverted << " hexes are still inverted after untangling"
              << (ids.empty() ? "" : " (" + ids + ")") << "; "
              << (write_mesh ? "the mesh was written (--keep-invalid)"
                             : "the mesh was not written (--fail-on-inverted); add --keep-invalid "
                               "to write it anyway, or see the report's position.stop")
              << "\n";
    return kInverted;
  }
  return kSuccess;
}

}  // namespace

Action add_mesh_command(CLI::App& app) {
  auto args = std::make_shared<MeshArgs>();
  CLI::App* sub = app.add_subcommand(
      "mesh",
      "Fill a closed quad surface with hexahedra: read IN (a quad surface, or a hex mesh whose "
      "boundary is taken), weave its STC, check the hex complex (an invalid complex is never "
      "written: exit code 3), place interior nodes, write OUT.");
  sub->add_option("input", args->input,
                  "input surface (OBJ, OFF, VTK, VTU, MSH, MEDIT, MFEM) or CAD solid (STEP, "
                  "BREP, IGES)")
      ->required();
  sub->add_option("-o,--output", args->output,
                  "output hex mesh; format from the extension (.vtk .vtu .msh .mesh .inp)")
      ->required();
  sub->add_option("--input-format", args->input_format, "input format name (default: auto)");
  sub->add_option("--output-format", args->output_format,
                  "output format name: vtk, vtu, msh, msh2, medit, inp (default: auto)");
  add_weave_options(sub, args->weave);
  add_cad_options(sub, args->cad, args->input);
  sub->add_option("--report", args->report,
                  "write a JSON report (hexes, nodes, interior_nodes, valid, sheets, chords, "
                  "quality, position report, seconds per stage)");
  sub->add_option("--trace", args->trace,
                  "write a JSON-lines trace: one line per loop selection (candidates, weights, "
                  "choice) and per rule application (rule, node, faces, hex)");
  sub->add_flag("--check", args->check,
                "check the front invariants after every rule (slow, for debugging)");
  sub->add_flag("--keep-invalid", args->keep_invalid,
                "write the mesh even when the woven complex is invalid (exit code 3 all the same) "
                "or, with --fail-on-inverted, has inverted hexes (exit code 4 all the same)");
  sub->add_flag("--fail-on-inverted", args->fail_on_inverted,
                "exit with code 4, and do not write the mesh, when hexes are still inverted "
                "(scaled Jacobian <= 0) after untangling");
  sub->add_flag("--no-loop-moves", args->no_loop_moves,
                "refuse surfaces whose loops cross themselves (exit code 2) instead of attaching "
                "hexes until they do not, and do not rescue a loop-clean surface whose weave "
                "blocks with the ways of that stage");
  sub->add_option("--front-on-failure", args->front_on_failure,
                  "where the front goes when the search for loop moves gives up (default: "
                  "OUT.front.obj)");
  sub->add_option("--loop-moves-max", args->loop_moves_max, "loop moves: most hexes attached")
      ->check(kCount)
      ->capture_default_str();
  sub->add_option("--loop-moves-beam-depth", args->loop_moves_beam_depth,
                  "loop moves: moves looked ahead when no single move helps")
      ->check(kCount)
      ->capture_default_str();
  sub->add_option("--loop-moves-beam-width", args->loop_moves_beam_width,
                  "loop moves: fronts kept per level of that look-ahead")
      ->check(kCount)
      ->capture_default_str();
  sub->add_option("--loop-moves-evaluations", args->loop_moves_evaluations,
                  "loop moves: candidate moves evaluated in all (the search's evaluation bound)")
      ->check(kCount)
      ->capture_default_str();
  sub->add_option("--loop-moves-work", args->loop_moves_work,
                  "loop moves: work bound, the sum over evaluated candidates of the front's "
                  "faces (about 5 s on a 10,000-quad surface at the default)")
      ->check(kCount)
      ->capture_default_str();
  sub->add_option("--loop-moves-tiny-depth", args->loop_moves_tiny_depth,
                  "loop moves: on a front of at most " +
                      std::to_string(primal::SelfCrossingOptions{}.search.tiny_front) +
                      " faces where every look-ahead stalls, search every sequence of up to "
                      "this many moves (0: off)")
      ->check(kCount)
      ->capture_default_str();
  sub->add_flag("--depth-filter-always", args->depth_filter_always,
                "extended: weave a genus-0 shell with the depth filter from the start (by default "
                "it is woven without it first, and with it only when that weave blocks; "
                "docs/extended-rules.md)");
  sub->add_flag("--no-untangle", args->no_untangle,
                "keep the harmonic placement of the interior nodes (no untangling)");
  sub->add_option("--start", args->start,
                  "untangling starts from: harmonic, or layers (the weave's layer placement, or "
                  "the harmonic one when that has fewer inverted corners)")
      ->capture_default_str();
  sub->add_option("--pillow", args->pillow,
                  "pillow the boundary (a layer of hexes between each boundary quad and an "
                  "interior copy of it): auto (only shells with a hex corner fixed by the "
                  "boundary and flat or inverted), always, never")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "always", "never"}));
  sub->add_option("--interior", args->interior,
                  "the interior of a triangle-split surface (docs/tet-interior.md): auto (weave "
                  "it and split a tetrahedral mesh of it, keep the better), weave, tets (split "
                  "a tetrahedral mesh; other surfaces are refused)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "weave", "tets"}));
  sub->add_option("--tet-growth", args->tet_growth,
                  "tet interior: the interior tetrahedra may grow away from the boundary to this "
                  "many times the boundary's edge length (1: Gmsh's sizes)")
      ->check(kFinite)
      ->capture_default_str()
      ->check(CLI::Range(1.0, 10.0));
  sub->add_option("--tet-flips", args->tet_flips,
                  "tet interior: 3-2 flips before the split (four hexes fewer each), each made "
                  "only when its new tets' worst corner quality stays at least this floor or at "
                  "least the replaced tets' worst (0 to 1; 1: never lower it); off: none")
      ->capture_default_str()
      ->check([](const std::string& value) -> std::string {
        if (value == "off") return {};
        std::size_t used = 0;
        double floor = -1.0;
        try {
          floor = std::stod(value, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used == value.size() && floor >= 0.0 && floor <= 1.0) return {};
        return "must be off or a quality floor from 0 to 1, not '" + value + "'";
      });
  sub->add_option("--position-rounds", args->position_rounds,
                  "untangling: most rounds of (minimise, lower epsilon)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  sub->add_option("--position-iterations", args->position_iterations,
                  "untangling: most L-BFGS iterations per round")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000000));
  sub->add_option("--position-total-iterations", args->position_total_iterations,
                  "untangling: most L-BFGS iterations over every round, its total work bound "
                  "(0: none); when it is reached the hexes still inverted go to the repair")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000000));
  sub->add_flag("--position-precondition,!--no-position-precondition", args->position_precondition,
                "untangling: L-BFGS preconditioned by a multigrid V-cycle of the hex edges' graph "
                "Laplacian")
      ->capture_default_str();
  sub->add_option("--position-newton-after", args->position_newton_after,
                  "untangling: a round whose L-BFGS uses this many iterations goes on with "
                  "projected Newton steps (sparse Cholesky); 0: never")
      ->capture_default_str()
      ->check(CLI::Range(0, 10000000));
  sub->add_option("--position-newton-steps", args->position_newton_steps,
                  "untangling: most projected Newton steps per round")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  sub->add_option("--position-theta", args->position_theta,
                  "untangling: weight of the volume term against the shape term, in [0, 1]")
      ->check(kFinite)
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--cluster-passes", args->cluster_passes,
                  "local untangling after the repair: most passes over the clusters of hexes "
                  "still inverted, each positioned on its own with its boundary held (0: off; "
                  "docs/geometry.md \"Local untangling\")")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  sub->add_flag("--no-cluster-hinge", args->no_cluster_hinge,
                "local untangling: skip its last phase (a sum of hinges on a mean-ratio measure "
                "minimised over each cluster still inverted; docs/geometry.md \"Local "
                "untangling\")");
  sub->add_option("--threads", args->threads,
                  "positioning: threads for the untangling energy of meshes of 1,024 hexes or "
                  "more and for the local untangling's two starts; above 1, stages that read the "
                  "same data also run side by side (validation and harmonic placement, STC and "
                  "positioning) (0: one per hardware thread; 1: one thread, e.g. when several "
                  "runs share the machine); the mesh does not depend on it")
      ->capture_default_str()
      ->check(CLI::Range(0, 256));
  sub->add_option("--shape-sweeps", args->shape_sweeps,
                  "shape phase after untangling: most sweeps of local max-min moves that raise "
                  "the worst scaled Jacobian (0: off)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000));
  sub->add_option("--shape-target", args->shape_target,
                  "shape phase: hexes below this scaled Jacobian are worked on")
      ->check(kFinite)
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--shape-hinges-below", args->shape_hinges_below,
                  "shape phase, last pass: hexes still below this scaled Jacobian are raised by "
                  "hinges over small sub-meshes around them, worst first (0: off; "
                  "docs/geometry.md \"Shape phase\")")
      ->check(kFinite)
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--good-start", args->good_start,
                  "positioning keeps a start with no inverted corner whose min scaled Jacobian "
                  "is at least this (no untangling rounds; above 1: never)")
      ->check(kFinite)
      ->capture_default_str()
      ->check(CLI::Range(0.0, 2.0));
  sub->add_option("--certify-depth", args->certify_depth,
                  "subdivision depth of the Bezier validity certification of every hex")
      ->capture_default_str()
      ->check(CLI::Range(0, 8));
  sub->add_flag("--no-cell-data", args->no_cell_data,
                "write the mesh alone: no cell data (scaled_jacobian, sheet_0..2, chord_0..2, "
                "layer, creation_step, shrink, rule, depth) and no point data (boundary, "
                "valence) in VTK, VTU and MSH output");
  sub->add_option("--html", args->html,
                  "also write the browser page of the mesh (self-contained HTML, three.js "
                  "inlined): replay of the weave, sheets, quality; see `stcweave view`");
  sub->add_flag("--progress", args->progress,
                "print stage, front-move search, weaving and positioning progress on stderr "
                "(the default on a terminal unless -q)");
  sub->add_flag("-q,--quiet", args->quiet, "print nothing on success");
  return [args] { return run_mesh(*args); };
}

}  // namespace stcweave::cli
