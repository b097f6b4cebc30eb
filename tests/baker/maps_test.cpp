// Irradiance maps (--maps, baker/5_write_maps.h): read back with OpenEXR, every texel equals the surface's own
// estimator evaluated at the texel centre, and the header names the quantity, units, surface and texel size.
#include <gtest/gtest.h>

#include "baker/2_bin_photons.h"
#include "baker/3_irradiance_field.h"
#include "baker/bake.h"
#include "baker/image_io.h"
#include "mesh/errors.h"
#include "mesh/obj_loader.h"
#include "tests/test_scenes.h"
#include "tests/staged_bake.h"

namespace pb {
namespace {

std::string Attribute(const std::vector<std::pair<std::string, std::string>>& attributes, const std::string& key) {
  for (const auto& [k, v] : attributes)
    if (k == key) return v;
  return "<missing>";
}

// A bake of the 4 m square-light floor into `dir`, with maps of texel `texel` [m].
BakeOptions MapBake(const std::string& dir, float texel, uint64_t photons) {
  BakeOptions o;
  o.direct.mode = DirectLight::kPhotons;  // the maps' noise model is the photons'
  o.scenePath = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 8);
  o.outputPath = dir + "/out.ply";
  o.photons = photons;
  o.seed = 3;
  o.mapsDirectory = dir;
  o.texel = texel;
  return o;
}

TEST(IrradianceMaps, RoundTripMatchesTheEstimatorAtTexelCentres) {
  const BakeOptions o = MapBake(test::TempDirectory("maps"), 0.1f, 100000);
  const BakeReport report = Bake(o, Log(true));
  ASSERT_EQ(report.maps.paths.size(), report.surfaces.size());

  // The same estimators, rebuilt from the same photons.
  const test::TracedScene traced(o.scenePath);
  const PhotonStore hits = traced.Trace(o.photons, o.seed, o.maxBounces);
  const SurfaceBins bins = BinPhotons(traced.surfaces, hits);
  const SurfaceRegions& regions = traced.regions;
  const IrradianceField field = test::FieldOf(traced, bins, o.estimator);

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
      const Rgb expected = field.Photons().ChartDensity(floor, uv);  // a planar chart: per surface area too
      ASSERT_EQ(map.At(i, j).g, expected.g) << i << "," << j;
      sum += map.At(i, j).g;
    }
  // The map's mean over the floor is the floor's mean irradiance, within the estimate's smoothing and noise.
  EXPECT_NEAR(sum / (40 * 40), Luminance(report.surfaces[floor].meanIrradiance), 0.03 * sum / (40 * 40));
}

TEST(IrradianceMaps, RefusesTexelsTooSmallForTheSurface) {
  // 1e-4 m texels: 40,000 on a side.
  EXPECT_THROW(Bake(MapBake(test::TempDirectory("maps-small"), 1e-4f, 1000), Log(true)), InputError);
}

}  // namespace
}  // namespace pb
