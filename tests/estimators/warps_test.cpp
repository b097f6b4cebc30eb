// Every warp: a chi-square test of its samples against the integral of its pdf over each cell, and
// Invert(Sample(u)) == u. Significance 1e-3 per test with fixed seeds, so a pass is reproducible and a failure
// means the sampler and its pdf disagree.
#include "estimators/warps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "estimators/rng.h"
#include "tests/chi2.h"

namespace pb {
namespace {

constexpr double kSignificance = 1e-3;
constexpr int kSamples = 1'000'000;

TEST(Warps, CosineHemisphereMatchesItsPdf) {
  // Cells in (theta, phi); the integral of cos(theta)/pi over a cell is dphi/pi * (sin^2 t1 - sin^2 t0) / 2.
  constexpr int nt = 12, np = 24;
  std::vector<double> observed(nt * np, 0), expected(nt * np, 0);
  for (int i = 0; i < nt; ++i)
    for (int j = 0; j < np; ++j) {
      const double t0 = M_PI / 2 * i / nt, t1 = M_PI / 2 * (i + 1) / nt, dphi = 2 * M_PI / np;
      expected[i * np + j] = kSamples * dphi / M_PI * (std::pow(std::sin(t1), 2) - std::pow(std::sin(t0), 2)) / 2;
    }
  Rng rng(1, 0);
  for (int s = 0; s < kSamples; ++s) {
    const DirectionSample d = SampleCosineHemisphere(rng.Uniform2());
    ASSERT_GE(d.direction.z, 0.0f);
    ASSERT_NEAR(LengthSquared(d.direction), 1.0f, 1e-5f);
    ASSERT_NEAR(d.pdf, CosineHemispherePdf(d.direction.z), 1e-6f);
    const double theta = std::acos(std::min(1.0f, d.direction.z));
    double phi = std::atan2(d.direction.y, d.direction.x);
    if (phi < 0) phi += 2 * M_PI;
    const int i = std::min(nt - 1, int(theta / (M_PI / 2) * nt)), j = std::min(np - 1, int(phi / (2 * M_PI) * np));
    observed[i * np + j] += 1;
  }
  const test::Chi2Result r = test::Chi2Test(observed, expected);
  EXPECT_GT(r.pValue, kSignificance) << "chi2 " << r.statistic << " dof " << r.degreesOfFreedom << "\n" << r.histograms;
}

TEST(Warps, UniformTriangleMatchesItsPdf) {
  // Cells of an n x n grid over (b1, b2); the triangle b1 + b2 < 1 covers a cell fully, half, or not at all.
  constexpr int n = 20;
  std::vector<double> observed(n * n, 0), expected(n * n, 0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double area = i + j + 2 <= n ? 1.0 : (i + j + 1 == n ? 0.5 : 0.0);
      expected[i * n + j] = kSamples * 2.0 * area / (n * n);
    }
  Rng rng(2, 0);
  for (int s = 0; s < kSamples; ++s) {
    const Barycentrics b = SampleUniformTriangle(rng.Uniform2());
    ASSERT_GE(b.b1, 0.0f);
    ASSERT_GE(b.b2, 0.0f);
    ASSERT_LE(b.b1 + b.b2, 1.0f + 1e-6f);
    observed[std::min(n - 1, int(b.b1 * n)) * n + std::min(n - 1, int(b.b2 * n))] += 1;
  }
  const test::Chi2Result r = test::Chi2Test(observed, expected);
  EXPECT_GT(r.pValue, kSignificance) << "chi2 " << r.statistic << "\n" << r.histograms;
}

// The sub-triangle (of n^2, from splitting each side into n) that barycentrics (b1, b2) fall in: the upward
// triangle of cell (i, j) is 2 (i n + j), the downward one 2 (i n + j) + 1.
int SubTriangle(double b1, double b2, int n) {
  const int i = std::clamp(int(b1 * n), 0, n - 1), j = std::clamp(int(b2 * n), 0, n - 1);
  const bool down = b1 * n - i + (b2 * n - j) > 1 && i + j + 2 <= n;
  return 2 * (i * n + j) + (down ? 1 : 0);
}

// Directions from p toward triangle (v0, v1, v2) against the solid angle of each of its n^2 sub-triangles.
void ExpectUniformOverSolidAngle(Point3 p, Point3 v0, Point3 v1, Point3 v2, uint64_t seed) {
  constexpr int n = 8;
  const auto sphere = SphericalTriangle::From(p, v0, v1, v2);
  ASSERT_TRUE(sphere.has_value());
  const auto at = [&](double b1, double b2) { return v0 + (v1 - v0) * float(b1) + (v2 - v0) * float(b2); };
  std::vector<double> observed(2 * n * n, 0), expected(2 * n * n, 0);
  double total = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      const double s = 1.0 / n;
      const auto up = SphericalTriangle::From(p, at(i * s, j * s), at((i + 1) * s, j * s), at(i * s, (j + 1) * s));
      total += expected[2 * (i * n + j)] = up ? up->SolidAngle() : 0.0;
      if (i + j + 2 > n) continue;
      const auto down =
          SphericalTriangle::From(p, at((i + 1) * s, j * s), at((i + 1) * s, (j + 1) * s), at(i * s, (j + 1) * s));
      total += expected[2 * (i * n + j) + 1] = down ? down->SolidAngle() : 0.0;
    }
  ASSERT_NEAR(total, sphere->SolidAngle(), 1e-6 * sphere->SolidAngle());
  for (double& e : expected) e *= kSamples / total;
  // Each direction meets the triangle's plane inside the triangle: solve p + t w = v0 + b1 e1 + b2 e2.
  const Vector3 e1 = v1 - v0, e2 = v2 - v0, normal = Cross(e1, e2);
  Rng rng(seed, 0);
  for (int s = 0; s < kSamples; ++s) {
    const Vector3 w = sphere->Sample(rng.Uniform2());
    ASSERT_NEAR(LengthSquared(w), 1.0f, 1e-5f);
    const double t = double(Dot(v0 - p, normal)) / Dot(w, normal);
    ASSERT_GT(t, 0);
    const Vector3 r = (p + w * float(t)) - v0;
    const double d = Dot(Cross(e1, e2), normal);
    const double b1 = Dot(Cross(r, e2), normal) / d, b2 = Dot(Cross(e1, r), normal) / d;
    ASSERT_GT(b1, -1e-3);
    ASSERT_GT(b2, -1e-3);
    ASSERT_LT(b1 + b2, 1 + 1e-3);
    observed[SubTriangle(b1, b2, n)] += 1;
  }
  const test::Chi2Result r = test::Chi2Test(observed, expected);
  EXPECT_GT(r.pValue, kSignificance) << "chi2 " << r.statistic << " dof " << r.degreesOfFreedom << "\n" << r.histograms;
}

TEST(Warps, SphericalTriangleIsUniformOverItsSolidAngle) {
  const Point3 v0{0, 0, 0}, v1{1, 0, 0}, v2{0.2f, 1, 0};
  ExpectUniformOverSolidAngle({0.3f, 0.3f, 1}, v0, v1, v2, 6);        // a light above the point
  ExpectUniformOverSolidAngle({0.4f, 0.3f, 0.02f}, v0, v1, v2, 7);    // nearly the whole hemisphere
  ExpectUniformOverSolidAngle({2, -1, 0.3f}, v0, v1, v2, 8);          // seen at a grazing angle, off to the side
  ExpectUniformOverSolidAngle({0.3f, 0.3f, 150}, v0, v1, v2, 9);      // small and far: about 2e-5 sr
}

TEST(Warps, SphericalTriangleSolidAngleMatchesClosedForms) {
  // An octant: the corners on the three axes subtend 4 pi / 8 from the origin.
  const auto octant = SphericalTriangle::From({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  ASSERT_TRUE(octant.has_value());
  EXPECT_NEAR(octant->SolidAngle(), M_PI / 2, 1e-9);
  // A far triangle: its area times the cosine over the squared distance.
  const auto far = SphericalTriangle::From({0, 0, 100}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  ASSERT_TRUE(far.has_value());
  EXPECT_NEAR(far->SolidAngle(), 0.5 / (100.0 * 100.0), 1e-3 * 0.5e-4);
  // A point in the triangle's plane sees no solid angle.
  EXPECT_FALSE(SphericalTriangle::From({5, 5, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}).has_value());
}

TEST(Warps, DiscreteCdfMatchesItsPmf) {
  const std::vector<double> weights = {0.0, 3.0, 1.0, 0.5, 0.0, 5.5};
  std::vector<double> cdf;
  double total = 0;
  for (double w : weights) cdf.push_back(total += w);
  for (double& c : cdf) c /= total;
  std::vector<double> observed(weights.size(), 0), expected(weights.size());
  for (size_t i = 0; i < weights.size(); ++i) expected[i] = kSamples * weights[i] / total;
  Rng rng(3, 0);
  std::vector<double> remappedHistogram(10, 0);
  for (int s = 0; s < kSamples; ++s) {
    const auto pick = SampleDiscreteCdf(cdf, rng.Uniform());
    ASSERT_TRUE(pick.has_value());
    ASSERT_NEAR(pick->pmf, weights[pick->index] / total, 1e-12);
    ASSERT_GE(pick->uRemapped, 0.0f);
    ASSERT_LT(pick->uRemapped, 1.0f);
    observed[pick->index] += 1;
    remappedHistogram[int(pick->uRemapped * 10)] += 1;
  }
  const test::Chi2Result r = test::Chi2Test(observed, expected);
  EXPECT_GT(r.pValue, kSignificance) << r.histograms;
  // The remapped number is again uniform, so it may drive a second decision.
  const test::Chi2Result u = test::Chi2Test(remappedHistogram, std::vector<double>(10, kSamples / 10.0));
  EXPECT_GT(u.pValue, kSignificance) << u.histograms;
  EXPECT_FALSE(SampleDiscreteCdf({}, 0.5f).has_value());
}

TEST(Warps, InvertUndoesSample) {
  Rng rng(4, 0);
  for (int s = 0; s < 100000; ++s) {
    const Point2 u = rng.Uniform2();
    const Point2 c = InvertCosineHemisphere(SampleCosineHemisphere(u).direction);
    ASSERT_NEAR(c.u, u.u, 2e-4f) << u.u << " " << u.v;
    ASSERT_NEAR(c.v, u.v, 2e-4f) << u.u << " " << u.v;
    const Point2 t = InvertUniformTriangle(SampleUniformTriangle(u));
    ASSERT_NEAR(t.u, u.u, 1e-5f);
    if (u.u > 1e-3f) {  // v is undefined at the apex b1 = b2 = 0
      ASSERT_NEAR(t.v, u.v, 1e-4f);
    }
  }
}

TEST(Warps, RngIsAPureFunctionOfSeedAndIndex) {
  Rng a(42, 7), b(42, 7), c(42, 8), d(43, 7);
  int sameAsNeighbour = 0, sameAsOtherSeed = 0;
  for (int i = 0; i < 1000; ++i) {
    const uint32_t x = a.NextU32();
    ASSERT_EQ(x, b.NextU32());
    sameAsNeighbour += x == c.NextU32();
    sameAsOtherSeed += x == d.NextU32();
  }
  EXPECT_LE(sameAsNeighbour, 1);
  EXPECT_LE(sameAsOtherSeed, 1);
}

TEST(Chi2, RejectsAWrongPdfAndAcceptsTheRightOne) {
  // The test's own power: uniform samples against a linear pdf must fail; against the uniform pdf pass.
  Rng rng(5, 0);
  std::vector<double> observed(20, 0), uniform(20, kSamples / 20.0), linear(20);
  for (int s = 0; s < kSamples; ++s) observed[std::min(19, int(rng.Uniform() * 20))] += 1;
  for (int i = 0; i < 20; ++i) linear[i] = kSamples * ((i + 1) * (i + 1) - i * i) / 400.0;
  EXPECT_GT(test::Chi2Test(observed, uniform).pValue, kSignificance);
  EXPECT_LT(test::Chi2Test(observed, linear).pValue, 1e-12);
  EXPECT_NEAR(test::RegularizedGammaQ(1.0, 2.0), std::exp(-2.0), 1e-12);  // Q(1, x) = e^-x
}

}  // namespace
}  // namespace pb
