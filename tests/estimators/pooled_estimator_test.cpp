// The pooled estimator (estimators/pooled_estimator.h) on a closed form: photons of equal flux spread uniformly
// over a thin cylinder cut into 64 x 40 facets (a banister's piece: every facet far smaller than the photons'
// spacing), so the true irradiance is E = Phi / A everywhere. The ratio of the photons' weighted flux to the
// facets' weighted area must read E at any point, within its own predicted noise: the estimate's relative noise is
// sqrt(sum (phi w)^2) / sum phi w, about 10% at 200 neighbours, so a point is checked to 4 of its predicted
// sigmas plus the area samples' own 2%, and the mean over 40 points (independent photons: each point's r holds
// other facets) to 4 sigma of that mean. Dividing by pi r^2 instead, the photon map's way, reads a cylinder of
// radius r/2 too dark by about 2.5x: the last check of the first test shows the area term is what makes it right.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "estimators/pooled_estimator.h"
#include "estimators/rng.h"
#include "estimators/warps.h"

namespace pb {
namespace {

constexpr float kRadius = 0.05f, kHeight = 1.0f;
constexpr int kAround = 64, kRings = 40;
constexpr double kIrradiance = 3.0;  // W/m^2 everywhere on the cylinder

Scene Cylinder() {
  Scene scene;
  for (int j = 0; j <= kRings; ++j)
    for (int i = 0; i < kAround; ++i) {
      const float a = 2 * kPi * float(i) / kAround;
      scene.positions.push_back({kRadius * std::cos(a), kHeight * float(j) / kRings, kRadius * std::sin(a)});
    }
  const auto at = [](int i, int j) { return uint32_t(j * kAround + i % kAround); };
  for (int j = 0; j < kRings; ++j)
    for (int i = 0; i < kAround; ++i) {  // counter-clockwise seen from outside: front normals point outward
      scene.triangles.push_back({{at(i, j), at(i, j + 1), at(i + 1, j)}});
      scene.triangles.push_back({{at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)}});
    }
  return scene;
}

std::vector<uint32_t> AllTriangles(const Scene& scene) {
  std::vector<uint32_t> all(scene.triangles.size());
  std::iota(all.begin(), all.end(), 0u);
  return all;
}

double TotalArea(const Scene& scene) {
  double area = 0;
  for (uint32_t t = 0; t < scene.triangles.size(); ++t) area += scene.Area(t);
  return area;
}

// `count` photons uniform over the scene's area, each of flux E A / count, from stream `seed`, weighed with the
// normal their triangle's area was sampled with.
std::vector<MapPhoton> UniformPhotons(const Scene& scene, const AreaSamples& sampled, size_t count, uint64_t seed) {
  std::vector<double> cdf;
  double area = 0;
  for (uint32_t t = 0; t < scene.triangles.size(); ++t) cdf.push_back(area += scene.Area(t));
  const auto phi = float(kIrradiance * area / double(count));
  std::vector<MapPhoton> photons;
  for (size_t i = 0; i < count; ++i) {
    Rng rng(seed, i);
    const double pick = rng.Uniform() * area;
    const auto t = uint32_t(std::min<size_t>(std::lower_bound(cdf.begin(), cdf.end(), pick) - cdf.begin(), cdf.size() - 1));
    const Barycentrics b = SampleUniformTriangle(rng.Uniform2());
    photons.push_back({scene.PointAt(t, b.b1, b.b2), Vector3{0, 1, 0}, Rgb{phi, phi, phi}, sampled.normalOf.at(t)});
  }
  return photons;
}

constexpr size_t kPhotons = 20'000;

// What a bake pools on `scene`: its area sampled at 4 per photon of kPhotons, and the settings PhotonIrradiance gives.
struct Pool {
  AreaSamples area;
  PooledSettings settings;
  explicit Pool(const Scene& scene) {
    const double density = double(kPhotons) / TotalArea(scene);
    area = SampleArea(scene, AllTriangles(scene), 4 * density);
    settings.maxRadius = float(std::sqrt(2 * settings.neighbours / (kPi * density)));
  }
  PooledEstimator With(const Scene& scene, uint64_t seed) const {
    return {UniformPhotons(scene, area, kPhotons, seed), area.samples, settings};
  }
};

// The estimate at a facet's centre on the cylinder, facing out.
NoisyIrradiance At(const PooledEstimator& pooled, const Scene& scene, uint32_t t) {
  return pooled.Estimate(scene.PointAt(t, 1.0f / 3, 1.0f / 3), scene.FrontNormal(t));
}

TEST(PooledEstimator, ReadsAUniformIrradianceOnAFacetedCylinderWithinItsNoise) {
  const Scene scene = Cylinder();
  const Pool pool(scene);
  const PooledEstimator pooled = pool.With(scene, 7);
  double sum = 0, variance = 0;
  int points = 0;
  for (int j = 2; j < kRings - 2; j += 4)  // away from the open ends, whose facets see half a neighbourhood
    for (int i = 0; i < kAround; i += 16) {
      const uint32_t t = uint32_t(2 * (j * kAround + i));
      const NoisyIrradiance e = At(pooled, scene, t);
      ASSERT_GT(e.relativeNoise, 0.03) << "at facet " << t;
      ASSERT_LT(e.relativeNoise, 0.25) << "at facet " << t;
      EXPECT_NEAR(e.irradiance.g, kIrradiance, kIrradiance * (4 * e.relativeNoise + 0.02)) << "at facet " << t;
      sum += e.irradiance.g, variance += std::pow(e.relativeNoise * kIrradiance, 2), ++points;
    }
  const double mean = sum / points, sigma = std::sqrt(variance) / points;
  EXPECT_NEAR(mean, kIrradiance, 4 * sigma + 0.01 * kIrradiance) << points << " points";
  // The same photons over pi r^2 for a r that holds ~200 of them at this density read far too dark on the
  // cylinder, whose area within r is a band: the area samples are what the estimate divides by.
  const double r = pool.settings.maxRadius;
  EXPECT_LT(200.0 * kIrradiance * TotalArea(scene) / double(kPhotons) / (kPi * r * r), 0.6 * kIrradiance);
}

TEST(PooledEstimator, PredictsItsOwnNoise) {
  // At one point, over 200 independent photon sets: the spread of the estimates is the noise each predicts, within
  // 15% (the standard error of a standard deviation from 200 draws is 5%).
  const Scene scene = Cylinder();
  const Pool pool(scene);
  const uint32_t t = 2 * (20 * kAround + 5);
  double sum = 0, sum2 = 0, predicted = 0;
  const int draws = 200;
  for (int k = 0; k < draws; ++k) {
    const NoisyIrradiance e = At(pool.With(scene, 100 + k), scene, t);
    sum += e.irradiance.g, sum2 += double(e.irradiance.g) * e.irradiance.g, predicted += e.relativeNoise;
  }
  const double mean = sum / draws, measured = std::sqrt(sum2 / draws - mean * mean) / mean;
  EXPECT_NEAR(measured, predicted / draws, 0.15 * measured) << "mean " << mean;
}

TEST(PooledEstimator, AreaSamplesCountEveryTriangleOnce) {
  // Facets far smaller than a sample are gathered, large triangles spread: either way the area is kept exactly.
  Scene scene = Cylinder();
  const size_t facets = scene.triangles.size();
  const auto base = uint32_t(scene.positions.size());
  scene.positions.insert(scene.positions.end(), {{-1, -1, -1}, {1, -1, -1}, {1, -1, 1}});  // a 2 m^2 triangle
  scene.triangles.push_back({{base, base + 2, base + 1}});
  for (double density : {10.0, 1000.0, 1e5}) {
    const std::vector<MapPhoton> samples = SampleArea(scene, AllTriangles(scene), density).samples;
    double area = 0;
    for (const MapPhoton& s : samples) area += s.flux.r;
    EXPECT_NEAR(area, TotalArea(scene), 1e-5 * TotalArea(scene)) << "density " << density;
    // About density x area samples where triangles are larger than a sample; one per facet at most where gathered.
    EXPECT_GE(double(samples.size()), 0.9 * std::min(density * TotalArea(scene), double(facets))) << density;
    EXPECT_LE(double(samples.size()), density * TotalArea(scene) + double(facets) + 1) << density;
  }
}

// A 1 m square of 40 x 40 x 2 facets in the plane y = 0, facing up.
Scene Square() {
  Scene scene;
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 40; ++i) scene.positions.push_back({float(i) / 40, 0, float(j) / 40});
  const auto at = [](int i, int j) { return uint32_t(j * 41 + i); };
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) {
      scene.triangles.push_back({{at(i, j), at(i, j + 1), at(i + 1, j)}});
      scene.triangles.push_back({{at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)}});
    }
  return scene;
}

TEST(PooledEstimator, SidesTurnedAwayShareNoPhotons) {
  // Photons on a panel's upper side only: its underside, at the same points, reads 0, not the upper side's light.
  const Scene scene = Square();
  ASSERT_GT(scene.FrontNormal(0).y, 0.99f);
  const PooledEstimator pooled = Pool(scene).With(scene, 9);
  const Point3 centre{0.5f, 0, 0.5f};
  const NoisyIrradiance up = pooled.Estimate(centre, Normal3{0, 1, 0});
  EXPECT_NEAR(up.irradiance.g, kIrradiance, kIrradiance * (4 * up.relativeNoise + 0.02));
  EXPECT_EQ(pooled.Estimate(centre, Normal3{0, -1, 0}).irradiance.g, 0.0f);
  // Tilted by 45 degrees the side still shares them, at half weight on both sums: the same reading.
  const NoisyIrradiance tilted = pooled.Estimate(centre, NormalFrom(Vector3{1, 1, 0}));
  EXPECT_NEAR(tilted.irradiance.g, kIrradiance, kIrradiance * (4 * tilted.relativeNoise + 0.02));
}

}  // namespace
}  // namespace pb
