// Closed form: a 1 x 1 m square light of radiance L = 1 W/(m^2 sr), 1 m above a black (Kd 0) 4 x 4 m floor.
// The exact irradiance at a floor point is Lambert's polygon formula,
//   E(x) = (L / 2) * sum_i beta_i (n . unit(R_i x R_{i+1})),
// with R_i the unit vectors from x to the light's corners and beta_i the angle between consecutive R_i.
//
// Tolerances from the estimator's own noise: every photon carries phi = Phi / N (the floor is black, so
// nothing bounces), hence Var H(x) = phi E(x) integral(K_h^2) dA = phi E(x) * 4 / (3 pi h^2) for Epanechnikov.
// Each interior vertex must lie within 5 sigma of E (plus 0.5% for the kernel's smoothing bias,
// ~ h^2/8 * |lap E|/E < 0.1% here), and the mean relative error over all interior vertices must be < 1%.
#include <gtest/gtest.h>

#include <cmath>

#include "baker/bake.h"
#include "tests/ply_reader.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

struct V3 {
  double x, y, z;
};
V3 Sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 CrossD(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double DotD(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 Unit(V3 a) {
  const double l = std::sqrt(DotD(a, a));
  return {a.x / l, a.y / l, a.z / l};
}

// Irradiance [W/m^2] at x with normal n from a Lambertian polygon of radiance L [W/(m^2 sr)].
double LambertPolygonIrradiance(V3 x, V3 n, const std::vector<V3>& polygon, double L) {
  double sum = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const V3 a = Unit(Sub(polygon[i], x)), b = Unit(Sub(polygon[(i + 1) % polygon.size()], x));
    const double beta = std::acos(std::clamp(DotD(a, b), -1.0, 1.0));
    sum += beta * DotD(n, Unit(CrossD(a, b)));
  }
  return 0.5 * L * std::fabs(sum);
}

TEST(ClosedForm, LambertPolygonFormulaMatchesAKnownValue) {
  // Directly under the centre of a 1 x 1 light at height 1: E = 4 L (a / sqrt(1 + a^2)) atan(a / sqrt(1 + a^2))
  // with a = 0.5 (the standard closed form for a square, Howell's catalogue C-11 times pi).
  const std::vector<V3> light = {{-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5}};
  const double a = 0.5, s = a / std::sqrt(1 + a * a);
  EXPECT_NEAR(LambertPolygonIrradiance({0, 0, 0}, {0, 1, 0}, light, 1.0), 4 * s * std::atan(s), 1e-12);
}

TEST(ClosedForm, SquareLightOverBlackFloorMatchesLambert) {
  const std::string dir = test::TempDirectory("closed-form");
  BakeOptions o;
  o.scenePath = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 80);
  o.outputPath = dir + "/out.ply";
  o.photons = 2'000'000;
  o.estimator.bandwidth = 0.05f;
  const BakeReport report = Bake(o, Log(true));
  const test::PlyData ply = test::ReadPly(o.outputPath);

  const std::vector<V3> light = {{-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5}};
  const double phi = M_PI / double(o.photons);  // Phi = pi L A = pi W, split evenly
  const double h = o.estimator.bandwidth, kernelSquareIntegral = 4.0 / (3.0 * M_PI * h * h);
  double sumRelative = 0;
  int interior = 0, worstIndex = -1;
  double worstZ = 0;
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    const double x = ply.vertex.at("x")[v], y = ply.vertex.at("y")[v], z = ply.vertex.at("z")[v];
    if (y != 0.0 || std::fabs(x) > 2.0 - h || std::fabs(z) > 2.0 - h) continue;  // floor interior only
    const double exact = LambertPolygonIrradiance({x, 0, z}, {0, 1, 0}, light, 1.0);
    const double H = ply.vertex.at("irradiance_g")[v];
    const double sigma = std::sqrt(phi * exact * kernelSquareIntegral);
    const double zScore = std::fabs(H - exact) / (sigma + 0.001 * exact);
    if (zScore > worstZ) worstZ = zScore, worstIndex = int(v);
    EXPECT_LE(std::fabs(H - exact), 5 * sigma + 0.005 * exact) << "vertex " << v << " at (" << x << ", " << z << ")";
    sumRelative += (H - exact) / exact;
    ++interior;
  }
  ASSERT_GT(interior, 5000);
  EXPECT_LT(std::fabs(sumRelative / interior), 0.01) << "mean relative bias over " << interior << " vertices";
  EXPECT_EQ(report.trace.truncated, 0u);
  RecordProperty("worst_z", std::to_string(worstZ) + " at vertex " + std::to_string(worstIndex));
}

}  // namespace
}  // namespace pb
