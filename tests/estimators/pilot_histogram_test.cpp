// The automatic h's pilot histogram (estimators/pilot_histogram.h): its sums are exact and order-free, so that the
// processes of a distributed bake, each adding its own photons and summing the integers, hold one process's pilot
// and choose its h; and they are the photons' flux and squared flux to the rounding of one step a photon.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "estimators/bandwidth.h"
#include "estimators/pilot_histogram.h"
#include "estimators/rng.h"

namespace pb {
namespace {

// A 3 x 2 m rectangle lit more towards +u, with 60,000 photons of flux 1e-3 W scaled by 0.2-1 (several bounces'
// albedos), so that the pilot has 8 x 8 cells and both its sums vary.
std::vector<Triangle2> Rectangle() {
  const Point2 a{0, 0}, b{3, 0}, c{3, 2}, d{0, 2};
  return {{a, b, c}, {a, c, d}};
}
struct Lit {
  SurfaceRegion region{Rectangle()};
  std::vector<Point2> uv;
  std::vector<Rgb> flux;
  Lit() {
    for (uint64_t i = 0; uv.size() < 60'000; ++i) {
      Rng rng(41, i);
      const float u = 3 * rng.Uniform(), v = 2 * rng.Uniform();
      if (3 * rng.Uniform() > 1 + u) continue;
      const float a = 0.2f + 0.8f * rng.Uniform();
      uv.push_back({u, v}), flux.push_back(Rgb{1e-3f * a, 0.8e-3f * a, 0.6e-3f * a});
    }
  }
};

TEST(PilotHistogram, ThreeProcessesSummingTheirOwnPhotonsHoldThePilotOfOne) {
  const Lit lit;
  constexpr double kUnit = 1e-3;
  const PilotHistogram whole = PilotHistogram::Of(lit.region, lit.uv, lit.flux, kUnit);
  ASSERT_EQ(whole.CellsPerAxis(), 8);
  // Each "process" adds every third photon, in its own order; the integers are then summed into the first.
  std::vector<PilotHistogram> parts(3, PilotHistogram(lit.region, lit.uv.size(), kUnit));
  for (size_t r = 0; r < 3; ++r)
    for (size_t k = lit.uv.size(); k-- > 0;)
      if (k % 3 == r) parts[r].Add(lit.uv[k], lit.flux[k]);
  for (size_t r = 1; r < 3; ++r) {
    std::span<int64_t> into = parts[0].Units();
    const std::span<int64_t> from = parts[r].Units();
    for (size_t i = 0; i < into.size(); ++i) into[i] += from[i];
  }
  const std::span<const int64_t> a = std::as_const(parts[0]).Units(), b = whole.Units();
  EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end()));
  for (Kernel kernel : {Kernel::kEpanechnikov, Kernel::kBiweight})
    EXPECT_EQ(ChooseBandwidth(EstimatorKind::kKernel, kernel, parts[0]), ChooseBandwidth(EstimatorKind::kKernel, kernel, whole));
  EXPECT_EQ(PredictedBias(EstimatorKind::kKernel, Kernel::kEpanechnikov, parts[0], 0.3f),
            PredictedBias(EstimatorKind::kKernel, Kernel::kEpanechnikov, whole, 0.3f));
}

TEST(PilotHistogram, HoldsTheFluxAndItsSquaresToARoundingAPhoton) {
  const Lit lit;
  const PilotHistogram pilot = PilotHistogram::Of(lit.region, lit.uv, lit.flux, 1e-3);
  const int n = pilot.CellsPerAxis();
  std::vector<double> flux(size_t(n) * n, 0), squares(size_t(n) * n, 0);
  std::vector<int> photons(size_t(n) * n, 0);
  for (size_t k = 0; k < lit.uv.size(); ++k) {
    const int i = std::min(int(lit.uv[k].u / pilot.Side()), n - 1), j = std::min(int(lit.uv[k].v / pilot.Side()), n - 1);
    const double phi = Luminance(lit.flux[k]);
    flux[size_t(j) * n + i] += phi, squares[size_t(j) * n + i] += phi * phi, ++photons[size_t(j) * n + i];
  }
  double total = 0;
  for (size_t c = 0; c < flux.size(); ++c) {
    // Half a step a photon at most: 2^-27 of the unit for the flux, 2^-41 of its square for the squares.
    EXPECT_NEAR(pilot.Flux(c), flux[c], photons[c] * 1e-3 / 134217728.0 + 1e-18) << "cell " << c;
    EXPECT_NEAR(pilot.Squares(c), squares[c], photons[c] * 1e-6 / 2199023255552.0 + 1e-24) << "cell " << c;
    total += pilot.Flux(c);
  }
  EXPECT_GT(total, 0);
  EXPECT_EQ(pilot.Photons(), lit.uv.size());
}

}  // namespace
}  // namespace pb
