// The importance cache (estimators/importance_cache.h): its cells hold about N photons; a hit takes the map its
// own cell's photons facing its way build, and none where none faces its way; a group of few photons has its
// floor raised; the cell table keeps every key apart.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "estimators/importance_cache.h"
#include "estimators/rng.h"

namespace pb {
namespace {

// A floor (y = 0, normal up) whose photons all arrive from `floorLight`, and a wall (x = 0, normal +x) whose
// photons arrive along its normal: `n` photons each, uniform over 1 m x 1 m.
std::vector<MapPhoton> FloorAndWall(Vector3 floorLight, int n) {
  std::vector<MapPhoton> photons;
  Rng rng(3, 0);
  for (int i = 0; i < n; ++i) {
    const Point2 a = rng.Uniform2(), b = rng.Uniform2();
    photons.push_back({{a.u, 0, a.v}, floorLight, {1, 1, 1}, {0, 1, 0}});
    photons.push_back({{0, b.u, b.v}, {1, 0, 0}, {2, 2, 2}, {1, 0, 0}});
  }
  return photons;
}

TEST(ImportanceCache, CellsHoldAboutNPhotons) {
  const std::vector<MapPhoton> photons = FloorAndWall({0, 1, 0}, 100000);
  for (uint32_t n : {50u, 400u}) {
    const ImportanceCache cache(photons, {n, 4, 8, 0.2f});
    std::map<std::pair<uint64_t, bool>, int> counts;  // per cell and orientation
    for (const MapPhoton& p : photons) ++counts[{cache.CellOf(p.position), p.normal.y > 0.5f}];
    const double mean = double(photons.size()) / double(counts.size());
    // The side is set from the square law of photons on surfaces; cells cut by the planes' edges hold fewer.
    EXPECT_GT(mean, 0.6 * n) << "N " << n << ", cell " << cache.CellSide() << " m";
    EXPECT_LT(mean, 1.5 * n) << "N " << n << ", cell " << cache.CellSide() << " m";
    EXPECT_EQ(cache.Size(), counts.size()) << "a group for the floor's and one for the wall's photons of a cell";
  }
}

TEST(ImportanceCache, AHitTakesTheMapItsCellsPhotonsBuild) {
  const float s = std::sqrt(0.5f);
  const std::vector<MapPhoton> photons = FloorAndWall({s, s, 0}, 40000);
  const MapSettings settings{100, 4, 8, 0.2f};
  const ImportanceCache cache(photons, settings);
  const Point3 hit{0.52f, 0, 0.53f};
  const ImportanceMap* map = cache.At(hit, {0, 1, 0});
  ASSERT_NE(map, nullptr);
  // The floor's light, 45 degrees from the normal toward +x, in the floor's frame: the densest direction.
  const Frame frame = Frame::FromNormal({0, 1, 0});
  const Vector3 toLight = frame.ToLocal({s, s, 0}), away = frame.ToLocal({-s, s, 0});
  EXPECT_GT(map->Pdf(toLight), 5 * map->Pdf(away));
  // The very map the floor photons of the hit's cell build, with the floor raised if they are fewer than N.
  ImportanceMap own(4, 8, settings.domain);
  double count = 0;
  for (const MapPhoton& p : photons)
    if (p.normal.y > 0.5f && cache.CellOf(p.position) == cache.CellOf(hit)) {
      own.Add(frame.ToLocal(p.wi), Luminance(p.flux));
      ++count;
    }
  ASSERT_GT(count, 0);
  own.Finish(std::max(0.2f, float(1 - count / 100)));
  for (uint32_t k = 0; k < 32; ++k) EXPECT_FLOAT_EQ(own.RegionProbability(k), map->RegionProbability(k)) << k;
}

TEST(ImportanceCache, NoGroupFacingTheHitsWayGivesNoMap) {
  const std::vector<MapPhoton> photons = FloorAndWall({0, 1, 0}, 20000);
  const ImportanceCache cache(photons, {50, 4, 8, 0.2f});
  EXPECT_EQ(cache.At({0.5f, 0, 0.5f}, {0, -1, 0}), nullptr) << "the floor's underside";
  EXPECT_EQ(cache.At({0.5f, 3, 0.5f}, {0, 1, 0}), nullptr) << "beyond the photons' bounds";
  EXPECT_EQ(cache.At({-0.5f, 0, 0.5f}, {0, 1, 0}), nullptr) << "below the photons' lowest corner";
  EXPECT_EQ(cache.At({1e30f, 0, 0.5f}, {0, 1, 0}), nullptr) << "far beyond: no cell index overflows";
  EXPECT_EQ(cache.At({NAN, 0, 0.5f}, {0, 1, 0}), nullptr);
  const ImportanceMap* wall = cache.At({0, 0.5f, 0.5f}, {1, 0, 0});
  ASSERT_NE(wall, nullptr);
  EXPECT_GT(wall->Pdf({0, 0, 1}), wall->Pdf({1, 0, 0.01f})) << "the wall's light along its normal";
}

TEST(ImportanceCache, EveryCellKeepsAGroupForEachWayItsPhotonsFace) {
  // At 20,000 points a floor photon, then a wall photon: each wall group joins its cell's chain after the floor's,
  // while the groups' storage grows past what the allocator maps anew (a link into it, once read after the growth,
  // read freed memory).
  std::vector<MapPhoton> photons;
  for (int i = 0; i < 20000; ++i) {
    const Point3 p{float(i % 200), 0, float(i / 200)};
    photons.push_back({p, {0, 1, 0}, {1, 1, 1}, {0, 1, 0}});
    photons.push_back({p, {1, 0, 0}, {1, 1, 1}, {1, 0, 0}});
  }
  const ImportanceCache cache(photons, {2, 4, 8, 0.2f});
  std::map<uint64_t, int> cells;
  for (const MapPhoton& p : photons) ++cells[cache.CellOf(p.position)];
  EXPECT_EQ(cache.Size(), 2 * cells.size());
  for (const MapPhoton& p : photons) {
    ASSERT_NE(cache.At(p.position, {0, 1, 0}), nullptr);
    ASSERT_NE(cache.At(p.position, {1, 0, 0}), nullptr);
    ASSERT_NE(cache.At(p.position, {0, 1, 0}), cache.At(p.position, {1, 0, 0}));
  }
}

TEST(ImportanceCache, AGroupOfFewPhotonsIsNearlyTheCosineLobe) {
  // One photon, straight down the normal, where N = 200: floor 1 - 1/200.
  const ImportanceCache cache({{{0, 0, 0}, {0, 0, 1}, {1, 1, 1}, {0, 0, 1}}}, {200, 4, 8, 0.3f});
  const ImportanceMap* map = cache.At({0, 0, 0}, {0, 0, 1});
  ASSERT_NE(map, nullptr);
  const uint32_t zenith = *map->RegionOf({0, 0, 1});
  EXPECT_NEAR(map->RegionProbability(zenith), 1.0 / 200 + (1 - 1.0 / 200) / 32, 1e-6);
  EXPECT_NEAR(map->RegionProbability((zenith + 1) % 32), (1 - 1.0 / 200) / 32, 1e-6);
}

TEST(CellTable, KeepsEveryKeyApartThroughGrowth) {
  CellTable table;
  Rng rng(5, 0);
  std::vector<uint64_t> keys;
  for (int i = 0; i < 5000; ++i) keys.push_back(uint64_t(rng.Uniform() * 1e6f) << 21 | uint64_t(i));
  for (size_t i = 0; i < keys.size(); ++i) ASSERT_EQ(table.Insert(keys[i]), i);
  for (size_t i = 0; i < keys.size(); ++i) ASSERT_EQ(table.Insert(keys[i]), i) << "an old key keeps its index";
  for (size_t i = 0; i < keys.size(); ++i) ASSERT_EQ(table.Find(keys[i]), i);
  EXPECT_EQ(table.Find(uint64_t(1) << 63), CellTable::kAbsent);
  EXPECT_EQ(table.Size(), keys.size());
}

}  // namespace
}  // namespace pb
