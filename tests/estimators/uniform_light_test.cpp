// Uniform light: photons of equal flux spread uniformly over a square surface, so the true irradiance is the
// same everywhere, E = Phi / A. Every estimator, edge-corrected, must read the same at the surface's edge and
// corner vertices as in its interior: within 2%, at photon counts where the noise is far below that.
//
// Noise (relative standard deviation) at these settings, from the estimators' variance formulas:
//   kernel, h = 0.2 m, N = 4e6 photons on 1.21 m^2: sigma = sqrt(R(K) / (M n h^2)) with n = N / A and the
//     kernel's roughness R(K) <= 0.73 (triweight); M = 1/4 at a corner doubles it: <= 0.45%.
//   histogram, h = 0.2 m: the smallest (corner) bucket is 0.1 x 0.1 m, ~33000 photons: 0.55%.
//   knn, k = 40000: sigma = 1 / sqrt(k - 2) = 0.5% at every vertex.
// So 2% is at least 3.6 sigma at every vertex checked. Without edge correction the edges read ~1/2 and the
// corners ~1/4 of the interior, which the last test shows: these checks can fail.
#include <gtest/gtest.h>

#include <cmath>

#include "estimators/bandwidth.h"
#include "estimators/density_estimator.h"
#include "estimators/rng.h"

