// Direct light sampled at the points (--direct sampled; estimators/light_sampler.h, baker/3_irradiance_field.h).
//  - Closed form: a 1 x 1 m light of radiance 1 at 1 m over a floor. At 400 floor points the sampled E_d matches
//    Lambert's polygon formula within 5 of its own predicted standard errors; the mean of z^2 is at most 1.5 (the
//    prediction is the samples' standard error as if independent, which stratification only lowers), and the
//    mean relative error over all points is within 5 standard errors of that mean, so the sampler is unbiased.
//  - Occlusion: under an occluder, a floor point in the umbra reads exactly the photons' part, bit for bit, and
//    the direct part there is 0; in the open it is not.
//  - The sum: on the Cornell box, each large surface's mean H over its vertices agrees between --direct sampled
//    and --direct photons within 2%: the photons' density estimates of those means are within ~0.5% (1M photons,
//    hundreds of vertices each), the kernel's smoothing moves light along a surface but keeps its integral, and
//    the direct samples (64 per vertex) add ~1% per vertex, averaged away.
//  - Determinism: a sampled bake writes the same bytes on 1 and 2 threads.
#include <gtest/gtest.h>

#include <cmath>
#include <array>
#include <map>
#include <string>

#include "baker/1_trace_photons.h"
#include "baker/2_bin_photons.h"
#include "baker/3_irradiance_field.h"
#include "baker/bake.h"
#include "estimators/light_sampler.h"
#include "tests/lambert.h"
#include "tests/ply_reader.h"
#include "tests/staged_bake.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

TEST(Direct, SampledMatchesLambertWithinItsPredictedNoise) {
  const test::TracedScene prepared(
      test::WriteSquareLightOverFloor(test::TempDirectory("direct-lambert"), 1.0f, 1.0f, 1.0f, 4.0f, 4));
  const LightSampler sampler(prepared.scene, prepared.lights, *prepared.rays);
  constexpr int kSide = 20;
  constexpr uint32_t kSamples = 16;
  double z2 = 0, relativeSum = 0, relativeVariance = 0;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j) {
      const double x = -1.9 + 3.8 * (i + 0.5) / kSide, z = -1.9 + 3.8 * (j + 0.5) / kSide;
      Rng rng(7, uint64_t(i * kSide + j));
      const DirectSample d = sampler.Irradiance({float(x), 0, float(z)}, {0, 1, 0}, kSamples, rng);
      const double exact = test::SquareLightIrradiance(x, z), sigma = d.relativeNoise * d.irradiance.g;
      ASSERT_GT(sigma, 0) << x << ", " << z;
      EXPECT_NEAR(d.irradiance.g, exact, 5 * sigma) << x << ", " << z;
      z2 += std::pow((d.irradiance.g - exact) / sigma, 2);
      relativeSum += d.irradiance.g / exact - 1;
      relativeVariance += std::pow(sigma / exact, 2);
    }
  const int n = kSide * kSide;
  std::printf("mean z^2 %.3f, mean relative error %.2e (standard error %.2e)\n", z2 / n, relativeSum / n,
              std::sqrt(relativeVariance) / n);
  EXPECT_LE(z2 / n, 1.5);
  EXPECT_LE(std::fabs(relativeSum / n), 5 * std::sqrt(relativeVariance) / n);
}

// A grey floor y = 0 over [-1, 1]^2 under a 0.2 m light at y = 1 (radiance 50), a black 0.4 m occluder at y = 0.5
// (the umbra is |x|, |z| < 0.3) and a grey wall at x = 1.2 that sends light back under the occluder.
std::string WriteShadowWithWall(const std::string& dir) {
  test::WriteText(dir + "/s.mtl", "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl black\nKd 0 0 0\n"
                                   "newmtl lamp\nKd 0 0 0\nKe 50 50 50\n");
  test::WriteText(dir + "/s.obj",
                  "mtllib s.mtl\nusemtl grey\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nf 1 2 3 4\n"
                  "v 1.2 0 -1\nv 1.2 0 1\nv 1.2 1.5 1\nv 1.2 1.5 -1\nf 5 6 7 8\n"
                  "usemtl black\nv -0.2 0.5 -0.2\nv -0.2 0.5 0.2\nv 0.2 0.5 0.2\nv 0.2 0.5 -0.2\nf 9 10 11 12\n"
                  "usemtl lamp\nv -0.1 1 -0.1\nv 0.1 1 -0.1\nv 0.1 1 0.1\nv -0.1 1 0.1\nf 13 14 15 16\n");
  return dir + "/s.obj";
}

