// Weave time on structured boxes k x k x k and on the largest shared loop-clean surfaces.
// Run: build/bin/stcweave_bench [--benchmark_filter=...]; counters give hexes per second.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/weave/weave.hpp"
#include "support/shapes.hpp"

namespace {

using namespace stcweave;

void weave_box(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const auto box = test::box_surface(k, k, k);
  std::size_t hexes = 0;
  for (auto _ : state) {
    const auto r = weave::weave(box.surface);
    hexes = r.complex.hexes.size();
    benchmark::DoNotOptimize(hexes);
  }
  state.counters["hexes"] = static_cast<double>(hexes);
  state.counters["hexes_per_s"] =
      benchmark::Counter(static_cast<double>(hexes) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
}
BENCHMARK(weave_box)->Arg(4)->Arg(8)->Arg(16)->Arg(24)->Arg(32)->Unit(benchmark::kMillisecond);

void weave_shared(benchmark::State& state, const std::string& name) {
  const std::filesystem::path path = std::filesystem::path(STCWEAVE_SHARED_DATA) / name;
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("shared data not found");
    return;
  }
  primal::SurfaceMesh s = primal::surface_of(primal::read_mesh(path));
  (void)primal::orient_outward(s);
  std::size_t hexes = 0;
  for (auto _ : state) {
    const auto r = weave::weave(s.surface);
    hexes = r.complex.hexes.size();
    benchmark::DoNotOptimize(hexes);
  }
  state.counters["quads"] = static_cast<double>(s.surface.quads.size());
  state.counters["hexes"] = static_cast<double>(hexes);
  state.counters["hexes_per_s"] =
      benchmark::Counter(static_cast<double>(hexes) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(weave_shared, lblock_tf_medium, std::string("gmsh/lblock_tf_medium.obj"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(weave_shared, cube_tf_medium, std::string("gmsh/cube_tf_medium.obj"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(weave_shared, Chamfer_L0, std::string("real/hexalab/selpad2019_Chamfer_L0.mesh"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(weave_shared, pave2, std::string("real/mesquite/pave2.e.vtk"))
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
