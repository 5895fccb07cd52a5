#include "stcweave/primal/pipeline.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <chrono>
#include <exception>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "position_pinch.hpp"
#include "stcweave/primal/beside.hpp"
#include "stcweave/primal/cut.hpp"
#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/primal/pillow.hpp"
#include "stcweave/primal/self_crossing_solids.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::primal {
namespace {

class Stopwatch {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return s;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

std::string figures(const MeshResult& r) {
  std::ostringstream out;
  out << r.quality.hexes << " hexes, " << r.quality.inverted << " inverted, min scaled Jacobian "
      << r.quality.min_scaled_jacobian;
  return out.str();
}

}  // namespace

bool better_or_equal(const MeshResult& x, const MeshResult& y) {
  if (x.validation.valid != y.validation.valid) return x.validation.valid;
  const QualitySummary& a = x.quality;
  const QualitySummary& b = y.quality;
  if (a.inverted != b.inverted) return a.inverted < b.inverted;
  if (a.min_scaled_jacobian != b.min_scaled_jacobian)
    return a.min_scaled_jacobian > b.min_scaled_jacobian;
  return a.hexes <= b.hexes;
}

namespace {

/// A necessary condition, in one pass over the quads, so that `auto` orients no surface that
/// cannot be triangle-split (boxes, every transfinite surface): the quads come in threes, and
/// each triangle's centre lies in exactly three of them.
bool may_be_triangle_split(const stc::QuadSurface& surface) {
  if (surface.quads.empty() || surface.quads.size() % 3 != 0) return false;
  std::vector<std::size_t> valence(surface.num_nodes, 0);
  for (const stc::Quad& q : surface.quads)
    for (const NodeId v : q) ++valence[v.index()];
  const auto in_three = static_cast<std::size_t>(std::count(valence.begin(), valence.end(), 3));
  return 3 * in_three >= surface.quads.size();
}

/// `InteriorMode::Auto` on a triangle-split surface: the whole pipeline once with each
/// interior, the better kept; with a handle or several shells the tets first, kept alone when
/// valid with no inverted hex. Nothing when the surface is not triangle-split (or Gmsh is
/// missing, or the file is not a readable closed manifold surface): the caller weaves as usual.
std::optional<MeshResult> compare_interiors(const MeshFile& file, const MeshOptions& options) {
  if (!has_tet_interior_support()) return std::nullopt;
  int genus = 0;
  std::size_t shells = 1;
  try {
    // Recognition first (cheap, on the surface as the pipeline orients it), the diagnosis
    // only for a surface that is triangle-split.
    SurfaceMesh oriented = surface_of(file);
    if (!may_be_triangle_split(oriented.surface)) return std::nullopt;
    (void)orient_outward(oriented);
    if (!stc::recognise_triangle_split(oriented.surface)) return std::nullopt;
    const SurfaceDiagnosis d = diagnose(file);
    if (!d.closed || !d.manifold) return std::nullopt;
    genus = d.genus.value_or(0);
    shells = d.components;
  } catch (const Error&) {
    return std::nullopt;  // the woven path reports what is wrong with the file
  }
  // Each run says which it is; the weave's trace reaches the caller only if it is kept (or
  // if both fail: then it says why the weave did).
  const auto labelled = [&options](const char* which) {
    return [&options, which](const std::string& stage) {
      if (options.on_stage) options.on_stage(std::string(which) + stage);
    };
  };
  auto buffered = std::make_shared<std::vector<weave::TraceEvent>>();
  const auto replay_trace = [&options, buffered] {
    if (options.weave.on_trace)
      for (const weave::TraceEvent& e : *buffered) options.weave.on_trace(e);
  };
  MeshOptions weave_only = options;
  weave_only.interior.mode = InteriorMode::Weave;
  weave_only.on_stage = labelled("woven interior: ");
  if (options.weave.on_trace)
    weave_only.weave.on_trace = [buffered](const weave::TraceEvent& e) { buffered->push_back(e); };
  MeshOptions tets_only = options;
  tets_only.interior.mode = InteriorMode::Tets;
  tets_only.on_stage = labelled("tet interior: ");
  std::optional<MeshResult> woven;
  std::optional<MeshResult> tets;
  std::exception_ptr weave_error;
  std::string tet_error;
  Stopwatch clock;
  const auto run_tets = [&] {
    try {
      tets = mesh_file(file, tets_only);
    } catch (const Error& e) {
      tet_error = e.what();
    }
    return clock.lap();
  };
  double tet_seconds = 0.0;
  const bool tets_first = genus > 0 || shells > 1;
  if (tets_first) {
    // With handles or several shells the weave needs handles or cavities cut, or weaves each
    // shell's star alone (docs/topology.md); on every such surface tried that cost more and
    // gave worse hexes than the tets; so the tets go first, and a valid result with no
    // inverted hex is kept without weaving.
    tet_seconds = run_tets();
    if (tets && tets->validation.valid && tets->quality.inverted == 0) {
      tets->interior.reason =
          "auto: tets (" +
          (genus > 0 ? "genus " + std::to_string(genus) : std::to_string(shells) + " shells") +
          ": not woven, as the tet interior is valid with no inverted hex and a weave would "
          "need " +
          (genus > 0 ? "its handles cut" : "its shells woven one by one or its cavities cut") + ")";
      return tets;
    }
  }
  try {
    woven = mesh_file(file, weave_only);
  } catch (const Error&) {
    weave_error = std::current_exception();
  }
  const double weave_seconds = clock.lap();
  if (!tets_first) tet_seconds = run_tets();
  if (!tets) {
    replay_trace();
    if (weave_error) std::rethrow_exception(weave_error);
    woven->interior.triangle_split = true;
    woven->interior.compared = true;
    woven->interior.reason = "auto: woven (the tet interior failed: " + tet_error + ")";
    woven->seconds.other_interior = tet_seconds;
    return woven;
  }
  tets->interior.compared = true;
  if (!woven) {
    tets->seconds.other_interior = weave_seconds;
    std::string why = "the weave failed";
    try {
      std::rethrow_exception(weave_error);
    } catch (const Error& e) {
      why += ": ";
      why += e.what();
    }
    tets->interior.reason = "auto: tets (" + why + ")";
    return tets;
  }
  const bool keep_tets = better_or_equal(*tets, *woven) && !better_or_equal(*woven, *tets);
  if (!keep_tets) replay_trace();
  MeshResult& kept = keep_tets ? *tets : *woven;
  kept.seconds.other_interior = (keep_tets ? *woven : *tets).seconds.total();
  // The tet run's report (its counts), whichever mesh is kept.
  TetInteriorReport report = tets->interior;
  report.used = keep_tets;
  report.reason = std::string("auto: ") + (keep_tets ? "tets" : "woven") +
                  " kept (tets: " + figures(*tets) + "; woven: " + figures(*woven) + ")";
  kept.interior = std::move(report);
  return std::move(kept);
}

}  // namespace

weave::WeaveResult weave_whole_shell(const stc::QuadSurface& surface, const MeshOptions& options,
                                     const std::vector<std::array<double, 4>>& angles,
                                     std::string& retry) {
  retry.clear();
  if (!options.depth_filter_after_block || options.weave.rules != weave::RuleSet::Extended ||
      !options.weave.extended.depth_filter)
    return weave::weave(surface, options.weave, angles);
  weave::WeaveOptions first = options.weave;
  first.extended.depth_filter = false;
  // The retry undoing the shrinks that leave a seam blocked comes last, in the weave with the
  // filter (the order measured first: docs/extended-rules.md, docs/weave-recovery.md).
  first.undo_seam_blocking_on_block = false;
  std::vector<weave::TraceEvent> held;
  if (options.weave.on_trace)
    first.on_trace = [&held](const weave::TraceEvent& e) { held.push_back(e); };
  try {
    weave::WeaveResult r = weave::weave(surface, first, angles);
    for (const weave::TraceEvent& e : held) options.weave.on_trace(e);
    return r;
  } catch (const WeaveError& blocked) {
    retry = blocked.what();
  }
  return weave::weave(surface, options.weave, angles);
}

MeshResult mesh_file(const MeshFile& file, const MeshOptions& options) {
  if (options.interior.mode == InteriorMode::Auto) {
    if (std::optional<MeshResult> compared = compare_interiors(file, options))
      return std::move(*compared);
  }
  const auto stage = [&](const char* name) {
    if (options.on_stage) options.on_stage(name);
  };
  MeshResult r;
  Stopwatch clock;

  stage("diagnose");
  r.diagnosis = diagnose(file);
  require_weavable(r.diagnosis, options.self_crossing_moves);
  // Handles and several shells go through `weave_solids` (cut.hpp); a single genus-0 shell
  // is woven whole (through the front moves of self_crossing.hpp when its loops cross
  // themselves).
  bool whole = r.diagnosis.components <= 1;
  for (const auto& g : r.diagnosis.genus_per_component) whole = whole && g && *g == 0;
  // The tet interior needs no handle cycle: a tetrahedral mesh of the solid exists whatever
  // they are (an odd one is still refused above, by require_weavable).
  if (r.diagnosis.handles && !r.diagnosis.handles->decided &&
      options.interior.mode != InteriorMode::Tets) {
    throw Unsupported(file.path + ": cannot tell which cycles bound inside the solid (" +
                      r.diagnosis.handles->undecided_reason +
                      "), so whether a hex mesh exists is undecided; docs/topology.md lists "
                      "the assumptions of the test");
  }
  r.surface = surface_of(file, &r.file_nodes);
  r.seconds.diagnose = clock.lap();

  stage("orient");
  r.orientation = orient_outward(r.surface);
  // Cavities and solids inside cavities (any nesting depth) are several shells, so not
  // `whole`: weave_solids weaves each solid with the cavities it is the innermost solid around.
  r.seconds.orient = clock.lap();

  stage("weave");
  // The extended rule set reads the surface's dihedral angles (weave knows no coordinates).
  const std::vector<std::array<double, 4>> angles = options.weave.rules == weave::RuleSet::Extended
                                                        ? dihedral_angles(r.surface)
                                                        : std::vector<std::array<double, 4>>{};
  const bool self_crossing = r.diagnosis.self_intersecting_loops.value_or(0) > 0;
  Points tet_positions;
  if (options.interior.mode == InteriorMode::Tets) {
    const std::optional<stc::TriangleSplit> split =
        stc::recognise_triangle_split(r.surface.surface);
    if (!split) {
      throw InvalidInput(file.path +
                         ": the tet interior (--interior tets) needs a triangle-split "
                         "surface (every triangle of a triangle mesh cut into three quads at its "
                         "centre and edge middles), and this one is not; use --interior weave");
    }
    r.interior.triangle_split = true;
    r.interior.used = true;
    r.interior.reason = "tets: the surface is triangle-split (" +
                        std::to_string(split->triangles.size()) + " triangles)";
    r.woven = tet_interior(r.surface, *split, options.interior, tet_positions, &r.interior);
  } else if (!whole && options.self_crossing_moves && self_crossing) {
    r.woven = weave_solids_self_crossing(r.surface, options.weave, options.cut,
                                         options.self_crossing, &r.solids, r.self_crossing);
  } else if (whole && options.self_crossing_moves && self_crossing) {
    r.woven = weave_self_crossing(r.surface, options.weave, angles, options.self_crossing,
                                  r.self_crossing);
  } else if (whole) {
    try {
      r.woven = weave_whole_shell(r.surface.surface, options, angles, r.depth_filter_retry);
    } catch (const WeaveError& blocked) {
      // A loop-clean shell whose weave blocked even with the block recovery: the other ways
      // of the front-move stage (the fill by moves of a small front, the weave with recovery
      // pillows of blocked valence-2 nodes, the reliable rules, last the front a stalled fill
      // left; docs/weave-recovery.md "Rescue"). Not with --block-recovery off, which asks for the
      // first block alone, nor with a rule budget of the caller's (--max-rules), which the rescue
      // would not keep.
      if (!options.self_crossing_moves ||
          options.weave.block_recovery == weave::BlockRecovery::Off || options.weave.max_rules != 0)
        throw;
      SelfCrossingOptions rescue = options.self_crossing;
      rescue.plain_weave_blocked = true;
      try {
        r.woven = weave_self_crossing(r.surface, options.weave, angles, rescue, r.self_crossing);
      } catch (const WeaveError& again) {
        throw WeaveError(std::string(blocked.what()) + "\n  rescue by the ways of the front-move " +
                         "stage: " + again.what());
      }
      r.self_crossing.after_block = blocked.what();
    }
  } else {
    r.woven = weave_solids(r.surface, options.weave, options.cut, &r.solids);
  }
  r.seconds.weave = clock.lap();

  // The validation and the harmonic placement both only read the woven complex: with a
  // second thread they run side by side (with it, the pinched face pairs the pillow stage
  // looks for are found there too). The validation's verdict is still acted on first.
  const bool side_by_side = second_thread(options.position.threads);
  struct Checked {
    stc::ValidationReport validation;
    std::optional<std::vector<PinchedFaces>> pinched;
  };
  stage("validate");
  Beside<Checked> checking(side_by_side, [&] {
    Checked c{stc::validate_hex_complex(r.woven.complex, &r.surface.surface), std::nullopt};
    if (side_by_side && c.validation.valid) c.pinched = pinched_faces(r.woven.complex);
    return c;
  });
  Checked checked;
  const auto act_on_validation = [&] {
    checked = checking.get();
    r.validation = checked.validation;
    if (!r.validation.valid && !options.keep_invalid) stc::require_valid(r.validation);
  };
  if (!side_by_side) act_on_validation();  // done already: an invalid complex stops here

  stage("recover");
  std::exception_ptr recover_error;
  Stopwatch recover_clock;
  try {
    if (r.interior.used) {
      // The tet split comes with its own positions: Gmsh's interior vertices, the centres.
      r.mesh.complex = r.woven.complex;
      r.mesh.points = tet_positions;
    } else {
      r.mesh = recover_hex_mesh(r.surface.points, r.woven, &r.harmonic);
    }
  } catch (...) {
    recover_error = std::current_exception();
  }
  r.seconds.recover = recover_clock.lap();
  if (side_by_side) act_on_validation();
  // Read once the task is over (`get` waited for it).
  r.seconds.validate = checking.seconds();
  const double validate_and_recover = clock.lap();
  if (side_by_side) {
    r.seconds.overlap =
        std::max(0.0, r.seconds.validate + r.seconds.recover - validate_and_recover);
  }
  if (recover_error) std::rethrow_exception(recover_error);

  // The layer placement reads the weave's own hexes, so it runs before pillowing.
  const bool layer_start = !r.interior.used && options.untangle && options.layer_start &&
                           layer_positions(r.mesh, r.woven) > 0;

  stage("pillow");
  // Auto may compare the pillowed complex with the woven one after positioning both.
  std::optional<HexMesh> woven_mesh;
  if (options.untangle && options.pillow.mode == PillowMode::Auto && options.pillow.compare)
    woven_mesh = r.mesh;
  r.pillow = pillow(r.mesh, r.surface.surface, options.pillow);
  if (r.pillow.applied) {
    // A pillowed complex that is not a hex complex with the input as boundary is a bug.
    r.validation = stc::validate_hex_complex(r.mesh.complex, &r.surface.surface);
    if (!r.validation.valid && !options.keep_invalid) stc::require_valid(r.validation);
  }
  // Pinched face pairs (docs/geometry.md "Pinched faces") keep a flat corner whatever the
  // positions: pillow a 2-hex block at each (interior nodes only); no-op without one. The
  // result is then validated with the pinched-pair check: one left is refused, not output.
  if (r.validation.valid) {
    // The pairs found beside the recovery are those of this complex unless a pillow changed it.
    const UnpinchReport u = unpinch(r.mesh, r.surface.surface.num_nodes, r.surface.surface,
                                    r.pillow.applied ? std::nullopt : std::move(checked.pinched));
    r.pillow.pinched_pairs = u.pinched_before;
    r.pillow.unpinch_blocks = u.blocks;
    r.pillow.unpinch_hexes = u.hexes_added;
    r.pillow.pinched_left = u.pinched_after;
    if (u.pinched_before > 0) {
      r.pillow.reason += "; " + std::to_string(u.pinched_before) + " pinched face pairs, " +
                         std::to_string(u.blocks) + " 2-hex blocks pillowed (" +
                         std::to_string(u.hexes_added) + " hexes), " +
                         std::to_string(u.pinched_after) + " left";
      r.validation = stc::validate_hex_complex(r.mesh.complex, &r.surface.surface, true);
      if (!r.validation.valid && !options.keep_invalid) {
        const std::string pairs =
            "the woven complex has " + std::to_string(u.pinched_after) +
            " pinched face pairs (two faces sharing two edges at a node, no placement makes "
            "the hexes there valid; " +
            r.validation.summary() + ") that no pillow of a 2-hex block of interior nodes removes";
        if (!r.pillow.unpillowable.empty()) {
          // Not a bug: the pairs at boundary nodes need the pillow layer, which such a shell
          // cannot have (its hexes would share four nodes off a face).
          throw WeaveError(pairs + ", and the boundary cannot be pillowed: its quads " +
                           r.pillow.unpillowable +
                           " share two nodes that are not an edge, so their pillow hexes would "
                           "share four nodes off a face (docs/self-intersecting-loops.md "
                           "\"Hexes sharing four nodes off a face\"); re-mesh the surface so that "
                           "no two quads meet at two opposite corners (--keep-invalid writes the "
                           "mesh anyway)");
        }
        throw InternalError(
            pairs + (r.pillow.applied ? std::string() : std::string(": try --pillow always")) +
            " (--keep-invalid writes the mesh anyway)");
      }
    }
  }
  r.seconds.pillow = clock.lap();

  // The STC reads only the complex, which the positioning does not change: with a second
  // thread it is built beside the positioning and the quality summary.
  Stopwatch section;
  using SharedStc = std::shared_ptr<const stc::HexStc>;
  const auto build_stc = [](const HexMesh& mesh) {
    // Built in place (not moved: a moved HexStc copies its Boost graphs).
    return SharedStc(new stc::HexStc(stc::build_hex_stc(mesh.complex)));  // NOLINT
  };
  std::optional<Beside<SharedStc>> stc_beside;
  const auto build_stc_beside = [&] {
    if (options.build_stc && side_by_side)
      stc_beside.emplace(true, [&] { return build_stc(r.mesh); });
  };
  build_stc_beside();

  if (options.untangle) {
    stage("position");
    PositionOptions position = options.position;
    position.num_fixed = r.woven.num_input_nodes;
    if (layer_start) position.start = StartPosition::Auto;
    r.position = position_nodes(r.mesh, position);
    if (woven_mesh && pillow_worth_comparing(r.pillow, options.pillow)) {
      stage("position without the pillow (to compare)");
      PositionReport unpillowed = position_nodes(*woven_mesh, position);
      const auto candidate = [](const HexMesh& m, const PositionReport& p) {
        return PillowCandidate{p.inverted_after, p.min_scaled_jacobian_after,
                               p.mean_scaled_jacobian_after, m.complex.hexes.size()};
      };
      const PillowCandidate with = candidate(r.mesh, r.position);
      const PillowCandidate without = candidate(*woven_mesh, unpillowed);
      const bool keep = choose_pillowed(with, without);
      r.pillow = compared_pillow_report(r.pillow, keep, with, without);
      if (!keep) {
        // The complex changes: the STC of the pillowed one is dropped (after its thread ends).
        if (stc_beside) (void)stc_beside->get();
        stc_beside.reset();
        r.mesh = std::move(*woven_mesh);
        build_stc_beside();
        r.position = std::move(unpillowed);
        r.validation = stc::validate_hex_complex(r.mesh.complex, &r.surface.surface,
                                                 r.pillow.pinched_pairs > 0);
      }
    }
    r.seconds.position = clock.lap();
    // A node that is not finite is never written (the fuzzing of 2026-12-07 found a box with
    // one node pulled 1000 units out whose local untangling kept NaN positions: a NaN hex
    // passed for an untangled one; hex_scaled_jacobian now scores it -1).
    for (Eigen::Index v = 0; v < r.mesh.points.rows(); ++v) {
      if (!r.mesh.points.row(v).allFinite()) {
        throw InternalError(file.path + ": node n" + std::to_string(v) +
                            " has a coordinate that is not finite after positioning (" +
                            r.position.stop.substr(0, 300) +
                            "); no mesh is written: please report the input (--no-untangle "
                            "writes the complex at its start positions)");
      }
    }
  }

  stage("quality");
  r.quality = summarize_quality(r.mesh);
  r.seconds.quality = clock.lap();

  // The last validation of the final complex asked this check too (the default); with
  // --keep-invalid the pairs it found are reported.
  if (const stc::Violation* v = r.validation.find(stc::Invariant::SharedNodesNotAFace))
    r.shared_nodes = *v;

  if (stc_beside) {
    r.stc = stc_beside->get();
    r.seconds.stc = stc_beside->seconds();
    clock.lap();
    r.seconds.overlap +=
        std::max(0.0, r.seconds.position + r.seconds.quality + r.seconds.stc - section.lap());
  } else if (options.build_stc) {
    stage("stc");
    r.stc = build_stc(r.mesh);
    r.seconds.stc = clock.lap();
  }
  return r;
}

}  // namespace stcweave::primal
