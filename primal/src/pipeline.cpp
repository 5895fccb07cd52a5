#include "stcweave/primal/pipeline.hpp"

#include <chrono>

#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/primal/pillow.hpp"
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
  for (std::size_t c = 0; c < r.diagnosis.genus_per_component.size(); ++c) {
    const auto& g = r.diagnosis.genus_per_component[c];
    if (g && *g > 0) {
      throw Unsupported("component " + std::to_string(c) + " of " + file.path + " has genus " +
                        std::to_string(*g) +
                        ": surfaces with handles (genus > 0) are not supported yet; only "
                        "genus-0 shells can be woven");
    }
  }
  r.surface = surface_of(file, &r.file_nodes);
  r.seconds.diagnose = clock.lap();

  stage("orient");
  r.orientation = orient_outward(r.surface);
  for (std::size_t c = 0; c < r.orientation.nesting_depth.size(); ++c) {
    if (r.orientation.nesting_depth[c] > 0) {
      throw Unsupported("component " + std::to_string(c) + " of " + file.path +
                        " lies inside another component (nested shells, e.g. a hollow ball): "
                        "not supported yet; mesh each shell's solid separately");
    }
  }
  r.seconds.orient = clock.lap();

  stage("weave");
  // The extended rule set reads the surface's dihedral angles (weave knows no coordinates).
  const std::vector<std::array<double, 4>> angles = options.weave.rules == weave::RuleSet::Extended
                                                        ? dihedral_angles(r.surface)
                                                        : std::vector<std::array<double, 4>>{};
  if (options.self_crossing_moves && r.diagnosis.self_intersecting_loops.value_or(0) > 0) {
    r.woven = weave_self_crossing(r.surface, options.weave, angles, options.self_crossing,
                                  r.self_crossing);
  } else {
    r.woven = weave::weave(r.surface.surface, options.weave, angles);
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
  r.pillow = pillow(r.mesh, r.surface.surface, options.pillow);
  if (r.pillow.applied) {
    // A pillowed complex that is not a hex complex with the input as boundary is a bug.
    r.validation = stc::validate_hex_complex(r.mesh.complex, &r.surface.surface);
    if (!r.validation.valid && !options.keep_invalid) stc::require_valid(r.validation);
  }
  r.seconds.pillow = clock.lap();

  if (options.untangle) {
    stage("position");
    PositionOptions position = options.position;
    position.num_fixed = r.woven.num_input_nodes;
    if (layer_start) position.start = StartPosition::Auto;
    r.position = position_nodes(r.mesh, position);
    r.seconds.position = clock.lap();
  }

  stage("quality");
  r.quality = summarize_quality(r.mesh);
  r.seconds.quality = clock.lap();
  return r;
}

}  // namespace stcweave::primal
