// Direct light sampled at points under many lights (estimators/light_sampler.h): the light tree against the exact
// guess over every light, on an LED ceiling (tests/test_scenes.h's WriteLampGrid: side^2 lamps of 2 cm at a pitch
// of 4 cm, 2.5 m over a floor, powers over three decades).
//   BM_DirectLight/lamps:N/tree:T: 64 shadow rays at each of 256 floor points per iteration, one thread, with the
//     tree (T = 1) or the exact per-point guess, which costs O(lights x their triangles) per point (T = 0).
//     Reports points/s.
// Usage: bench_direct [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>

#include "baker/0_prepare_scene.h"
#include "estimators/light_sampler.h"
#include "tests/test_scenes.h"

namespace {

const pb::PreparedScene& Ceiling(int side) {
  static std::map<int, std::unique_ptr<pb::PreparedScene>> scenes;
  auto& scene = scenes[side];
  if (!scene) {
    const std::string dir = pb::test::TempDirectory("bench-direct-" + std::to_string(side));
    const float pitch = 0.04f, floorSide = side * pitch + 2;
    pb::StageClock clock;
    scene = std::make_unique<pb::PreparedScene>(pb::PrepareScene(
        pb::SceneSettings{pb::test::WriteLampGrid(dir, side, pitch, 0.02f, 2.5f, floorSide)}, clock));
  }
  return *scene;
}

void BM_DirectLight(benchmark::State& state) {
  const auto side = int(std::lround(std::sqrt(double(state.range(0)))));
  const pb::PreparedScene& scene = Ceiling(side);
  const pb::LightSampler sampler(scene.scene, scene.lights, *scene.rays, state.range(1) ? 1 : SIZE_MAX);
  const float extent = side * 0.04f / 2;
  uint64_t points = 0;
  double sum = 0;
  for (auto _ : state) {
    for (int k = 0; k < 256; ++k, ++points) {
      pb::Rng rng(3, points);
      const pb::Point2 u = rng.Uniform2();
      const pb::Point3 p{(2 * u.u - 1) * extent, 0, (2 * u.v - 1) * extent};
      sum += sampler.Irradiance(p, {0, 1, 0}, 64, rng).irradiance.g;
    }
  }
  benchmark::DoNotOptimize(sum);
  state.counters["points/s"] = benchmark::Counter(double(points), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DirectLight)
    ->ArgNames({"lamps", "tree"})
    ->ArgsProduct({{16, 1024, 10000}, {0, 1}})
    ->Args({100000, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
