// Weave time on structured boxes k x k x k and on the largest shared loop-clean surfaces.
// Run: build/bin/stcweave_bench [--benchmark_filter=...]; counters give hexes per second.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/weave/weave.hpp"
#include "support/shapes.hpp"

namespace {

using namespace stcweave;

// Second argument: 0 = reliable, 1 = extended (with the surface's dihedral angles).
weave::WeaveOptions options_for(std::int64_t rules) {
  weave::WeaveOptions o;
  o.rules = rules == 0 ? weave::RuleSet::Reliable : weave::RuleSet::Extended;
  return o;
}

/// Times weaving `s` with the rule set `rules` (0 reliable, 1 extended) and reports hexes and
/// hexes per second.
void measure(benchmark::State& state, const primal::SurfaceMesh& s, std::int64_t rules,
             bool backtrack = true) {
  weave::WeaveOptions options = options_for(rules);
  options.backtrack = backtrack;
  const auto angles =
      rules == 0 ? std::vector<std::array<double, 4>>{} : primal::dihedral_angles(s);
  std::size_t hexes = 0;
  for (auto _ : state) {
    const auto r = weave::weave(s.surface, options, angles);
    hexes = r.complex.hexes.size();
    benchmark::DoNotOptimize(hexes);
  }
  state.counters["quads"] = static_cast<double>(s.surface.quads.size());
  state.counters["hexes"] = static_cast<double>(hexes);
  state.counters["hexes_per_s"] =
      benchmark::Counter(static_cast<double>(hexes) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
}

void weave_box(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  measure(state, test::box_surface(k, k, k), state.range(1));
}
BENCHMARK(weave_box)
    ->ArgNames({"k", "extended"})
    ->ArgsProduct({{4, 8, 16, 24, 32}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

// The same without backtracking: the difference is the cost of the undo points (one
// checkpoint per shrink; it was a copy of the whole state before the journal).
void weave_box_no_backtrack(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  measure(state, test::box_surface(k, k, k), state.range(1), false);
}
BENCHMARK(weave_box_no_backtrack)
    ->ArgNames({"k", "extended"})
    ->ArgsProduct({{16, 32}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

void weave_shared(benchmark::State& state, const std::string& name) {
  const std::filesystem::path path = std::filesystem::path(STCWEAVE_SHARED_DATA) / name;
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("shared data not found");
    return;
  }
  primal::SurfaceMesh s = primal::surface_of(primal::read_mesh(path));
  (void)primal::orient_outward(s);
  measure(state, s, state.range(0));
}
BENCHMARK_CAPTURE(weave_shared, lblock_tf_medium, std::string("gmsh/lblock_tf_medium.obj"))
    ->ArgName("extended")
    ->DenseRange(0, 1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(weave_shared, cube_tf_medium, std::string("gmsh/cube_tf_medium.obj"))
    ->ArgName("extended")
    ->DenseRange(0, 1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(weave_shared, Chamfer_L0, std::string("real/hexalab/selpad2019_Chamfer_L0.mesh"))
    ->ArgName("extended")
    ->DenseRange(0, 1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(weave_shared, pave2, std::string("real/mesquite/pave2.e.vtk"))
    ->ArgName("extended")
    ->DenseRange(0, 1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
