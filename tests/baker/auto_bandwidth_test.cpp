// --h auto on the closed-form scene (1 x 1 m light 1 m above a black 4 x 4 m floor): the bandwidth it picks
// must land within a factor of 2 of the h that minimises the relative RMSE over the floor's interior vertices
// (farther from its edges than the largest h scanned), which this test finds by scanning h on a geometric grid
// (ratio 2^(1/4)) over the same photons, and its error within 10% of that optimum's. The interior, because that is
// the error the plug-in rule models; at the edges the local linear correction trades the bias away for variance
// (estimators/kernel_estimator.h). At every photon count from 2e5 to 4e6, for the kernel and the histogram: the
// optimum shrinks as the photons grow, and the rule must follow it. (A pilot of 400 photons per cell, measuring
// mostly noise, chose h 30-40% below the optimum at 1e6 and 4e6, +21% and +32% of RMSE; the histogram's rule,
// modelled on a second-order bias, 2.4x above it, +79%.)
#include <gtest/gtest.h>

#include <cmath>

#include "baker/2_bin_photons.h"
#include "baker/3_irradiance_field.h"
#include "mesh/split_mesh.h"
#include "tests/lambert.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

// The estimator (kernel or histogram, whose bias is first order: its rule reads the gradient, not the curvature)
// and the photons traced.
struct Case {
  EstimatorKind kind;
  uint64_t photons;
};

class AutoBandwidth : public ::testing::TestWithParam<Case> {};

TEST_P(AutoBandwidth, LandsWithinAFactorOfTwoOfTheScannedOptimum) {
  constexpr float kInterior = 2.0f - 0.45f;  // beyond the largest scanned h from the floor's edges
  const std::string dir = test::TempDirectory("auto-bandwidth");
  const test::TracedScene prepared(test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 80));
  const Scene& scene = prepared.scene;
  const SurfaceSet& surfaces = prepared.surfaces;
  const Log quiet(true);
  const PhotonStore hits = prepared.Trace(GetParam().photons, 5);
  const SurfaceBins bins = BinPhotons(surfaces, hits);
  const SurfaceRegions& regions = prepared.regions;
  EstimatorSettings settings;
  settings.kind = GetParam().kind;

  const auto relativeRmse = [&](const std::vector<float>& h) {
    const IrradianceField field(prepared, std::make_unique<PhotonIrradiance>(prepared, bins, settings, h));
    const BakedMesh baked = EstimateIrradiance(field, SplitBySurface(scene, surfaces), quiet);
    double sum = 0;
    int n = 0;
    for (size_t v = 0; v < baked.mesh.VertexCount(); ++v) {
      const Point3 p = baked.mesh.positions[v];
      if (p.y != 0.0f || std::fabs(p.x) > kInterior || std::fabs(p.z) > kInterior) continue;
      const double exact = test::SquareLightIrradiance(p.x, p.z);
      sum += std::pow((baked.irradiance[v].g - exact) / exact, 2), ++n;
    }
    return std::sqrt(sum / n);
  };
  EstimatorSettings perSurface = settings;
  perSurface.bandwidth.reset();
  const std::vector<float> automatic = SurfaceBandwidths(regions, bins, perSurface);
  const size_t floor = surfaces.surfaceOfTriangle[0];
  double bestH = 0, bestError = INFINITY;
  for (double h = 0.02; h < 0.45; h *= std::pow(2.0, 0.25)) {
    std::vector<float> scan = automatic;
    scan[floor] = float(h);
    const double error = relativeRmse(scan);
    if (error < bestError) bestError = error, bestH = h;
  }
  const double autoError = relativeRmse(automatic);
  RecordProperty("auto_h", std::to_string(automatic[floor]));
  RecordProperty("best_h", std::to_string(bestH));
  std::printf("%s, %llu photons: auto h %.4f (relative RMSE %.4f), scanned optimum h %.4f (%.4f)\n",
              EstimatorName(GetParam().kind).c_str(), (unsigned long long)GetParam().photons, automatic[floor],
              autoError, bestH, bestError);
  EXPECT_GT(bestH, 0.03);  // the optimum is inside the scanned range, not at its ends
  EXPECT_LT(bestH, 0.38);
  EXPECT_GT(automatic[floor], bestH / 2);
  EXPECT_LT(automatic[floor], bestH * 2);
  // And its error is the optimum's: with bias^2 ~ h^4 and variance ~ 1/h^2, an h 1.25x off costs 11% of RMSE. The
  // pilot at 400 photons per cell cost 21% at 1e6 photons and 32% at 4e6 (same photons, paired).
  EXPECT_LT(autoError, 1.1 * bestError);
}

INSTANTIATE_TEST_SUITE_P(PhotonCounts, AutoBandwidth,
                         ::testing::Values(Case{EstimatorKind::kKernel, 200'000}, Case{EstimatorKind::kKernel, 1'000'000},
                                           Case{EstimatorKind::kKernel, 4'000'000},
                                           Case{EstimatorKind::kHistogram, 1'000'000},
                                           Case{EstimatorKind::kHistogram, 4'000'000}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return EstimatorName(info.param.kind) + "_" + std::to_string(info.param.photons);
                         });

}  // namespace
}  // namespace pb
