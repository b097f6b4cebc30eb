// --h auto on the closed-form scene (1 x 1 m light 1 m above a black 4 x 4 m floor): the bandwidth it picks
// must land within a factor of 2 of the h that minimises the relative RMSE over the floor's interior vertices
// (farther from its edges than the largest h scanned), which this test finds by scanning h on a geometric grid
// (ratio 2^(1/4)) over the same photons. The interior, because that is the error the plug-in rule models; at the
// edges the local linear correction trades the bias away for variance (estimators/kernel_estimator.h).
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

TEST(AutoBandwidth, LandsWithinAFactorOfTwoOfTheScannedOptimum) {
  constexpr float kInterior = 2.0f - 0.45f;  // beyond the largest scanned h from the floor's edges
  const std::string dir = test::TempDirectory("auto-bandwidth");
  const test::TracedScene prepared(test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 80));
  const Scene& scene = prepared.scene;
  const SurfaceSet& surfaces = prepared.surfaces;
  const Log quiet(true);
  const PhotonStore hits = prepared.Trace(1'000'000, 5);
  const SurfaceBins bins = BinPhotons(surfaces, hits);
  const SurfaceRegions& regions = prepared.regions;
  const EstimatorSettings settings;

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
  const std::vector<float> automatic = SurfaceBandwidths(regions, bins, settings, true);
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
  std::printf("auto h %.4f (relative RMSE %.4f), scanned optimum h %.4f (%.4f)\n", automatic[floor], autoError, bestH, bestError);
  EXPECT_GT(bestH, 0.03);  // the optimum is inside the scanned range, not at its ends
  EXPECT_LT(bestH, 0.38);
  EXPECT_GT(automatic[floor], bestH / 2);
  EXPECT_LT(automatic[floor], bestH * 2);
}

}  // namespace
}  // namespace pb
