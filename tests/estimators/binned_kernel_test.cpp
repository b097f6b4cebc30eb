// The kernel estimator's binned sums (estimators/kernel_estimator.h) against its exact sums over the photons:
// 8M photons on a 1 x 1 m surface whose density rises linearly across it (so the local linear fit at the edges
// has a gradient to remove), h = 0.05 m, local linear correction on. At 441 points on a grid that includes the
// edges and corners, the binned estimate is within 0.5% of the exact one for every kernel with a continuous
// profile (the uniform and the truncated Gaussian kernels, which step at their rim, are not binned: their sums
// stay exact), and the predicted noise within 5%. The difference comes from replacing each photon's kernel weight by its bilinear interpolation from
// nodes h / 8 apart: deterministic for given photons, but at the edges, where the linear fit's weights swing
// widely, it behaves like noise (each photon's interpolation error differs) and falls as photons grow. Measured:
// worst 0.19-0.27% over the kernels at 8M photons, 0.26-0.50% at 2M; in the interior about 0.1%.
#include <gtest/gtest.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "estimators/kernel_estimator.h"
#include "estimators/rng.h"
#include "estimators/surface_region.h"

namespace pb {
namespace {

constexpr uint64_t kPhotons = 8'000'000;

struct SlopedSquare {
  std::vector<Triangle2> triangles = {{Point2{0, 0}, Point2{1, 0}, Point2{1, 1}}, {Point2{0, 0}, Point2{1, 1}, Point2{0, 1}}};
  std::vector<Point2> uv;
  std::vector<Rgb> flux;
  explicit SlopedSquare(uint64_t photons = kPhotons) {
    // Density 2/3 (1 + u): u by inverting its CDF (u + u^2 / 2) / 1.5.
    for (uint64_t i = 0; i < photons; ++i) {
      Rng rng(5, i);
      const Point2 r = rng.Uniform2();
      uv.push_back({float(std::sqrt(1 + 3 * double(r.u)) - 1), r.v});
    }
    flux.assign(photons, Rgb{1e-6f, 2e-6f, 0.5e-6f});
  }
};

TEST(BinnedKernel, MatchesTheExactSumWithin0_5Percent) {
  const SlopedSquare s;
  const SurfaceRegion region(s.triangles);
  for (const Kernel kernel : {Kernel::kUniform, Kernel::kGaussian}) {
    const KernelEstimator stepAtRim(s.uv, s.flux, 0.05f, kernel, &region, true, KernelEstimator::Binning::kAuto);
    EXPECT_FALSE(stepAtRim.Binned()) << KernelName(kernel);
  }
  for (const Kernel kernel : {Kernel::kEpanechnikov, Kernel::kBiweight, Kernel::kTriweight, Kernel::kCone}) {
    const KernelEstimator exact(s.uv, s.flux, 0.05f, kernel, &region, true, KernelEstimator::Binning::kExact);
    const KernelEstimator binned(s.uv, s.flux, 0.05f, kernel, &region, true, KernelEstimator::Binning::kAuto);
    ASSERT_FALSE(exact.Binned());
    ASSERT_TRUE(binned.Binned()) << "2M photons on 1 m^2 are dense enough to bin at h = 0.05 m";
    double worst = 0, worstNoise = 0;
    for (int j = 0; j <= 20; ++j)
      for (int i = 0; i <= 20; ++i) {
        const Point2 x{i / 20.0f, j / 20.0f};
        const auto a = exact.EstimateWithNoise(x), b = binned.EstimateWithNoise(x);
        worst = std::max(worst, std::fabs(double(b.irradiance.g) / a.irradiance.g - 1));
        worstNoise = std::max(worstNoise, std::fabs(b.relativeNoise / a.relativeNoise - 1));
      }
    std::printf("%s: binned within %.3f%% of the exact sum, noise within %.2f%%\n", KernelName(kernel).c_str(), 100 * worst,
                100 * worstNoise);
    EXPECT_LT(worst, 0.005) << KernelName(kernel);
    EXPECT_LT(worstNoise, 0.05) << KernelName(kernel);
  }
}

// A kernel wider than half the surface (h = 0.8 m on the 1 m square, as h chosen from few photons comes out on a
// room's floor) is binned too, on the lattice of a quarter of the surface's width (nodes 3 cm apart), where it had
// summed every photon at every point; from 200,000 photons, within 0.3% of the exact sum at the same 441 points,
// edges and corners included (measured 0.14%; 0.51% on the lattice of half the width, the error second order in
// the spacing and largest along the edges, where the local linear fit's weights swing). A bake binning while
// tracing (kWide) keeps the lattice of h, so such a surface is not binned there.
TEST(BinnedKernel, AKernelWiderThanHalfTheSurfaceIsBinnedOnAFinerLattice) {
  const SlopedSquare s(200'000);
  const SurfaceRegion region(s.triangles);
  const KernelEstimator exact(s.uv, s.flux, 0.8f, Kernel::kEpanechnikov, &region, true, KernelEstimator::Binning::kExact);
  const KernelEstimator binned(s.uv, s.flux, 0.8f, Kernel::kEpanechnikov, &region, true, KernelEstimator::Binning::kAuto);
  const KernelEstimator wide(s.uv, s.flux, 0.8f, Kernel::kEpanechnikov, &region, true, KernelEstimator::Binning::kWide);
  ASSERT_TRUE(binned.Binned());
  EXPECT_FALSE(wide.Binned());
  double worst = 0;
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) {
      const Point2 x{i / 20.0f, j / 20.0f};
      worst = std::max(worst, std::fabs(double(binned.Estimate(x).g) / exact.Estimate(x).g - 1));
    }
  std::printf("h = 0.8 m on a 1 m square: binned within %.4f%% of the exact sum\n", 100 * worst);
  EXPECT_LT(worst, 0.003);
}

// Photons binned one by one in store order, and the same photons binned in reverse by several threads at once (as a
// bake that bins while tracing does), hold the same bytes; both within a part in 10^7 of double-precision sums of
// the bilinear shares (the fixed point rounds each share to 1.5e-8 of the flux unit).
TEST(BinnedPhotons, SumsAreExactWhateverTheOrderAndThreads) {
  constexpr size_t kCount = 200'000;
  std::vector<Point2> uv(kCount);
  std::vector<Rgb> flux(kCount);
  for (size_t i = 0; i < kCount; ++i) {
    Rng rng(9, i);
    uv[i] = rng.Uniform2();
    flux[i] = Rgb{rng.Uniform(), rng.Uniform(), rng.Uniform()} * 1e-5f;
  }
  Bounds2 square;
  square.Extend({0, 0}), square.Extend({1, 1});
  const NodeLattice lattice = NodeLattice::Over(square, 0.05f, KernelEstimator::kNodesPerH);
  const double unit = 1e-5;
  BinnedPhotons inOrder(lattice, unit), shuffled(lattice, unit);  // "shuffled": reversed, then split among threads
  std::vector<std::array<double, 4>> exact(lattice.Count(), std::array<double, 4>{});
  for (size_t i = 0; i < kCount; ++i) {
    inOrder.Add(uv[i], flux[i]);
    const double y = Luminance(flux[i]);
    lattice.ShareAt(uv[i], [&](size_t n, double w) {
      exact[n][0] += w * flux[i].r, exact[n][1] += w * flux[i].g, exact[n][2] += w * flux[i].b, exact[n][3] += w * y * y;
    });
  }
  std::vector<size_t> order(kCount);
  std::iota(order.begin(), order.end(), size_t(0));
  std::reverse(order.begin(), order.end());
  tbb::parallel_for(size_t(0), kCount, [&](size_t i) { shuffled.Add(uv[order[i]], flux[order[i]]); });
  EXPECT_EQ(inOrder.Photons(), kCount);
  EXPECT_EQ(shuffled.Photons(), kCount);
  double worst = 0;
  for (size_t n = 0; n < lattice.Count(); ++n) {
    ASSERT_EQ(inOrder.Flux(n), shuffled.Flux(n)) << "node " << n;
    ASSERT_EQ(inOrder.Squares(n), shuffled.Squares(n)) << "node " << n;
    if (exact[n][0] > 0) worst = std::max(worst, std::fabs(inOrder.Flux(n).r / exact[n][0] - 1));
  }
  EXPECT_LT(worst, 1e-6);
}

// An estimator built from photons binned as they were traced answers like one built from the same photons listed
// with Binning::kWide, bit for bit, at the edges and inside.
TEST(BinnedPhotons, GiveTheSameEstimatorAsTheListedPhotons) {
  const SlopedSquare s;
  const SurfaceRegion region(s.triangles);
  const size_t count = 100'000;  // sparse: kAuto would not bin them, kWide does
  const std::span<const Point2> uv(s.uv.data(), count);
  const std::span<const Rgb> flux(s.flux.data(), count);
  const std::optional<NodeLattice> lattice = KernelEstimator::WideLattice(Kernel::kEpanechnikov, region, 0.05f);
  ASSERT_TRUE(lattice.has_value());
  BinnedPhotons traced(*lattice, 2e-6);
  tbb::parallel_for(size_t(0), count, [&](size_t i) { traced.Add(uv[i], flux[i]); });
  const KernelEstimator listed(uv, flux, 0.05f, Kernel::kEpanechnikov, &region, true, KernelEstimator::Binning::kWide, 2e-6);
  const KernelEstimator streamed(traced, 0.05f, Kernel::kEpanechnikov, region, true);
  ASSERT_TRUE(listed.Binned());
  ASSERT_TRUE(streamed.Binned());
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) {
      const Point2 x{i / 20.0f, j / 20.0f};
      const auto a = listed.EstimateWithNoise(x), b = streamed.EstimateWithNoise(x);
      ASSERT_EQ(a.irradiance, b.irradiance) << x.u << ", " << x.v;
      ASSERT_EQ(a.relativeNoise, b.relativeNoise);
      ASSERT_GT(a.irradiance.g, 0.0f);
    }
  EXPECT_FALSE(KernelEstimator::WideLattice(Kernel::kUniform, region, 0.05f)) << "steps at its rim";
  EXPECT_FALSE(KernelEstimator::WideLattice(Kernel::kEpanechnikov, region, 0.6f)) << "narrower than 2 h";
}

}  // namespace
}  // namespace pb
