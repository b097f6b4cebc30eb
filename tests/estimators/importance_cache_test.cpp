// The importance cache (estimators/importance_cache.h): a hit takes the map of a nearby site that faces its way,
// the very map the site's own photons build, and none where no site faces its way.
#include <gtest/gtest.h>

#include <cmath>

#include "estimators/importance_cache.h"

namespace pb {
namespace {

// A floor (y = 0, normal up) whose photons all arrive from one direction, and a wall (x = 0, normal +x) whose
// photons arrive along its normal: 400 photons each on a 20 x 20 grid of 5 cm.
PhotonMap FloorAndWall(Vector3 floorLight) {
  std::vector<MapPhoton> photons;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      const float a = 0.1f + 0.05f * float(i), b = 0.1f + 0.05f * float(j);
      photons.push_back({{a, 0, b}, floorLight, {1, 1, 1}, {0, 1, 0}});
      photons.push_back({{0, a, b}, {1, 0, 0}, {2, 2, 2}, {1, 0, 0}});
    }
  return PhotonMap(std::move(photons));
}

TEST(ImportanceCache, AHitTakesTheMapOfASiteFacingItsWay) {
  const float s = std::sqrt(0.5f);
  const PhotonMap photons = FloorAndWall({s, s, 0});
  const MapSettings settings{20, 4, 8, 0.2f};
  const ImportanceCache cache(photons, settings, 4);
  EXPECT_EQ(cache.Size(), 200u) << "every 4th photon: floor photons alone (the photons alternate)";
  std::vector<uint32_t> indices;
  std::vector<float> distance2;
  const Point3 hit{0.52f, 0, 0.53f};
  const ImportanceMap* map = cache.At(hit, {0, 1, 0}, indices, distance2);
  ASSERT_NE(map, nullptr);
  // The floor's light, 45 degrees from the normal toward +x, in the floor's frame: the densest direction.
  const Frame frame = Frame::FromNormal({0, 1, 0});
  const Vector3 toLight = frame.ToLocal({s, s, 0}), away = frame.ToLocal({-s, s, 0});
  EXPECT_GT(map->Pdf(toLight), 5 * map->Pdf(away));
  // The map is the one a nearby floor site's own photons build (its cell's nearest, or else its nearest).
  bool some = false;
  for (size_t i = 0; i < photons.Size() && !some; i += 4) {
    const MapPhoton& site = photons[uint32_t(i)];
    const float dx = site.position.x - hit.x, dz = site.position.z - hit.z;
    if (site.normal.y < 0.5f || dx * dx + dz * dz > 0.15f * 0.15f) continue;
    ImportanceMap own(4, 8, settings.domain);
    BuildImportanceMap(own, photons, site.position, {0, 1, 0}, settings, indices, distance2);
    some = own.Pdf(toLight) == map->Pdf(toLight) && own.Pdf(away) == map->Pdf(away);
  }
  EXPECT_TRUE(some) << "a nearby site's own map";
}

TEST(ImportanceCache, NoSiteFacingTheHitsWayGivesNoMap) {
  const PhotonMap photons = FloorAndWall({0, 1, 0});
  const ImportanceCache cache(photons, {20, 4, 8, 0.2f}, 3);  // floor and wall sites (the photons alternate)
  std::vector<uint32_t> indices;
  std::vector<float> distance2;
  EXPECT_EQ(cache.At({0.5f, 0, 0.5f}, {0, -1, 0}, indices, distance2), nullptr) << "the floor's underside";
  const ImportanceMap* wall = cache.At({0, 0.5f, 0.5f}, {1, 0, 0}, indices, distance2);
  ASSERT_NE(wall, nullptr);
  EXPECT_GT(wall->Pdf({0, 0, 1}), wall->Pdf({1, 0, 0.01f})) << "the wall's light along its normal";
}

}  // namespace
}  // namespace pb
