// The importance map (estimators/importance_map.h): both warps pass a chi-square test against the map's pdf on
// random maps, maps with empty regions, a map with one dominant region and an empty map; Sample's pdf equals
// Pdf; Invert(Sample(u)) = u wherever the pdf is positive.
#include <gtest/gtest.h>

#include <cmath>

#include "estimators/importance_map.h"
#include "estimators/rng.h"
#include "tests/chi2.h"

namespace pb {
namespace {

constexpr double kSignificance = 1e-3;
constexpr int kSamples = 400'000;

// (s, t) of a direction, as the map defines it (header): cos(theta) = 1 - s, cos(theta)^2 = 1 - s or
// cos(theta) = 1 - 2s; phi = 2 pi t.
double SOf(double z, MapDomain domain) {
  return domain == MapDomain::kHemisphere ? 1 - z : domain == MapDomain::kSphere ? 0.5 * (1 - z) : 1 - z * z;
}
double ZOf(double s, MapDomain domain) {
  return domain == MapDomain::kHemisphere ? 1 - s : domain == MapDomain::kSphere ? 1 - 2 * s : std::sqrt(1 - s);
}
Point2 SquareOf(Vector3 d, MapDomain domain) {
  double phi = std::atan2(d.y, d.x);
  if (phi < 0) phi += 2 * M_PI;
  return {float(SOf(d.z, domain)), float(phi / (2 * M_PI))};
}

enum class Fill { kRandom, kHalfEmpty, kDominant, kNothing };

ImportanceMap MakeMap(int rows, int cols, MapDomain domain, Fill fill, float floorFraction, uint64_t seed) {
  ImportanceMap map(rows, cols, domain);
  Rng rng(seed, 0);
  for (int k = 0; k < rows * cols; ++k) {
    // A direction in the middle of region k.
    const float s = (float(k / cols) + 0.5f) / float(rows), t = (float(k % cols) + 0.5f) / float(cols);
    const float z = float(ZOf(s, domain)), r = std::sqrt(1 - z * z);
    const Vector3 d{r * std::cos(float(2 * M_PI) * t), r * std::sin(float(2 * M_PI) * t), z};
    float w = 0;
    switch (fill) {
      case Fill::kRandom: w = rng.Uniform(); break;
      case Fill::kHalfEmpty: w = rng.Uniform() < 0.5f ? 0.0f : rng.Uniform(); break;
      case Fill::kDominant: w = k == 5 ? 1e6f : 1.0f; break;
      case Fill::kNothing: break;
    }
    map.Add(d, w);
  }
  map.Finish(floorFraction);
  return map;
}

void ExpectMatchesPdf(const ImportanceMap& map, ImportanceWarp warp, uint64_t seed) {
  const MapDomain domain = map.Domain();
  // Histogram in cells of half a region per side; the pdf is constant over each region in (s, t), so a cell
  // expects a quarter of its region's probability.
  const int rows = 2 * map.Rows(), cols = 2 * map.Cols();
  std::vector<double> observed(size_t(rows * cols), 0.0), expected(size_t(rows * cols), 0.0);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      expected[size_t(r * cols + c)] = kSamples * map.RegionProbability(uint32_t((r / 2) * map.Cols() + c / 2)) / 4.0;
  double worstRoundTrip = 0;
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(seed, uint64_t(i));
    const Point2 u = rng.Uniform2();
    const ImportanceSample s = map.Sample(u, warp);
    ASSERT_NEAR(Length(s.direction), 1.0f, 1e-5);
    if (domain != MapDomain::kSphere) {
      ASSERT_GE(s.direction.z, 0.0f);
    }
    ASSERT_GT(s.pdf, 0.0f);
    ASSERT_NEAR(s.pdf, map.Pdf(s.direction), 1e-4f * s.pdf);
    const Point2 st = SquareOf(s.direction, domain);
    const int r = std::min(rows - 1, int(st.u * rows)), c = std::min(cols - 1, int(st.v * cols));
    ++observed[size_t(r * cols + c)];
    if (const auto back = map.Invert(s.direction, warp)) {
      worstRoundTrip = std::max({worstRoundTrip, double(std::abs(back->u - u.u)), double(std::abs(back->v - u.v))});
    }
  }
  for (size_t k = 0; k < expected.size(); ++k) {
    if (expected[k] == 0) {
      EXPECT_EQ(observed[k], 0) << "a sample in a region of probability 0";
    }
  }
  const test::Chi2Result r = test::Chi2Test(observed, expected);
  EXPECT_GT(r.pValue, kSignificance) << "chi2 " << r.statistic << " dof " << r.degreesOfFreedom << "\n" << r.histograms;
  EXPECT_LT(worstRoundTrip, 1e-3) << "Invert(Sample(u)) = u (up to the 1e-4 edge margin of a region)";
}

class ImportanceWarps : public testing::TestWithParam<ImportanceWarp> {};

constexpr MapDomain kHemisphere = MapDomain::kHemisphere;
TEST_P(ImportanceWarps, RandomMap) { ExpectMatchesPdf(MakeMap(8, 16, kHemisphere, Fill::kRandom, 0.1f, 1), GetParam(), 2); }
TEST_P(ImportanceWarps, EmptyRegionsWithoutFloor) {
  ExpectMatchesPdf(MakeMap(8, 16, kHemisphere, Fill::kHalfEmpty, 0.0f, 3), GetParam(), 4);
}
TEST_P(ImportanceWarps, OneDominantRegion) {
  ExpectMatchesPdf(MakeMap(8, 8, kHemisphere, Fill::kDominant, 0.1f, 5), GetParam(), 6);
}
TEST_P(ImportanceWarps, NoPhotonsGivesTheUniformMap) {
  const ImportanceMap map = MakeMap(4, 8, kHemisphere, Fill::kNothing, 0.0f, 7);
  EXPECT_FLOAT_EQ(map.Pdf({0, 0, 1}), float(1 / (2 * M_PI)));
  ExpectMatchesPdf(map, GetParam(), 8);
}
TEST_P(ImportanceWarps, SphereForTransparentSurfaces) {
  ExpectMatchesPdf(MakeMap(8, 16, MapDomain::kSphere, Fill::kRandom, 0.05f, 9), GetParam(), 10);
}
TEST_P(ImportanceWarps, CosineDomainRandomAndEmptyRegions) {
  ExpectMatchesPdf(MakeMap(8, 16, MapDomain::kCosineHemisphere, Fill::kRandom, 0.1f, 11), GetParam(), 12);
  ExpectMatchesPdf(MakeMap(4, 8, MapDomain::kCosineHemisphere, Fill::kHalfEmpty, 0.0f, 13), GetParam(), 14);
}
TEST_P(ImportanceWarps, CosineDomainUniformMapIsTheCosineLobe) {
  const ImportanceMap map = MakeMap(4, 8, MapDomain::kCosineHemisphere, Fill::kNothing, 0.0f, 15);
  for (const float z : {1.0f, 0.7f, 0.2f, 0.01f}) {
    const Vector3 d{std::sqrt(1 - z * z), 0, z};
    EXPECT_NEAR(map.Pdf(d), z / M_PI, 1e-6) << "cos(theta) / pi at cos(theta) = " << z;
  }
  ExpectMatchesPdf(map, GetParam(), 16);
}

INSTANTIATE_TEST_SUITE_P(BothWarps, ImportanceWarps, testing::Values(ImportanceWarp::kMipmap, ImportanceWarp::kInversion),
                         [](const auto& info) { return info.param == ImportanceWarp::kMipmap ? "Mipmap" : "Inversion"; });

TEST(ImportanceMap, FloorSpreadsAFractionOfTheTotalOverEveryRegion) {
  ImportanceMap map(4, 4);
  map.Add({0, 0, 1}, 3.0f);  // all in the zenith region
  map.Finish(0.2f);
  const uint32_t zenith = *map.RegionOf({0, 0, 1});
  EXPECT_NEAR(map.RegionProbability(zenith), 0.8 + 0.2 / 16, 1e-6);
  EXPECT_NEAR(map.RegionProbability((zenith + 1) % 16), 0.2 / 16, 1e-7);
  // The paper's scale factor for equal-area regions, s = I / (I_k n), is 1 / (pdf * Omega).
  EXPECT_NEAR(1.0 / (map.Pdf({0, 0, 1}) * 2 * M_PI), 1.0 / ((0.8 + 0.2 / 16) * 16), 1e-5);
  EXPECT_EQ(map.Pdf({0, 0, -1}), 0.0f) << "below the hemisphere";
}

TEST(ImportanceMap, CosineDomainWeightIsTheScaleFactorWithinARegion) {
  // A Lambertian BRDF's weight f cos / pdf = (1 / pi) cos / pdf is 1 / (P_k n) at every direction of region k.
  ImportanceMap map(4, 4, MapDomain::kCosineHemisphere);
  map.Add({0, 0, 1}, 3.0f);
  map.Finish(0.2f);
  const uint32_t zenith = *map.RegionOf({0, 0, 1});
  for (const float z : {0.999f, 0.95f, 0.9f}) {  // the first band is cos(theta)^2 in [0.75, 1]
    const Vector3 d{std::sqrt(1 - z * z), 0, z};
    ASSERT_EQ(*map.RegionOf(d), zenith);
    EXPECT_NEAR(z / M_PI / map.Pdf(d), 1.0 / ((0.8 + 0.2 / 16) * 16), 1e-5);
  }
}

}  // namespace
}  // namespace pb
