// The mesh stage's cost on the box (2M photons, h = 0.05 m, 2 threads unless --threads says otherwise):
//   BM_RefineAdaptive/T: --refine at tolerance T/1000 (coarsen, refine, evaluate, measure);
//   BM_SubdivideUniform/L: --subdivide L (OpenSubdiv, evaluate, measure).
// Counters: vertices written and the largest and mean (by area) displayed-luminance errors, so that time, size
// and accuracy of each run are read off one line. Photons are traced once, outside the timing.
// Usage: bench_refine [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include "tests/staged_bake.h"

namespace {

const pb::test::StagedBake& Box() {
  static const pb::test::StagedBake bake(PB_SOURCE_DIR "/data/box/box.obj", 2'000'000, {.bandwidth = 0.05f});
  return bake;
}

void Report(benchmark::State& state, const pb::BakedMesh& mesh, const pb::RefineReport& report) {
  state.counters["vertices"] = double(mesh.mesh.VertexCount());
  state.counters["max_error"] = report.maxError;
  state.counters["mean_error"] = report.meanError;
}

void BM_RefineAdaptive(benchmark::State& state) {
  pb::RefineSettings settings;
  settings.adaptive = true;
  settings.tolerance = float(state.range(0)) / 1000.0f;
  for (auto _ : state) {
    const pb::RefinedMesh refined = Box().Refine(settings);
    Report(state, refined.mesh, refined.report);
  }
}
BENCHMARK(BM_RefineAdaptive)->Arg(40)->Arg(20)->Arg(10)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SubdivideUniform(benchmark::State& state) {
  for (auto _ : state) {
    const pb::RefinedMesh refined = Box().Refine({.subdivide = int(state.range(0))});
    Report(state, refined.mesh, refined.report);
  }
}
BENCHMARK(BM_SubdivideUniform)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
