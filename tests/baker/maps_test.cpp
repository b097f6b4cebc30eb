// Irradiance maps (--maps, baker/5_write_maps.h): read back with OpenEXR, every texel equals the surface's own
// estimator evaluated at the texel centre, and the header names the quantity, units, surface and texel size.
#include <gtest/gtest.h>

#include "baker/2_bin_photons.h"
#include "baker/3_irradiance_field.h"
#include "baker/4_refine_mesh.h"
#include "baker/5_write_maps.h"
#include "baker/bake.h"
#include "baker/files/image_io.h"
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

// Work that multiplies (issue 39): --texel 1e-4 on the box ran 90 s without a word. The maps' and subdivision's
// time is foretold from the time a point of the estimate took, and warned about past a minute.
TEST(IrradianceMaps, MapsOrSubdivisionThatWouldTakeMinutesAreForetold) {
  SurfaceRegions square;  // 1 m^2
  square.push_back(std::make_unique<SurfaceRegion>(std::vector<Triangle2>{
      {Point2{0, 0}, Point2{1, 0}, Point2{1, 1}}, {Point2{0, 0}, Point2{1, 1}, Point2{0, 1}}}));
  EXPECT_NEAR(MapTexelCount(1e-3f, square), 1e6, 4e3);
  EXPECT_TRUE(MapTimeWarnings(1e-2f, square, 1e-4).empty()) << "1e4 texels at 0.1 ms: 1 s";
  const std::vector<std::string> slow = MapTimeWarnings(1e-4f, square, 1e-4);  // 1e8 texels: 10^4 s
  ASSERT_EQ(slow.size(), 1u);
  EXPECT_NE(slow[0].find("about 2 h 46 min"), std::string::npos) << slow[0];
  EXPECT_NE(slow[0].find("--texel 0.0013 would take about a minute"), std::string::npos) << slow[0];
  EXPECT_TRUE(SubdivisionTimeWarnings(1000, 2, 1e-3).empty()) << "8,000 vertices at 1 ms: 8 s";
  const std::vector<std::string> deep = SubdivisionTimeWarnings(1000, 5, 1e-3);  // 512,000 vertices: 512 s
  ASSERT_EQ(deep.size(), 1u);
  EXPECT_NE(deep[0].find("--subdivide 5: warning: about 5.12e+05 vertices to estimate, about 8 min 32 s"),
            std::string::npos) << deep[0];
}

}  // namespace
}  // namespace pb
