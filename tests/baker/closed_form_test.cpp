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
#include "estimators/kernels.h"
#include "tests/lambert.h"
#include "tests/ply_reader.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

using test::V3;
using test::LambertPolygonIrradiance;

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
  const double h = *o.estimator.bandwidth, kernelSquareIntegral = 4.0 / (3.0 * M_PI * h * h);
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

// ---- Relative RMSE over all floor vertices, edges and corners included, for each estimator at its defaults ----
//
// The expected error of each estimator at each vertex is computed from the exact E by quadrature, then
// averaged: predicted relative MSE = mean over vertices of (bias^2 + variance) / E^2, where, for photons of
// flux phi landing with density E / phi,
//   kernel:    E[H] = integral_floor W(x,y) E(y) dy,    Var H = phi integral_floor W^2 E dy, with W the local
//              linear fit's weight K(x-y) (1 - c.(y-x)) / (m0 - c.m1) (KernelMoments; K / M(x) when renormalised)
//   knn:       as kernel with the uniform kernel of radius r(x), pi r^2 E(x) / phi = k; Var H / H^2 = 1/(k-2)
//   histogram: E[H] = mean of E over x's bucket on the floor, Var H = phi E[H] / area; x sits on a bucket
//              corner, so the largest of the four candidate buckets' errors is used (an upper bound).
// The measured relative RMSE must lie within [0.85, 1.15] of the prediction (kernel, knn), or below 1.15 of
// the bound (histogram). Neighbouring vertices share photons, so ~1/4 of the 6561 are independent; the
// measured MSE then fluctuates by ~sqrt(2 / 1600) = 3.5%, and 15% on the RMSE is over 8 of those.
struct Floor {
  static constexpr double kHalf = 2.0;
  static bool Inside(double x, double z) { return std::fabs(x) <= kHalf && std::fabs(z) <= kHalf; }
};

double Exact(double x, double z) { return test::SquareLightIrradiance(x, z); }

struct Moments {
  double mean = 0, variance = 0;
};

// Kernel-weighted moments over the floor, by the midpoint rule in polar coordinates about (x, z). With
// `localLinear`, the weights are the local linear fit's (kernel_estimator.h): w = K(t) (1 - c.t) / (m0 - c.m1),
// with m0, m1, m2 the kernel's moments over the floor and c = m2^-1 m1 (0 inside, where it is renormalisation's).
Moments KernelMoments(double x, double z, Kernel kernel, double h, double phi, bool localLinear) {
  constexpr int kRings = 24, kAngles = 96;
  struct Node {
    double dx, dz, k, area, e;  // offset [m], kernel [1/m^2], quadrature area [m^2], Lambert's E
  };
  std::vector<Node> nodes;
  double m0 = 0, mx = 0, mz = 0, sxx = 0, sxz = 0, szz = 0;
  for (int i = 0; i < kRings; ++i) {
    const double r = (i + 0.5) * h / kRings, k = KernelProfile(kernel, r / h) / (h * h);
    for (int j = 0; j < kAngles; ++j) {
      const double a = (j + 0.5) * 2 * M_PI / kAngles, dx = r * std::cos(a), dz = r * std::sin(a);
      if (!Floor::Inside(x + dx, z + dz)) continue;
      const double area = r * (h / kRings) * (2 * M_PI / kAngles), w = k * area;
      nodes.push_back({dx, dz, k, area, Exact(x + dx, z + dz)});
      m0 += w, mx += w * dx, mz += w * dz, sxx += w * dx * dx, sxz += w * dx * dz, szz += w * dz * dz;
    }
  }
  double cx = 0, cz = 0;
  const double det = sxx * szz - sxz * sxz;
  if (localLinear && std::fabs(mx) + std::fabs(mz) > 1e-9 * m0 * h && det > 0)
    cx = (szz * mx - sxz * mz) / det, cz = (sxx * mz - sxz * mx) / det;
  const double denominator = m0 - (cx * mx + cz * mz);
  double first = 0, second = 0;
  for (const Node& n : nodes) {
    const double w = n.k * (1 - (cx * n.dx + cz * n.dz)) / denominator;  // per unit area
    first += w * n.e * n.area;
    second += w * w * n.e * n.area;
  }
  return {first, phi * second};
}

