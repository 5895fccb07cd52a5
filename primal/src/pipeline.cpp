#include "stcweave/primal/pipeline.hpp"

#include <chrono>
#include <optional>
#include <string>
#include <utility>

#include "position_pinch.hpp"
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

}  // namespace

MeshResult mesh_file(const MeshFile& file, const MeshOptions& options) {
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
  if (r.diagnosis.handles && !r.diagnosis.handles->decided) {
    throw Unsupported(file.path + ": cannot tell which cycles bound inside the solid (" +
                      r.diagnosis.handles->undecided_reason +
                      "), so whether a hex mesh exists is undecided; docs/topology.md lists "
                      "the assumptions of the test");
  }
  r.surface = surface_of(file, &r.file_nodes);
  r.seconds.diagnose = clock.lap();

  stage("orient");
  r.orientation = orient_outward(r.surface);
  for (std::size_t c = 0; c < r.orientation.nesting_depth.size(); ++c) {
    if (r.orientation.nesting_depth[c] > 1) {
      throw Unsupported("component " + std::to_string(c) + " of " + file.path +
                        " lies inside a cavity of another shell (nesting depth " +
                        std::to_string(r.orientation.nesting_depth[c]) +
                        "): not supported yet; mesh the solids separately");
    }
    if (r.orientation.nesting_depth[c] == 1) whole = false;  // a cavity: weave_solids
  }
  r.seconds.orient = clock.lap();

  stage("weave");
  // The extended rule set reads the surface's dihedral angles (weave knows no coordinates).
  const std::vector<std::array<double, 4>> angles = options.weave.rules == weave::RuleSet::Extended
                                                        ? dihedral_angles(r.surface)
                                                        : std::vector<std::array<double, 4>>{};
  const bool self_crossing = r.diagnosis.self_intersecting_loops.value_or(0) > 0;
  if (!whole && options.self_crossing_moves && self_crossing) {
    r.woven = weave_solids_self_crossing(r.surface, options.weave, options.cut,
                                         options.self_crossing, &r.solids, r.self_crossing);
  } else if (whole && options.self_crossing_moves && self_crossing) {
    r.woven = weave_self_crossing(r.surface, options.weave, angles, options.self_crossing,
                                  r.self_crossing);
  } else if (whole) {
    try {
      r.woven = weave::weave(r.surface.surface, options.weave, angles);
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

  stage("validate");
  r.validation = stc::validate_hex_complex(r.woven.complex, &r.surface.surface);
  r.seconds.validate = clock.lap();
  if (!r.validation.valid && !options.keep_invalid) stc::require_valid(r.validation);

  stage("recover");
  r.mesh = recover_hex_mesh(r.surface.points, r.woven, &r.harmonic);
  r.seconds.recover = clock.lap();

  // The layer placement reads the weave's own hexes, so it runs before pillowing.
  const bool layer_start =
      options.untangle && options.layer_start && layer_positions(r.mesh, r.woven) > 0;

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
    const UnpinchReport u = unpinch(r.mesh, r.surface.surface.num_nodes, r.surface.surface);
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
        throw InternalError(
            "the woven complex has " + std::to_string(u.pinched_after) +
            " pinched face pairs (two faces sharing two edges at a node, no placement makes "
            "the hexes there valid; " +
            r.validation.summary() + ") that no pillow of a 2-hex block of interior nodes " +
            "removes" + (r.pillow.applied ? std::string() : std::string(": try --pillow always")) +
            " (--keep-invalid writes the mesh anyway)");
      }
    }
  }
  r.seconds.pillow = clock.lap();

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
        r.mesh = std::move(*woven_mesh);
        r.position = std::move(unpillowed);
        r.validation = stc::validate_hex_complex(r.mesh.complex, &r.surface.surface,
                                                 r.pillow.pinched_pairs > 0);
      }
    }
    r.seconds.position = clock.lap();
  }

  stage("quality");
  r.quality = summarize_quality(r.mesh);
  r.seconds.quality = clock.lap();
  return r;
}

}  // namespace stcweave::primal