namespace pb {
namespace {

constexpr float kSide = 1.1f;  // not a multiple of the bucket side: edge buckets are partial
constexpr int kCells = 5;
constexpr uint64_t kPhotons = 4'000'000;
constexpr double kFlux = 2.0;  // W over the square, so E = 2 / 1.21 W/m^2

struct UniformSquare {
  std::vector<Triangle2> triangles;
  std::vector<Point2> uv;
  std::vector<Rgb> power;
  UniformSquare() {
    const float step = kSide / kCells;
    for (int j = 0; j < kCells; ++j)
      for (int i = 0; i < kCells; ++i) {
        const Point2 a{i * step, j * step}, b{(i + 1) * step, j * step}, c{(i + 1) * step, (j + 1) * step},
            d{i * step, (j + 1) * step};
        triangles.push_back({a, b, c});
        triangles.push_back({a, c, d});
      }
    uv.reserve(kPhotons);
    for (uint64_t i = 0; i < kPhotons; ++i) {
      Rng rng(11, i);
      const float u = rng.Uniform() * kSide, v = rng.Uniform() * kSide;
      uv.push_back({u, v});
    }
    const float phi = float(kFlux / kPhotons);
    power.assign(kPhotons, Rgb{phi, phi, phi});
  }
};

const UniformSquare& Square() {
  static const UniformSquare square;
  return square;
}

enum class Place { kInterior, kEdge, kCorner };
Place PlaceOf(int i, int j) {
  const bool edgeI = i == 0 || i == kCells, edgeJ = j == 0 || j == kCells;
  return edgeI && edgeJ ? Place::kCorner : (edgeI || edgeJ) ? Place::kEdge : Place::kInterior;
}

struct Readings {
  double interiorMean = 0;
  double worstEdge = 0, worstCorner = 0;  // largest |H / interior mean - 1|
  double meanEdge = 0, meanCorner = 0;    // mean of H / interior mean
};

Readings Read(const EstimatorSettings& settings) {
  const UniformSquare& sq = Square();
  const SurfaceRegion region(sq.triangles);
  const auto estimator = MakeDensityEstimator(settings, region, sq.uv, sq.power);
  std::vector<std::pair<Place, double>> values;
  double interiorSum = 0;
  int interiorCount = 0;
  const float step = kSide / kCells;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) {
      const double h = estimator->Estimate({i * step, j * step}).g;
      values.push_back({PlaceOf(i, j), h});
      if (PlaceOf(i, j) == Place::kInterior) interiorSum += h, ++interiorCount;
    }
  Readings r;
  r.interiorMean = interiorSum / interiorCount;
  int edges = 0, corners = 0;
  for (const auto& [place, h] : values) {
    const double ratio = h / r.interiorMean;
    if (place == Place::kEdge) r.worstEdge = std::max(r.worstEdge, std::fabs(ratio - 1)), r.meanEdge += ratio, ++edges;
    if (place == Place::kCorner) r.worstCorner = std::max(r.worstCorner, std::fabs(ratio - 1)), r.meanCorner += ratio, ++corners;
  }
  r.meanEdge /= edges;
  r.meanCorner /= corners;
  return r;
}

struct Case {
  EstimatorKind kind;
  Kernel kernel;
  float h;
  uint32_t k;
};

class UniformLight : public testing::TestWithParam<Case> {};

TEST_P(UniformLight, EdgesAndCornersReadLikeTheInterior) {
  const Case c = GetParam();
  const Readings r = Read({c.kind, c.kernel, c.h, c.k, true});
  const double exact = kFlux / (double(kSide) * kSide);
  EXPECT_NEAR(r.interiorMean / exact, 1.0, 0.01);
  EXPECT_LT(r.worstEdge, 0.02) << "mean edge ratio " << r.meanEdge;
  EXPECT_LT(r.worstCorner, 0.02) << "mean corner ratio " << r.meanCorner;
}

std::vector<Case> AllCases() {
  std::vector<Case> cases;
  for (Kernel k : kAllKernels) cases.push_back({EstimatorKind::kKernel, k, 0.2f, 0});
  cases.push_back({EstimatorKind::kHistogram, Kernel::kEpanechnikov, 0.2f, 0});
  cases.push_back({EstimatorKind::kNearest, Kernel::kEpanechnikov, 0.2f, 40000});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(EveryEstimator, UniformLight, testing::ValuesIn(AllCases()),
                         [](const testing::TestParamInfo<Case>& info) {
                           std::string name = EstimatorName(info.param.kind);
                           if (info.param.kind == EstimatorKind::kKernel) name.append("_").append(KernelName(info.param.kernel));
                           return name;
                         });

TEST(UniformLight, WithoutEdgeCorrectionEdgesDarkenToAHalfAndCornersToAQuarter) {
  const Readings r = Read({EstimatorKind::kKernel, Kernel::kEpanechnikov, 0.2f, 0, false});
  EXPECT_NEAR(r.meanEdge, 0.5, 0.02);
  EXPECT_NEAR(r.meanCorner, 0.25, 0.02);
}

// A surface with too few photons for the automatic h's pilot (under 3,600): h holds 1,000 photons on average, up to
// the surface's size (estimators/bandwidth.h). A 0.2 m square of uniform light with 2,000 photons: h =
// sqrt(1000 A / (pi N)) = 0.0798 m, and the estimate's relative noise sqrt(R(K) / (n h^2)) = 3.6% in the interior
// (Epanechnikov, R = 4 / (3 pi); n h^2 = 318); at the edges the local linear fit raises it. Over a 9 x 9 grid of
// points the RMS reads 4.1% inside the border (below 6%) and 9.2% with the border (below 15%); when h held 50
// photons (0.018 m) it read 16% and 38%. With 300 photons the rule asks for 0.206 m, and the square's own size,
// 0.2 m, caps it.
TEST(UniformLight, ASurfaceTooSparseForAPilotReadsWithinTheNoiseOfAThousandPhotons) {
  constexpr float kSmall = 0.2f;
  const Point2 a{0, 0}, b{kSmall, 0}, c{kSmall, kSmall}, d{0, kSmall};
  const std::vector<Triangle2> square = {{a, b, c}, {a, c, d}};
  const SurfaceRegion region(square);
  const auto photons = [&](uint64_t n, std::vector<Point2>& uv, std::vector<Rgb>& power) {
    for (uint64_t i = 0; i < n; ++i) {
      Rng rng(23, i);
      uv.push_back({rng.Uniform() * kSmall, rng.Uniform() * kSmall});
    }
    power.assign(n, Rgb{float(kFlux / n), float(kFlux / n), float(kFlux / n)});
  };
  std::vector<Point2> uv, fewUv;
  std::vector<Rgb> power, fewPower;
  photons(2000, uv, power), photons(300, fewUv, fewPower);
  const float h = ChooseBandwidth(EstimatorKind::kKernel, Kernel::kEpanechnikov, PilotHistogram::Of(region, uv, power, kFlux));
  EXPECT_NEAR(h, std::sqrt(1000 * kSmall * kSmall / (M_PI * 2000)), 1e-4);
  EXPECT_NEAR(ChooseBandwidth(EstimatorKind::kKernel, Kernel::kEpanechnikov, PilotHistogram::Of(region, fewUv, fewPower, kFlux)),
              kSmall, 1e-4);
  const auto estimator = MakeDensityEstimator({EstimatorKind::kKernel, Kernel::kEpanechnikov, h, 0, true}, region, uv, power);
  const double exact = kFlux / (kSmall * kSmall);
  double all = 0, interior = 0;
  for (int j = 0; j <= 8; ++j)
    for (int i = 0; i <= 8; ++i) {
      const double error = estimator->Estimate({kSmall * i / 8, kSmall * j / 8}).g / exact - 1;
      all += error * error;
      if (i > 0 && i < 8 && j > 0 && j < 8) interior += error * error;
    }
  const double rmsAll = std::sqrt(all / 81), rmsInterior = std::sqrt(interior / 49);
  std::printf("h = %.4f m: relative RMS error %.4f over the grid, %.4f inside its border\n", h, rmsAll, rmsInterior);
  EXPECT_LT(rmsInterior, 0.06);
  EXPECT_LT(rmsAll, 0.15);
}

// A surface on which no stencil of the automatic h's pilot fits, at any level (a strip 8 x 0.6 m: the pilot's cells
// are square, 1 m at 50,000 photons, so none lies wholly on it; a wall that a gallery's floor cuts across is the
// same): h is the pilot's finest cell, no wider than the scale it looked at, where it was once the surface's own size
// (2.2 m here), which spread the atrium's walls' light over 9.7 m (docs/real-assets.md). Under light that curves
// along the strip, H = 2.5 - 1.5 cos(pi x / 4) (1 to 4 W/m^2), the peak at x = 4 m reads within 5% (bias at h = 1
// m about -2%, noise about 1%); at 2.2 m it reads 9.6% low.
TEST(UniformLight, ASurfaceNoPilotStencilFitsTakesThePilotsCell) {
  constexpr float kLength = 8, kWidth = 0.6f;
  const Point2 a{0, 0}, b{kLength, 0}, c{kLength, kWidth}, d{0, kWidth};
  const SurfaceRegion region(std::vector<Triangle2>{{a, b, c}, {a, c, d}});
  const auto H = [](double x) { return 2.5 - 1.5 * std::cos(M_PI * x / 4); };
  double integral = 0;  // of H over the strip [W]
  for (int k = 0; k < 8000; ++k) integral += H((k + 0.5) * kLength / 8000) * kLength / 8000 * kWidth;
  constexpr uint64_t kPhotons = 50'000;
  std::vector<Point2> uv;
  for (uint64_t i = 0; uv.size() < kPhotons; ++i) {  // rejection: x by H, y uniform
    Rng rng(31, i);
    const float x = rng.Uniform() * kLength, y = rng.Uniform() * kWidth;
    if (rng.Uniform() * 4 < H(x)) uv.push_back({x, y});
  }
  const float share = float(integral / kPhotons);
  const std::vector<Rgb> power(kPhotons, Rgb{share, share, share});
  const float h = ChooseBandwidth(EstimatorKind::kKernel, Kernel::kEpanechnikov, PilotHistogram::Of(region, uv, power, share));
  EXPECT_NEAR(h, 1.0f, 1e-4f) << "the pilot's finest cell: 8 m over 8 cells";
  const auto estimator = MakeDensityEstimator({EstimatorKind::kKernel, Kernel::kEpanechnikov, h, 0, true}, region, uv, power);
  const double peak = estimator->Estimate({4, kWidth / 2}).g / H(4) - 1;
  std::printf("h = %.3f m: the peak reads %+.4f\n", h, peak);
  EXPECT_LT(std::fabs(peak), 0.05);
}

}  // namespace
}  // namespace pb