Moments BucketMoments(double x0, double z0, double side, double phi) {
  constexpr int kSteps = 16;
  double area = 0, sum = 0;
  for (int i = 0; i < kSteps; ++i)
    for (int j = 0; j < kSteps; ++j) {
      const double px = x0 + (i + 0.5) * side / kSteps, pz = z0 + (j + 0.5) * side / kSteps;
      if (!Floor::Inside(px, pz)) continue;
      area += side * side / (kSteps * kSteps), sum += Exact(px, pz) * side * side / (kSteps * kSteps);
    }
  return {sum / area, phi * (sum / area) / area};
}

double RelativeMse(const Moments& m, double exact) {
  return ((m.mean - exact) * (m.mean - exact) + m.variance) / (exact * exact);
}

double PredictedRelativeMse(const EstimatorSettings& e, double x, double z, double phi) {
  const double exact = Exact(x, z);
  switch (e.kind) {
    case EstimatorKind::kKernel:
      return RelativeMse(KernelMoments(x, z, e.kernel, *e.bandwidth, phi, e.localLinear), exact);
    case EstimatorKind::kNearest: {
      const double r = std::sqrt(e.neighbours * phi / (M_PI * exact));
      Moments m = KernelMoments(x, z, Kernel::kUniform, r, phi, false);
      m.variance = m.mean * m.mean / (e.neighbours - 2.0);
      return RelativeMse(m, exact);
    }
    case EstimatorKind::kHistogram: {
      double worst = 0;
      for (double dx : {-1.0, 0.0})
        for (double dz : {-1.0, 0.0}) {
          const double side = *e.bandwidth, x0 = x + dx * side, z0 = z + dz * side;
          if (!Floor::Inside(x0 + side / 2, z0 + side / 2)) continue;
          worst = std::max(worst, RelativeMse(BucketMoments(x0, z0, side, phi), exact));
        }
      return worst;
    }
  }
  return 0;
}

class ClosedFormEveryEstimator : public testing::TestWithParam<EstimatorSettings> {};

TEST_P(ClosedFormEveryEstimator, RelativeRmseOverAllFloorVerticesMatchesItsPrediction) {
  const std::string dir = test::TempDirectory("closed-form-" + EstimatorName(GetParam().kind));
  BakeOptions o;
  o.direct.mode = DirectLight::kPhotons;  // the photons' noise model: the direct light from photons too
  o.scenePath = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 80);
  o.outputPath = dir + "/out.ply";
  o.photons = 1'000'000;
  o.estimator = GetParam();
  Bake(o, Log(true));
  const test::PlyData ply = test::ReadPly(o.outputPath);
  const double phi = M_PI / double(o.photons);
  double measured = 0, predicted = 0;
  int n = 0;
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    const double x = ply.vertex.at("x")[v], z = ply.vertex.at("z")[v];
    if (ply.vertex.at("y")[v] != 0.0) continue;
    const double exact = Exact(x, z), H = ply.vertex.at("irradiance_g")[v];
    measured += (H - exact) * (H - exact) / (exact * exact);
    predicted += PredictedRelativeMse(GetParam(), x, z, phi);
    ++n;
  }
  ASSERT_EQ(n, 81 * 81);
  const double measuredRmse = std::sqrt(measured / n), predictedRmse = std::sqrt(predicted / n);
  RecordProperty("relative_rmse", std::to_string(measuredRmse));
  EXPECT_LT(measuredRmse, 1.15 * predictedRmse);
  if (GetParam().kind != EstimatorKind::kHistogram) {
    EXPECT_GT(measuredRmse, 0.85 * predictedRmse);
  }
  std::printf("%s: relative RMSE %.4f, predicted %.4f\n", EstimatorName(GetParam().kind).c_str(), measuredRmse,
              predictedRmse);
}

