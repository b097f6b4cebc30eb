// A curved light sampled by the solid angle its triangles project to (estimators/light_sampler.h): a small sphere
// (an icosahedron cut twice, 320 triangles, radius 5 cm, radiance 3) 1 m over a black floor, far enough that no
// part of it is sampled by solid angle. Its closed form is Lambert's polygon formula summed over the triangles that face the
// point (a convex light: none hides another).
//  - Irradiance: unbiased at 100 floor points (mean relative error within 5 standard errors), and its error a
//    fraction of the same sampler's by area (kCurvedSpread at infinity), which spends half its samples on the far
//    side.
//  - The one-sample path (SampleAreaLights, AreaLightPdf): chi-square of the triangles the samples land on against
//    AreaLightPdf integrated over each; every sample's pdf is AreaLightPdf's; the mean is Lambert's.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <vector>

#include "estimators/light_sampler.h"
#include "tests/chi2.h"
#include "tests/grid_error.h"
#include "tests/lambert.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

constexpr double kRadius = 0.05, kHeight = 1.0, kRadiance = 3.0;

// The sphere's triangles: an icosahedron's faces (about the origin, unit radius), each cut in four twice and its
// corners pushed out onto the sphere; counter-clockwise seen from outside.
using Triangle = std::array<test::V3, 3>;
const std::vector<Triangle>& Triangles() {
  static const std::vector<Triangle> triangles = [] {
    const double g = (1 + std::sqrt(5.0)) / 2;
    const std::vector<test::V3> c = {{-1, g, 0}, {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                                     {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
    const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9},  {5, 11, 4},
                              {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6},  {3, 6, 8},
                              {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    std::vector<Triangle> t;
    for (const auto& f : faces) t.push_back({test::Unit(c[size_t(f[0])]), test::Unit(c[size_t(f[1])]), test::Unit(c[size_t(f[2])])});
    for (int level = 0; level < 2; ++level) {
      std::vector<Triangle> finer;
      const auto middle = [](test::V3 a, test::V3 b) { return test::Unit({a.x + b.x, a.y + b.y, a.z + b.z}); };
      for (const Triangle& f : t) {
        const test::V3 ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
        finer.insert(finer.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
      }
      t = finer;
    }
    for (Triangle& f : t)
      for (test::V3& p : f) p = {kRadius * p.x, kHeight + kRadius * p.y, kRadius * p.z};
    return t;
  }();
  return triangles;
}

std::string WriteSphereOverFloor() {
  const std::string dir = test::TempDirectory("curved-light");
  test::WriteText(dir + "/scene.mtl", fmt::format("newmtl black\nKd 0 0 0\nnewmtl light\nKd 0 0 0\nKe {0} {0} {0}\n",
                                                  kRadiance));
  // Floor 4 x 4 m facing +y: counter-clockwise seen from above.
  std::string obj = "mtllib scene.mtl\nusemtl black\nv -2 0 2\nv 2 0 2\nv 2 0 -2\nv -2 0 -2\nf 1 2 3 4\nusemtl light\n";
  for (const Triangle& f : Triangles())
    obj += fmt::format("v {:.9f} {:.9f} {:.9f}\nv {:.9f} {:.9f} {:.9f}\nv {:.9f} {:.9f} {:.9f}\nf -3 -2 -1\n", f[0].x, f[0].y,
                       f[0].z, f[1].x, f[1].y, f[1].z, f[2].x, f[2].y, f[2].z);
  test::WriteText(dir + "/scene.obj", obj);
  return dir + "/scene.obj";
}

const test::TracedScene& Scene() {
  static const test::TracedScene scene(WriteSphereOverFloor());
  return scene;
}

// Lambert's formula over the triangles whose front sees x (the floor's normal +y).
double Exact(test::V3 x) {
  double e = 0;
  for (const Triangle& f : Triangles()) {
    const test::V3 normal = test::CrossD(test::Sub(f[1], f[0]), test::Sub(f[2], f[0]));
    if (test::DotD(normal, test::Sub(x, f[0])) > 0) e += test::LambertPolygonIrradiance(x, {0, 1, 0}, {f[0], f[1], f[2]}, kRadiance);
  }
  return e;
}

TEST(CurvedLight, TheTrianglesAreWoundOutward) {
  for (const Triangle& f : Triangles()) {
    const test::V3 centre = {(f[0].x + f[1].x + f[2].x) / 3, (f[0].y + f[1].y + f[2].y) / 3 - kHeight,
                             (f[0].z + f[1].z + f[2].z) / 3};
    EXPECT_GT(test::DotD(test::CrossD(test::Sub(f[1], f[0]), test::Sub(f[2], f[0])), centre), 0);
  }
}

// Measured: RMS relative error 9.1% by projected solid angle, 19.8% by area, at 16 rays a point.
TEST(CurvedLight, ProjectedSolidAngleSamplingIsUnbiasedAndBeatsArea) {
  const test::TracedScene& s = Scene();
  const auto rmsError = [&](float curvedSpread) {
    const LightSampler sampler(s.scene, s.lights, *s.rays, LightSampler::kTreeLights, LightSampler::kSolidAngleFrom,
                               curvedSpread);
    return test::GridRmsError(sampler, 10, -1, 1, 0, 16, 5, Exact);
  };
  const double byProjection = rmsError(LightSampler::kCurvedSpread), byArea = rmsError(INFINITY);
  std::printf("a small sphere: RMS relative error %.4f by projected solid angle, %.4f by area\n", byProjection, byArea);
  EXPECT_LT(byProjection, 0.5 * byArea);
}

TEST(CurvedLight, OneSampleDrawsMatchTheirPdf) {
  const test::TracedScene& s = Scene();
  const LightSampler sampler(s.scene, s.lights, *s.rays);
  const Point3 p{0.4f, 0, -0.3f};
  const Normal3 n{0, 1, 0};
  LightSampler::OneSampleScratch scratch;
  // Each light triangle's probability: AreaLightPdf cos(theta_y) / d^2 integrated over it (the midpoint rule on
  // 16^2 sub-triangles' centroids; the integrand is smooth on one).
  std::unordered_map<uint32_t, size_t> cellOf;
  std::vector<double> probability;
  for (const Light& light : s.lights)
    for (uint32_t t : light.triangles) {
      constexpr int kSub = 16;
      double q = 0;
      const double dA = 0.5 * Length(s.scene.AreaVector(t)) / (kSub * kSub);
      for (int i = 0; i < kSub; ++i)
        for (int j = 0; i + j < kSub; ++j)
          for (int up = 0; up < (i + j + 1 < kSub ? 2 : 1); ++up) {
            const float b1 = (float(i) + (up ? 2.0f : 1.0f) / 3) / kSub, b2 = (float(j) + (up ? 2.0f : 1.0f) / 3) / kSub;
            const Point3 y = s.scene.PointAt(t, b1, b2);
            const Vector3 d = y - p;
            const double d2 = LengthSquared(d), cosY = -Dot(d, s.scene.FrontNormal(t)) / std::sqrt(d2);
            if (cosY > 0) q += sampler.AreaLightPdf(p, n, t, y, scratch) * cosY / d2 * dA;
          }
      cellOf[t] = probability.size();
      probability.push_back(q);
    }
  double total = 0;
  for (double q : probability) total += q;
  EXPECT_NEAR(total, 1.0, 2e-3) << "every sample lands on the light";
  constexpr int kSamples = 200'000;
  std::vector<double> observed(probability.size(), 0.0), expected(probability.size());
  for (size_t k = 0; k < probability.size(); ++k) expected[k] = kSamples * probability[k] / total;
  double sum = 0, squares = 0;
  int grazing = 0, offPdf = 0;
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(23, uint64_t(i));
    const LightSampler::AreaSample a = sampler.SampleAreaLights(p, n, rng, scratch);
    ASSERT_GT(a.pdf, 0);
    sum += a.irradiance.g, squares += double(a.irradiance.g) * a.irradiance.g;
    const auto hit = s.rays->Intersect(p, a.from);
    if (!hit) {  // a direction that grazes the sphere's outline, rounded past it (about 1 in 100,000)
      ++grazing;
      continue;
    }
    ASSERT_EQ(cellOf.count(hit->triangle), 1u) << "a sample toward no light";
    ++observed[cellOf[hit->triangle]];
    const float pdf = sampler.AreaLightPdf(p, n, hit->triangle, p + a.from * hit->t, scratch);
    offPdf += std::abs(double(pdf) / a.pdf - 1) > 2e-3;
  }
  // A ray rounded across an edge between two triangles finds the neighbour, whose density differs near the outline.
  EXPECT_LE(grazing, 20);
  EXPECT_LE(offPdf, 20) << "a sample's pdf is AreaLightPdf's for its direction";
  const test::Chi2Result r = test::Chi2Test(observed, expected);
  std::printf("%d grazing, %d pdfs off by more than 0.2%%, chi2 p %.3g\n", grazing, offPdf, r.pValue);
  EXPECT_GT(r.pValue, 1e-3) << "chi2 " << r.statistic << " dof " << r.degreesOfFreedom << "\n" << r.histograms;
  const double mean = sum / kSamples, error = std::sqrt((squares / kSamples - mean * mean) / kSamples);
  EXPECT_NEAR(mean, Exact({p.x, p.y, p.z}), 5 * error);
}

}  // namespace
}  // namespace pb
