// Photon-tracing throughput against the raw Embree ceiling on the same scene and thread count.
//   BM_RawEmbreeWalk: a diffuse random walk that only calls rtcIntersect1 (through RayScene) and picks cosine
//     directions: no storage, no flux, no roulette bookkeeping. This is the ray rate the tracer can approach.
//   BM_TracePhotons:  the real stage 1 (TracePhotons), storing every hit.
// Both report rays/s (Embree calls per wall second) and rays/cpu-s (per second of the process's CPU time, every
// thread's); their ratio is the tracer's efficiency (the target: >= 0.9 of CPU time).
//   BM_TraceEffects/forced:0|1: stage 1 with the effects the scene calls for (0) and with every effect forced on
//     (--effects all, 1), which runs the specular photon loop. On a diffuse scene both give identical hits, so
//     the time ratio is what planning the transport saves.
// Usage: bench_trace [scene.obj] [--benchmark_filter=...]; the default scene is data/box/box.obj.
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <ctime>
#include <optional>

#include "baker/0_prepare_scene.h"
#include "baker/1_trace_photons.h"
#include "baker/runtime/threads.h"
#include "estimators/emission.h"
#include "estimators/lambertian.h"

namespace {

std::string g_scenePath = PB_SOURCE_DIR "/data/box/box.obj";

struct Fixture : pb::PreparedScene {
  Fixture() : pb::PreparedScene(Prepare()) {}
  static pb::PreparedScene Prepare() {
    pb::StageClock clock;
    return pb::PrepareScene(pb::SceneSettings{g_scenePath}, clock);
  }
  static const Fixture& Get() {
    static const Fixture f;
    return f;
  }
};

constexpr uint64_t kPhotons = 1 << 20;

// This process's CPU time [s], every thread's: the measure of the tracer against the walk, which waiting
// for the last block on two threads does not count against either.
double ProcessCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
constexpr uint64_t kBlock = 4096;

// Photon i's light: the lights' shares of kPhotons as the tracer allocates them (N_l = n Phi_l / Phi), so that
// both walk the same mix of paths (picking the lights in turn had sent the walk's rays elsewhere than the
// tracer's: a box's camera light has 38% of the photons, not half).
struct LightOfPhoton {
  std::vector<uint64_t> ends;  // ends[l]: one past light l's last photon
  explicit LightOfPhoton(const Fixture& f) {
    uint64_t end = 0;
    for (uint64_t n : pb::AllocatePhotons(f.lights, kPhotons, f.plan.lightReaches)) ends.push_back(end += n);
  }
  size_t operator()(uint64_t i) const {
    return std::min(size_t(std::upper_bound(ends.begin(), ends.end(), i) - ends.begin()), ends.size() - 1);
  }
};

// The same walk as the tracer (emit, bounce with roulette on Kd), but nothing is stored or tallied.
uint64_t RawWalk(const Fixture& f, const LightOfPhoton& lightOf, uint64_t first, uint64_t count) {
  uint64_t rays = 0;
  for (uint64_t i = first; i < first + count; ++i) {
    pb::Rng rng(7, i);
    const pb::EmissionSample e = pb::SampleEmission(f.scene, f.lights[lightOf(i)], rng);
    pb::Point3 origin = f.rays->SpawnPoint(e.position, e.normal);
    pb::Vector3 direction = e.direction;
    for (;;) {
      ++rays;
      const auto hit = f.rays->Intersect(origin, direction);
      if (!hit) break;
      const pb::Normal3 n = f.scene.FrontNormal(hit->triangle);
      const pb::Normal3 side = pb::Dot(direction, n) < 0 ? n : -n;
      if (rng.Uniform() >= f.scene.MaterialOf(hit->triangle).albedo.Max()) break;
      direction = pb::SampleLambertian({1, 1, 1}, side, rng.Uniform2()).wi;
      origin = f.rays->SpawnPoint(f.scene.PointAt(hit->triangle, hit->b1, hit->b2), side);
    }
  }
  return rays;
}

void BM_RawEmbreeWalk(benchmark::State& state) {
  const Fixture& f = Fixture::Get();
  const pb::ThreadScope threads(unsigned(state.range(0)));
  const LightOfPhoton lightOf(f);
  uint64_t rays = 0;
  const double cpu = ProcessCpuSeconds();
  for (auto _ : state) {
    std::atomic<uint64_t> total{0};
    tbb::parallel_for(tbb::blocked_range<uint64_t>(0, kPhotons / kBlock, 1), [&](const auto& r) {
      for (uint64_t b = r.begin(); b != r.end(); ++b) total += RawWalk(f, lightOf, b * kBlock, kBlock);
    });
    rays += total;
  }
  state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
  state.counters["rays/cpu-s"] = double(rays) / (ProcessCpuSeconds() - cpu);
}

void BM_TracePhotons(benchmark::State& state) {
  const Fixture& f = Fixture::Get();
  const pb::ThreadScope threads(unsigned(state.range(0)));
  const pb::Log quiet(true);
  uint64_t rays = 0, photons = 0;
  const double cpu = ProcessCpuSeconds();
  for (auto _ : state) {
    const pb::PhotonStore hits = pb::TracePhotons(f, {kPhotons, 7}, quiet);
    rays += hits.stats.hits + hits.stats.escaped;
    photons += hits.stats.emitted;
  }
  state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
  state.counters["rays/cpu-s"] = double(rays) / (ProcessCpuSeconds() - cpu);
  state.counters["photons/s"] = benchmark::Counter(double(photons), benchmark::Counter::kIsRate);
  state.counters["bytes/hit"] = double(sizeof(pb::PhotonHit));
}

void BM_TraceEffects(benchmark::State& state) {
  const Fixture& f = Fixture::Get();
  const pb::ThreadScope threads(2);
  const pb::TransportPlan plan =
      pb::PlanTransport(f.scene, f.surfaces, f.lights, pb::ParseEffectOverrides(state.range(0) ? "all" : "auto"));
  const pb::Log quiet(true);
  uint64_t photons = 0;
  for (auto _ : state) photons += pb::TracePhotons(f.scene, f.lights, *f.rays, plan, {kPhotons, 7}, quiet).stats.emitted;
  state.counters["photons/s"] = benchmark::Counter(double(photons), benchmark::Counter::kIsRate);
}

BENCHMARK(BM_RawEmbreeWalk)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_TracePhotons)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_TraceEffects)->ArgName("forced")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (argc > 1) g_scenePath = argv[1];
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