INSTANTIATE_TEST_SUITE_P(Defaults, ClosedFormEveryEstimator,
                         testing::Values(EstimatorSettings{EstimatorKind::kKernel},
                                         EstimatorSettings{EstimatorKind::kHistogram},
                                         EstimatorSettings{EstimatorKind::kNearest}),
                         [](const testing::TestParamInfo<EstimatorSettings>& info) { return EstimatorName(info.param.kind); });

}  // namespace
}  // namespace pb

namespace pb {
namespace {

// ---- Local linear estimation at the floor's edges (estimators/kernel_estimator.h) ----
//
// A 1 x 1 m light at 1 m over a 2 x 2 m black floor: at the floor's edges E falls outward (d ln E / dx about -1.2
// there), so renormalisation reads high by about 0.34 h |grad E| / E, 4% at h = 0.1 m. The local linear fit is
// exact for linear E, leaving only the h^2 curvature term. Over the 76 edge vertices (corners excluded), at 2M
// photons, the mean relative error must be below 1% with it, and above 2% without (the bias it removes). Inside
// (more than h from the edges) the two bakes are the same bit for bit: the fit is the plain estimate there.
struct EdgeBake {
  std::vector<double> x, z, H;
};

EdgeBake BakeFloorEdges(const std::string& scene, bool localLinear) {
  BakeOptions o;
  o.direct.mode = DirectLight::kPhotons;  // the estimator's edges are under test: the direct light from photons
  o.scenePath = scene;
  o.outputPath = scene + (localLinear ? ".linear.ply" : ".renormalised.ply");
  o.photons = 2'000'000;
  o.estimator.bandwidth = 0.1f;
  o.estimator.localLinear = localLinear;
  Bake(o, Log(true));
  const test::PlyData ply = test::ReadPly(o.outputPath);
  EdgeBake b;
  for (size_t v = 0; v < ply.VertexCount(); ++v)
    if (ply.vertex.at("y")[v] == 0.0) {
      b.x.push_back(ply.vertex.at("x")[v]);
      b.z.push_back(ply.vertex.at("z")[v]);
      b.H.push_back(ply.vertex.at("irradiance_g")[v]);
    }
  return b;
}

// The mean of H / E - 1 over the edge vertices, corners excluded.
double EdgeBias(const EdgeBake& b) {
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < b.H.size(); ++i) {
    const bool onEdge = std::fabs(b.x[i]) > 0.999 || std::fabs(b.z[i]) > 0.999;
    const bool corner = std::fabs(b.x[i]) > 0.999 && std::fabs(b.z[i]) > 0.999;
    if (!onEdge || corner) continue;
    sum += b.H[i] / test::SquareLightIrradiance(b.x[i], b.z[i]) - 1;
    ++n;
  }
  EXPECT_EQ(n, 76);
  return sum / n;
}

TEST(ClosedForm, LocalLinearRemovesTheEdgesGradientBias) {
  const std::string scene = test::WriteSquareLightOverFloor(test::TempDirectory("local-linear"), 1.0f, 1.0f, 1.0f, 2.0f, 20);
  const EdgeBake linear = BakeFloorEdges(scene, true), renormalised = BakeFloorEdges(scene, false);
  EXPECT_LT(std::fabs(EdgeBias(linear)), 0.01) << "local linear";
  EXPECT_GT(EdgeBias(renormalised), 0.02) << "renormalisation's bias, which local linear removes";
  for (size_t i = 0; i < linear.H.size(); ++i)
    if (std::fabs(linear.x[i]) < 0.89 && std::fabs(linear.z[i]) < 0.89) {
      ASSERT_EQ(linear.H[i], renormalised.H[i]) << i;
    }
}

}  // namespace
}  // namespace pb
