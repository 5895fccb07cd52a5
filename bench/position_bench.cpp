// Positioning time against mesh size (Google Benchmark; timings live here, never in tests).
//
// - BM_PositionScrambledBox/n/precondition: the n^3 structured box with every interior node
//   moved by a seeded random vector of up to half its shortest edge (n = 10, 22, 46: about
//   1k, 10k and 100k hexes). Target: 100k hexes in under 10 s on the 2-core development
//   machine. precondition 1 is the default L-BFGS with the multigrid Laplacian
//   preconditioner, 0 the plain L-BFGS (docs/geometry.md, "Preconditioned L-BFGS"); the same
//   in BM_PositionBentBox.
// - BM_PositionBentBox/n/newton_after/precondition: the n^3 box bent into a 270-degree C,
//   interior from the harmonic map of the bent boundary (tangled: research/geometry.md
//   §3.3), a harder case; newton_after 0 is L-BFGS alone, 100 adds projected Newton steps to
//   slow rounds
//   (n = 20 with Newton takes about nine minutes: not run by default, docs/geometry.md).
//
// - BM_ShapePhaseScrambledBox/n: the shape phase alone on a valid scrambled box.
//
// Counters: hexes, inverted hexes before / after, min scaled Jacobian after, L-BFGS
// iterations, Newton steps and rounds.
#include <benchmark/benchmark.h>

#include <cmath>

#include "primal/position_helpers.hpp"
#include "stcweave/primal/position.hpp"
#include "support/shapes.hpp"

namespace {

using namespace stcweave;

/// Times position_nodes on copies of `start` (the copy is not timed) and reports the last run's
/// figures as counters.
void measure(benchmark::State& state, const primal::HexMesh& start,
             const primal::PositionOptions& options) {
  primal::PositionReport r;
  for (auto _ : state) {
    state.PauseTiming();
    primal::HexMesh mesh = start;
    state.ResumeTiming();
    r = primal::position_nodes(mesh, options);
    benchmark::DoNotOptimize(mesh.points.data());
  }
  state.counters["hexes"] = static_cast<double>(start.complex.hexes.size());
  state.counters["inverted_before"] = static_cast<double>(r.inverted_before);
  state.counters["inverted_after"] = static_cast<double>(r.inverted_after);
  state.counters["min_sj"] = r.min_scaled_jacobian_after;
  state.counters["iterations"] = static_cast<double>(r.iterations);
  state.counters["rounds"] = static_cast<double>(r.outer_iterations);
  state.counters["newton"] = static_cast<double>(r.newton_steps);
}

void BM_PositionScrambledBox(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  primal::HexMesh start = test::box_hexes(n, n, n);
  primal::PositionOptions options;
  options.fixed = test::boundary_nodes(start);
  test::scramble(start, options.fixed, 0.5, 1);
  options.precondition = state.range(1) != 0;
  measure(state, start, options);
}
BENCHMARK(BM_PositionScrambledBox)
    ->ArgNames({"n", "precondition"})
    ->ArgsProduct({{10, 22, 46}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

void BM_PositionBentBox(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  primal::HexMesh start = test::box_hexes(n, n, n);
  test::bend(start, n, n, 0.2 * n, 1.5 * M_PI);
  primal::PositionOptions options;
  options.num_fixed = test::boundary_first(start);
  options.start = primal::StartPosition::Harmonic;
  options.newton_after = static_cast<int>(state.range(1));
  options.precondition = state.range(2) != 0;
  measure(state, start, options);
}
BENCHMARK(BM_PositionBentBox)
    ->ArgNames({"n", "newton_after", "precondition"})
    ->Args({6, 0, 0})
    ->Args({6, 0, 1})
    ->Args({12, 0, 0})
    ->Args({12, 0, 1})
    ->Args({20, 0, 0})
    ->Args({20, 0, 1})
    ->Args({32, 0, 0})
    ->Args({32, 0, 1})
    ->Args({6, 100, 0})
    ->Args({12, 100, 0})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

/// The shape phase alone (`improve_shape`) on the n^3 box scrambled by 0.25 of the shortest
/// edge (valid, min scaled Jacobian well below the 0.6 target, every node active). Target:
/// 100k hexes (n = 46) under 10 s.
void BM_ShapePhaseScrambledBox(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  primal::HexMesh start = test::box_hexes(n, n, n);
  const std::vector<bool> fixed = test::boundary_nodes(start);
  test::scramble(start, fixed, 0.25, 3);
  primal::ShapeReport r;
  for (auto _ : state) {
    state.PauseTiming();
    primal::HexMesh mesh = start;
    state.ResumeTiming();
    r = primal::improve_shape(mesh, fixed, {});
    benchmark::DoNotOptimize(mesh.points.data());
  }
  state.counters["hexes"] = static_cast<double>(start.complex.hexes.size());
  state.counters["min_sj_before"] = r.min_scaled_jacobian_before;
  state.counters["min_sj_after"] = r.min_scaled_jacobian_after;
  state.counters["sweeps"] = static_cast<double>(r.sweeps);
  state.counters["moves"] = static_cast<double>(r.moves);
}
BENCHMARK(BM_ShapePhaseScrambledBox)
    ->Arg(10)
    ->Arg(22)
    ->Arg(46)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