TEST(Direct, APointInFullShadowReadsExactlyTheIndirectPart) {
  const test::TracedScene prepared(WriteShadowWithWall(test::TempDirectory("direct-shadow")));
  const PhotonStore photons = TracePhotons(prepared, {200'000, 1, kDefaultMaxBounces, false}, Log(true));
  const SurfaceBins bins = BinPhotons(prepared.surfaces, photons);
  StageClock clock;
  EstimatorSettings settings;
  settings.bandwidth = 0.1f;
  const IrradianceField field =
      BuildIrradianceField(prepared, bins, settings, false, clock, {DirectLight::kSampled, 64}, 1);
  const DirectIrradiance direct(prepared, 64, 1);
  const uint32_t floor = prepared.surfaces.surfaceOfTriangle[0];
  const SurfaceChart& chart = prepared.surfaces.surfaces[floor].chart;
  const auto pointAt = [&](float x, float z) {
    SurfacePoint p;
    p.surface = floor;
    p.position = {x, 0, z};
    p.normal = chart.frame.n;
    p.uv = chart.ToUv(p.position);
    return p;
  };
  for (float x : {-0.25f, 0.0f, 0.2f})
    for (float z : {-0.2f, 0.1f, 0.25f}) {
      const SurfacePoint p = pointAt(x, z);
      EXPECT_EQ(Luminance(direct.At(p)), 0.0) << x << ", " << z;
      const Rgb total = field.Irradiance(p), indirect = field.Photons().At(p);
      EXPECT_TRUE(total == indirect) << x << ", " << z;
      EXPECT_GT(Luminance(indirect), 0.0) << "the grey wall bounces light into the umbra";
    }
  for (float x : {-0.8f, 0.8f}) EXPECT_GT(Luminance(direct.At(pointAt(x, 0.8f))), 0.0) << "in the open";
}

// Mean H (luminance) over the vertices whose normal is one of the six axis directions, by direction.
std::map<int, double> MeansByFacing(const test::PlyData& ply) {
  std::map<int, std::pair<double, size_t>> sums;
  const auto& q = ply.vertex.at("quality");
  for (size_t v = 0; v < ply.VertexCount(); ++v)
    for (int axis = 0; axis < 3; ++axis) {
      const double c = ply.vertex.at(std::string("n") + "xyz"[axis])[v];
      if (std::fabs(c) < 0.99) continue;
      auto& [sum, n] = sums[c > 0 ? axis + 1 : -(axis + 1)];
      sum += q[v], ++n;
    }
  std::map<int, double> means;
  for (const auto& [facing, sn] : sums)
    if (sn.second >= 100) means[facing] = sn.first / double(sn.second);
  return means;
}

test::PlyData BakeBox(const std::string& name, DirectLight mode, unsigned threads) {
  BakeOptions o;
  o.scenePath = PB_SOURCE_DIR "/data/box/box.obj";
  o.outputPath = test::TempDirectory(name) + "/box.ply";
  o.photons = 1'000'000;
  o.estimator.bandwidth = 0.02f;
  o.direct.mode = mode;
  o.threads = threads;
  Bake(o, Log(true));
  return test::ReadPly(o.outputPath);
}

TEST(Direct, SampledAndPhotonsAgreeInTheMeanOnTheBox) {
  const std::map<int, double> photons = MeansByFacing(BakeBox("direct-box-photons", DirectLight::kPhotons, 0));
  const std::map<int, double> sampled = MeansByFacing(BakeBox("direct-box-sampled", DirectLight::kSampled, 0));
  ASSERT_EQ(photons.size(), 5u) << "floor, ceiling and three walls; the front is open";
  for (const auto& [facing, mean] : photons) {
    std::printf("facing %+d: photons %.4f, sampled %.4f W/m^2\n", facing, mean, sampled.at(facing));
    EXPECT_NEAR(sampled.at(facing) / mean, 1.0, 0.02) << "facing " << facing;
  }
}

TEST(Direct, ASampledBakeIsTheSameOnAnyThreadCount) {
  const test::PlyData one = BakeBox("direct-threads-1", DirectLight::kSampled, 1);
  const test::PlyData two = BakeBox("direct-threads-2", DirectLight::kSampled, 2);
  EXPECT_TRUE(one.vertex.at("irradiance_r") == two.vertex.at("irradiance_r"));
  EXPECT_TRUE(one.vertex.at("irradiance_g") == two.vertex.at("irradiance_g"));
  EXPECT_TRUE(one.vertex.at("irradiance_b") == two.vertex.at("irradiance_b"));
}

}  // namespace
}  // namespace pb
