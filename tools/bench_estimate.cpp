// bench_estimate: cost of each density estimator, per photon (building) and per vertex (querying), on a
// 1 x 1 m surface holding 1M or 10M uniformly spread photons, with 10^4 query vertices on a grid that
// includes the edges. Settings are the defaults (h = 0.05 m, k = 50), edge correction on.
// BM_KernelQuery/photons:N/binned:B: the kernel estimator's query with exact (B = 0) and binned sums (B = 1), up
// to 10^8 photons on the square.
// BM_KernelMass: the edge correction's boundary mass M(x) alone, at 1,000 points h/2 inside the boundary of a
// disc of radius 0.5 m cut as a fan of N triangles (N boundary edges), h = 0.05 m.
// BM_MomentsOnAGriddedFace: the local linear fit's kernel moments alone, at 1,000 points h/2 inside the sides of a
// 4 x 4 m square cut into N x N cells (4 N boundary edges before straight runs are joined), h = 0.6 m.
// Run: build/bench_estimate --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cmath>

#include "estimators/density_estimator.h"
#include "estimators/kernel_estimator.h"
#include "estimators/rng.h"

namespace {

struct Photons {
  std::vector<pb::Triangle2> square = {{pb::Point2{0, 0}, pb::Point2{1, 0}, pb::Point2{1, 1}},
                                       {pb::Point2{0, 0}, pb::Point2{1, 1}, pb::Point2{0, 1}}};
  std::vector<pb::Point2> uv;
  std::vector<pb::Rgb> power;
  explicit Photons(size_t n) : uv(n), power(n, pb::Rgb{1e-6f, 1e-6f, 1e-6f}) {
    for (size_t i = 0; i < n; ++i) {
      pb::Rng rng(1, i);
      uv[i] = rng.Uniform2();
    }
  }
};

const Photons& PhotonsOf(size_t n) {
  static const Photons million(1'000'000), tenMillion(10'000'000);
  if (n == 1'000'000) return million;
  if (n == 10'000'000) return tenMillion;
  static const Photons hundredMillion(100'000'000);  // 2 GB: built only when asked for
  return hundredMillion;
}

void BM_Build(benchmark::State& state, pb::EstimatorKind kind) {
  const Photons& p = PhotonsOf(size_t(state.range(0)));
  const pb::SurfaceRegion region(p.square);
  for (auto _ : state) benchmark::DoNotOptimize(pb::MakeDensityEstimator({kind}, region, p.uv, p.power));
  state.counters["ns_per_photon"] = benchmark::Counter(double(p.uv.size()), benchmark::Counter::kIsIterationInvariantRate |
                                                                                 benchmark::Counter::kInvert);
}

void BM_Query(benchmark::State& state, pb::EstimatorKind kind) {
  const Photons& p = PhotonsOf(size_t(state.range(0)));
  const pb::SurfaceRegion region(p.square);
  const auto estimator = pb::MakeDensityEstimator({kind}, region, p.uv, p.power);
  constexpr int kGrid = 100;
  for (auto _ : state)
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i)
        benchmark::DoNotOptimize(estimator->Estimate({float(i) / (kGrid - 1), float(j) / (kGrid - 1)}));
  state.counters["ns_per_vertex"] =
      benchmark::Counter(double(kGrid * kGrid), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// The kernel estimator's sums over the photons (binned 0) or over the binned nodes (1), at 32 x 32 points that
// include the edges and corners, local linear correction on.
void BM_KernelQuery(benchmark::State& state) {
  const Photons& p = PhotonsOf(size_t(state.range(0)));
  const pb::SurfaceRegion region(p.square);
  const pb::KernelEstimator estimator(p.uv, p.power, 0.05f, pb::Kernel::kEpanechnikov, &region, true,
                                      state.range(1) ? pb::KernelEstimator::Binning::kBinned
                                                     : pb::KernelEstimator::Binning::kExact);
  constexpr int kGrid = 32;
  for (auto _ : state)
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i)
        benchmark::DoNotOptimize(estimator.Estimate({float(i) / (kGrid - 1), float(j) / (kGrid - 1)}));
  state.counters["ns_per_vertex"] =
      benchmark::Counter(double(kGrid * kGrid), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// The regular N-gon of radius 0.5 m about (0.5, 0.5), as a fan of N triangles.
std::vector<pb::Triangle2> Disc(int corners) {
  const auto corner = [&](int i) {
    const double a = 2 * M_PI * (i % corners) / corners;
    return pb::Point2{float(0.5 + 0.5 * std::cos(a)), float(0.5 + 0.5 * std::sin(a))};
  };
  std::vector<pb::Triangle2> fan;
  for (int i = 0; i < corners; ++i) fan.push_back({pb::Point2{0.5f, 0.5f}, corner(i), corner(i + 1)});
  return fan;
}

void BM_KernelMass(benchmark::State& state) {
  const pb::SurfaceRegion region(Disc(int(state.range(0))));
  constexpr int kPoints = 1000;
  constexpr double kH = 0.05;
  for (auto _ : state)
    for (int i = 0; i < kPoints; ++i) {
      const double a = 2 * M_PI * (i + 0.5) / kPoints, r = 0.5 - kH / 2;
      const pb::Point2 x{float(0.5 + r * std::cos(a)), float(0.5 + r * std::sin(a))};
      benchmark::DoNotOptimize(region.KernelMass(x, pb::Kernel::kEpanechnikov, kH));
    }
  state.counters["ns_per_point"] =
      benchmark::Counter(double(kPoints), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

std::vector<pb::Triangle2> GriddedSquare(float side, int cells) {
  std::vector<pb::Triangle2> t;
  const float step = side / float(cells);
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const pb::Point2 a{i * step, j * step}, b{(i + 1) * step, j * step}, c{(i + 1) * step, (j + 1) * step},
          d{i * step, (j + 1) * step};
      t.push_back({a, b, c});
      t.push_back({a, c, d});
    }
  return t;
}

void BM_MomentsOnAGriddedFace(benchmark::State& state) {
  const pb::SurfaceRegion region(GriddedSquare(4, int(state.range(0))));
  constexpr int kPoints = 1000;
  constexpr double kH = 0.6;
  for (auto _ : state)
    for (int i = 0; i < kPoints; ++i) {  // along the side v = h/2, then along u = h/2
      const float along = float(4.0 * (i / 2 + 0.5) / (kPoints / 2)), in = float(kH / 2);
      const pb::Point2 x = i % 2 == 0 ? pb::Point2{along, in} : pb::Point2{in, along};
      benchmark::DoNotOptimize(region.Moments(x, pb::Kernel::kEpanechnikov, kH));
    }
  state.counters["ns_per_point"] =
      benchmark::Counter(double(kPoints), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK_CAPTURE(BM_Build, kernel, pb::EstimatorKind::kKernel)->Arg(1'000'000)->Arg(10'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Build, histogram, pb::EstimatorKind::kHistogram)->Arg(1'000'000)->Arg(10'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Build, knn, pb::EstimatorKind::kNearest)->Arg(1'000'000)->Arg(10'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query, kernel, pb::EstimatorKind::kKernel)->Arg(1'000'000)->Arg(10'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query, histogram, pb::EstimatorKind::kHistogram)->Arg(1'000'000)->Arg(10'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query, knn, pb::EstimatorKind::kNearest)->Arg(1'000'000)->Arg(10'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KernelQuery)
    ->ArgNames({"photons", "binned"})
    ->Args({1'000'000, 0})->Args({1'000'000, 1})->Args({10'000'000, 0})->Args({10'000'000, 1})->Args({100'000'000, 1})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_KernelMass)->Arg(64)->Arg(1000)->Arg(40000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MomentsOnAGriddedFace)->Arg(1)->Arg(40)->Arg(160)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
