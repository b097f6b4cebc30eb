// What --target-noise costs over one bake of the photon count it ended with (the count "chosen after the
// fact"), on the bundled scenes, h = 0.05 m, target 2%, first round 200k photons:
//   BM_TargetNoise/S: the rounds (each traces only the new photons, then bins, estimates and measures the noise);
//   BM_OneBake/S:     one bake of the rounds' final --photons, which writes the same bytes.
// S: 0 = box, 1 = office_empty. Counters: photons, rounds and the noise reached. Compare the medians of one run:
//   bench_progressive --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <map>

#include "baker/bake.h"

namespace {

const char* const kScenes[] = {PB_SOURCE_DIR "/data/box/box.obj", PB_SOURCE_DIR "/data/office_empty/office_empty.obj"};

pb::BakeOptions Options(int scene, uint64_t photons) {
  pb::BakeOptions o;
  o.scenePath = kScenes[scene];
  o.photons = photons;
  o.quiet = true;
  return o;
}

pb::BakeOptions Progressive(int scene) {
  pb::BakeOptions o = Options(scene, 200'000);
  o.targetNoise = 0.02f;
  return o;
}

// The rounds' final --photons, from one untimed run.
uint64_t FinalPhotons(int scene) {
  static std::map<int, uint64_t> found;
  if (!found.count(scene)) found[scene] = pb::BakeMesh(Progressive(scene), pb::Log(true)).report.progressive.rounds.back().requested;
  return found[scene];
}

void BM_TargetNoise(benchmark::State& state) {
  const int scene = int(state.range(0));
  for (auto _ : state) {
    const pb::BakeResult r = pb::BakeMesh(Progressive(scene), pb::Log(true));
    state.counters["photons"] = double(r.report.progressive.rounds.back().requested);
    state.counters["rounds"] = double(r.report.progressive.rounds.size());
    state.counters["noise"] = r.report.progressive.rounds.back().noise;
  }
}
BENCHMARK(BM_TargetNoise)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_OneBake(benchmark::State& state) {
  const int scene = int(state.range(0));
  const uint64_t photons = FinalPhotons(scene);
  for (auto _ : state) {
    const pb::BakeResult r = pb::BakeMesh(Options(scene, photons), pb::Log(true));
    state.counters["photons"] = double(photons);
    benchmark::DoNotOptimize(r.mesh.irradiance.data());
  }
}
BENCHMARK(BM_OneBake)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
