// The kernels of the pipeline, one at a time, on k x k x k boxes (k = 4 ... 32) and on the
// largest loop-clean shared surfaces: loop extraction, the cost of one rule application and
// of one loop shrink (see below), primal recovery, validation of the hex complex; and the
// search for front moves on shared surfaces whose loops cross themselves.
// (Whole weaves: weave_bench.cpp. Node positioning: position_bench.cpp.)
//
// Run: build/bin/stcweave_kernels_bench [--benchmark_filter=...]. Counters: quads, hexes,
// and for the weave the seconds per rule and per shrink.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/generate.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/primal/recover.hpp"
#include "stcweave/stc/loop_moves.hpp"
#include "stcweave/stc/loops.hpp"
#include "stcweave/stc/validate.hpp"
#include "stcweave/weave/weave.hpp"

namespace {

using namespace stcweave;

void box_sizes(benchmark::internal::Benchmark* b) {
  for (const int k : {4, 8, 16, 24, 32, 48}) b->Arg(k);
  b->Unit(benchmark::kMillisecond);
}

/// The surface of a shared file, oriented outward; empty when the data is missing.
primal::SurfaceMesh shared_surface(const std::string& name) {
  const std::filesystem::path path = std::filesystem::path(STCWEAVE_SHARED_DATA) / name;
  if (!std::filesystem::exists(path)) return {};
  primal::SurfaceMesh s = primal::surface_of(primal::read_mesh(path));
  (void)primal::orient_outward(s);
  return s;
}

// ---- loop extraction (stc::find_loops, sides included as the weave needs them) ----

void find_loops_on(benchmark::State& state, const primal::SurfaceMesh& s) {
  std::size_t loops = 0;
  for (auto _ : state) {
    const stc::LoopSet set = stc::find_loops(s.surface);
    loops = set.size();
    benchmark::DoNotOptimize(loops);
  }
  state.counters["quads"] = static_cast<double>(s.surface.quads.size());
  state.counters["loops"] = static_cast<double>(loops);
}

void loops_box(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  find_loops_on(state, primal::box_surface(k, k, k));
}
BENCHMARK(loops_box)->Apply(box_sizes);

void loops_shared(benchmark::State& state, const std::string& name) {
  const primal::SurfaceMesh s = shared_surface(name);
  if (s.surface.quads.empty()) {
    state.SkipWithError("shared data not found");
    return;
  }
  find_loops_on(state, s);
}
BENCHMARK_CAPTURE(loops_shared, KPDloekr, std::string("real/hexalab/cfip2016_KPDloekr-hex.vtk"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(loops_shared, lblock_tf_medium, std::string("gmsh/lblock_tf_medium.obj"))
    ->Unit(benchmark::kMillisecond);

// ---- one rule application, one loop shrink ----
// The public weave API runs a whole weave; a single seam / cross or a single shrink is not
// callable on its own. These kernels time whole weaves and divide: the counters give the
// mean seconds per rule applied (seams + crosses + blind chords) and per loop shrink.

void weave_rule_cost(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const primal::SurfaceMesh s = primal::box_surface(k, k, k);
  weave::WeaveStats stats;
  for (auto _ : state) {
    const weave::WeaveResult r = weave::weave(s.surface);
    stats = r.stats;
    benchmark::DoNotOptimize(r.complex.hexes.data());
  }
  const double rules = static_cast<double>(stats.seams + stats.crosses + stats.blind_chords);
  const double shrinks = static_cast<double>(stats.shrinks);
  state.counters["rules"] = rules;
  state.counters["shrinks"] = shrinks;
  state.counters["s_per_rule"] = benchmark::Counter(
      rules, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["s_per_shrink"] = benchmark::Counter(
      shrinks, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(weave_rule_cost)->Apply(box_sizes);

// ---- primal recovery and validation, on a woven box ----

struct WovenBox {
  primal::SurfaceMesh surface;
  weave::WeaveResult woven;
};

WovenBox woven_box(int k) {
  WovenBox w;
  w.surface = primal::box_surface(k, k, k);
  w.woven = weave::weave(w.surface.surface);
  return w;
}

void recover_box(benchmark::State& state) {
  const WovenBox w = woven_box(static_cast<int>(state.range(0)));
  primal::HarmonicReport report;
  for (auto _ : state) {
    const primal::HexMesh mesh = primal::recover_hex_mesh(w.surface.points, w.woven, &report);
    benchmark::DoNotOptimize(mesh.points.data());
  }
  state.counters["hexes"] = static_cast<double>(w.woven.complex.hexes.size());
  state.counters["iterations"] = static_cast<double>(report.iterations);
  state.counters["levels"] = static_cast<double>(report.levels);
}
BENCHMARK(recover_box)->Apply(box_sizes);

void validate_box(benchmark::State& state) {
  const WovenBox w = woven_box(static_cast<int>(state.range(0)));
  std::size_t invalid = 0;
  for (auto _ : state) {
    const stc::ValidationReport report =
        stc::validate_hex_complex(w.woven.complex, &w.surface.surface);
    invalid += report.valid ? 0 : 1;
    benchmark::DoNotOptimize(report.faces);
  }
  state.counters["hexes"] = static_cast<double>(w.woven.complex.hexes.size());
  if (invalid > 0) state.SkipWithError("the woven box is not a valid complex");
}
BENCHMARK(validate_box)->Apply(box_sizes);

// ---- the search for front moves (stc::untangle_loops), default bounds ----
// Counters: evaluations (candidate moves evaluated), the seconds per evaluation, attached
// hexes and the self-crossing quads left (0: the loops are simple). rod's search stalls with
// default options (26 self-crossing quads left): its time is that of a search that gives up.

void loop_moves_shared(benchmark::State& state, const std::string& name) {
  const primal::SurfaceMesh s = shared_surface(name);
  if (s.surface.quads.empty()) {
    state.SkipWithError("shared data not found");
    return;
  }
  stc::LoopMoveResult r;
  for (auto _ : state) {
    r = stc::untangle_loops(s.surface);
    benchmark::DoNotOptimize(r.front.quads.data());
  }
  state.counters["quads"] = static_cast<double>(s.surface.quads.size());
  state.counters["evaluations"] = static_cast<double>(r.evaluations);
  state.counters["s_per_evaluation"] = benchmark::Counter(
      static_cast<double>(r.evaluations),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["hexes"] = static_cast<double>(r.hexes.hexes.size());
  state.counters["self_crossing_left"] = static_cast<double>(r.self_crossing_quads_after);
}
BENCHMARK_CAPTURE(loop_moves_shared, cylinder2_c3, std::string("real/gmsh-quad/cylinder2_c3.msh"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(loop_moves_shared, rod, std::string("real/gmsh-quad/rod.msh"))
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
