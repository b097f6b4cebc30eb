// The light sampler's one-sample path for render's next-event estimation with multiple importance sampling
// (estimators/light_sampler.h: SampleAreaLights, AreaLightPdf), on two lamps of different sizes 1 m over a floor,
// each sampled by solid angle where it subtends enough and by area otherwise (and by area everywhere with the
// solid-angle threshold at infinity):
//  - chi-square: where the samples land on the lamps (4 x 4 cells each) against the probability AreaLightPdf
//    gives each cell (its pdf over directions turned into one over the lamp's area, integrated numerically);
//  - the pdf a sample carries is AreaLightPdf's for its direction;
//  - the mean of the samples is Lambert's direct irradiance of both lamps, within 5 standard errors.
#include <gtest/gtest.h>

#include <cmath>

#include "estimators/light_sampler.h"
#include "tests/chi2.h"
#include "tests/lambert.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

constexpr float kHeight = 1.0f;
const std::vector<test::TestLamp> kLamps = {{-0.9f, -0.5f, -0.2f, 0.2f, kHeight}, {0.3f, 0.5f, -0.1f, 0.1f, kHeight}};
constexpr int kCells = 4;  // per lamp side

struct TwoLamps : test::TracedScene {
  TwoLamps() : TracedScene(test::WriteFloorWithLamps(test::TempDirectory("next-event"), 0.5f, 3.0f, kLamps)) {}
};

const TwoLamps& Scene() {
  static const TwoLamps scene;
  return scene;
}

// The point on lamp `lamp` at (a, b) in [0, 1]^2 across its rectangle.
Point3 OnLamp(int lamp, double a, double b) {
  const test::TestLamp& l = kLamps[size_t(lamp)];
  return {float(l.x0 + a * (l.x1 - l.x0)), l.y, float(l.z0 + b * (l.z1 - l.z0))};
}

// The lamp and cell that a point on a lamp lies in; -1 when on neither.
int CellOf(Point3 y) {
  for (int lamp = 0; lamp < 2; ++lamp) {
    const test::TestLamp& l = kLamps[size_t(lamp)];
    if (y.x < l.x0 || y.x > l.x1 || y.z < l.z0 || y.z > l.z1 || std::abs(y.y - l.y) > 1e-3f) continue;
    const int i = std::min(kCells - 1, int((y.x - l.x0) / (l.x1 - l.x0) * kCells));
    const int j = std::min(kCells - 1, int((y.z - l.z0) / (l.z1 - l.z0) * kCells));
    return lamp * kCells * kCells + j * kCells + i;
  }
  return -1;
}

// The probability of each cell: the integral over it of AreaLightPdf cos(theta_y) / d^2 dA (the midpoint rule on
// 24 x 24 points a cell; the integrand is smooth within one).
std::vector<double> CellProbabilities(const LightSampler& sampler, Point3 p, Normal3 n) {
  const TwoLamps& s = Scene();
  LightSampler::OneSampleScratch scratch;
  std::vector<double> probability(2 * kCells * kCells, 0.0);
  constexpr int kSub = 24;
  for (int lamp = 0; lamp < 2; ++lamp) {
    const test::TestLamp& l = kLamps[size_t(lamp)];
    const double dA = (l.x1 - l.x0) * (l.z1 - l.z0) / double(kCells * kCells * kSub * kSub);
    for (int i = 0; i < kCells * kSub; ++i)
      for (int j = 0; j < kCells * kSub; ++j) {
        const Point3 y = OnLamp(lamp, (i + 0.5) / (kCells * kSub), (j + 0.5) / (kCells * kSub));
        const auto hit = s.rays->Intersect(p, Normalize(y - p));
        if (!hit) {
          ADD_FAILURE() << "no lamp toward " << y.x << ", " << y.z;
          continue;
        }
        const Vector3 d = y - p;
        const double d2 = LengthSquared(d), cosY = d.y / std::sqrt(d2);  // the lamps face down
        probability[size_t(CellOf(y))] +=
            sampler.AreaLightPdf(p, n, hit->triangle, y, scratch) * cosY / d2 * dA;
      }
  }
  return probability;
}

void ExpectSamplesMatchThePdf(double solidAngleFrom, Point3 p) {
  const TwoLamps& s = Scene();
  const LightSampler sampler(s.scene, s.lights, *s.rays, LightSampler::kTreeLights, solidAngleFrom);
  const Normal3 n{0, 1, 0};
  const std::vector<double> probability = CellProbabilities(sampler, p, n);
  double total = 0;
  for (double q : probability) total += q;
  EXPECT_NEAR(total, 1.0, 2e-3) << "every sample lands on a lamp";
  LightSampler::OneSampleScratch scratch;
  constexpr int kSamples = 200'000;
  std::vector<double> observed(probability.size(), 0.0), expected(probability.size());
  for (size_t k = 0; k < probability.size(); ++k) expected[k] = kSamples * probability[k] / total;
  double worstPdf = 0, sum = 0, squares = 0;
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(21, uint64_t(i));
    const LightSampler::AreaSample a = sampler.SampleAreaLights(p, n, rng, scratch);
    ASSERT_GT(a.pdf, 0);
    const auto hit = s.rays->Intersect(p, a.from);
    ASSERT_TRUE(hit.has_value());
    const Point3 y = p + a.from * hit->t;
    const int cell = CellOf(y);
    ASSERT_GE(cell, 0) << "a sample toward no lamp";
    ++observed[size_t(cell)];
    const float pdf = sampler.AreaLightPdf(p, n, hit->triangle, y, scratch);
    worstPdf = std::max(worstPdf, std::abs(double(pdf) / a.pdf - 1));
    sum += a.irradiance.g, squares += double(a.irradiance.g) * a.irradiance.g;
  }
  const test::Chi2Result r = test::Chi2Test(observed, expected);
  EXPECT_GT(r.pValue, 1e-3) << "chi2 " << r.statistic << " dof " << r.degreesOfFreedom << "\n" << r.histograms;
  EXPECT_LT(worstPdf, 2e-3) << "a sample's pdf is AreaLightPdf's for its direction";
  // Unbiased: the mean against Lambert's formula for both lamps (radiance 3).
  double exact = 0;
  for (int lamp = 0; lamp < 2; ++lamp) {
    std::vector<test::V3> corners;
    for (const auto& [a, b] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{1, 1}, std::pair{0, 1}}) {
      const Point3 c = OnLamp(lamp, a, b);
      corners.push_back({c.x, c.y, c.z});
    }
    exact += test::LambertPolygonIrradiance({p.x, p.y, p.z}, {0, 1, 0}, corners, 3.0);
  }
  const double mean = sum / kSamples, error = std::sqrt((squares / kSamples - mean * mean) / kSamples);
  EXPECT_NEAR(mean, exact, 5 * error) << "solid angle from " << solidAngleFrom;
}

TEST(NextEvent, SolidAngleSamplesMatchTheirPdf) { ExpectSamplesMatchThePdf(LightSampler::kSolidAngleFrom, {0, 0.5f, 0}); }
TEST(NextEvent, AreaSamplesMatchTheirPdf) { ExpectSamplesMatchThePdf(INFINITY, {0.2f, 0, 0.3f}); }

}  // namespace
}  // namespace pb
