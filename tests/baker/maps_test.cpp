// Irradiance maps (--maps, baker/5_write_maps.h): read back with OpenEXR, every texel equals the surface's own
// estimator evaluated at the texel centre, and the header names the quantity, units, surface and texel size.
#include <gtest/gtest.h>

#include "baker/2_bin_photons.h"
#include "baker/3_estimate_irradiance.h"
#include "baker/bake.h"
#include "baker/image_io.h"
#include "mesh/errors.h"
#include "mesh/obj_loader.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

std::string Attribute(const std::vector<std::pair<std::string, std::string>>& attributes, const std::string& key) {
  for (const auto& [k, v] : attributes)
    if (k == key) return v;
  return "<missing>";
}

TEST(IrradianceMaps, RoundTripMatchesTheEstimatorAtTexelCentres) {
  const std::string dir = test::TempDirectory("maps");
  BakeOptions o;
  o.scenePath = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 8);
  o.outputPath = dir + "/out.ply";
  o.photons = 100000;
  o.seed = 3;
  o.mapsDirectory = dir;
  o.texel = 0.1f;
  const BakeReport report = Bake(o, Log(true));
  ASSERT_EQ(report.maps.paths.size(), report.surfaces.size());

  // The same estimators, rebuilt from the same photons.
  const Scene scene = LoadObj(o.scenePath).scene;
  const SurfaceSet surfaces = BuildSurfaces(scene);
  const std::vector<AreaLight> lights = CollectLights(scene, surfaces);
  const RayScene rays(scene);
  const PhotonHits hits = TracePhotons(scene, lights, rays, PlanTransport(scene, surfaces, lights, {}),
                                       {o.photons, o.seed, o.maxBounces}, Log(true));
  const SurfaceBins bins = BinPhotons(surfaces, hits);
  const SurfaceRegions regions = BuildRegions(surfaces);
  const SurfaceEstimators estimators =
      BuildEstimators(regions, bins, o.estimator, SurfaceBandwidths(regions, bins, o.estimator, false));

  const uint32_t floor = 0;  // the floor is written first
  std::vector<std::pair<std::string, std::string>> attributes;
  const Image map = ReadExr(report.maps.paths[floor], &attributes);
  EXPECT_EQ(Attribute(attributes, "quantity"), "irradiance");
  EXPECT_EQ(Attribute(attributes, "units").rfind("W/m^2", 0), 0u);
  EXPECT_EQ(Attribute(attributes, "surface"), "0");
  EXPECT_EQ(Attribute(attributes, "texel_size_m"), "0.100000001");
  const Bounds2 b = regions[floor]->Bounds();
  ASSERT_EQ(map.width, 40);  // a 4 m floor in 0.1 m texels
  ASSERT_EQ(map.height, 40);
  double sum = 0;
  for (int j = 0; j < map.height; ++j)
    for (int i = 0; i < map.width; ++i) {
      const Point2 uv{b.lo.u + (float(i) + 0.5f) * o.texel, b.lo.v + (float(j) + 0.5f) * o.texel};
      const Rgb expected = estimators[floor]->Estimate(uv);
      ASSERT_EQ(map.At(i, j).g, expected.g) << i << "," << j;
      sum += map.At(i, j).g;
    }
  // The map's mean over the floor is the floor's mean irradiance, within the estimate's smoothing and noise.
  EXPECT_NEAR(sum / (40 * 40), Luminance(report.surfaces[floor].meanIrradiance), 0.03 * sum / (40 * 40));
}

TEST(IrradianceMaps, RefusesTexelsTooSmallForTheSurface) {
  const std::string dir = test::TempDirectory("maps-small");
  BakeOptions o;
  o.scenePath = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 8);
  o.outputPath = dir + "/out.ply";
  o.photons = 1000;
  o.mapsDirectory = dir;
  o.texel = 1e-4f;  // 40,000 texels on a side
  EXPECT_THROW(Bake(o, Log(true)), InputError);
}

}  // namespace
}  // namespace pb
