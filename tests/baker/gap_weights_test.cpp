// Weighing the paths gathered in narrow gaps against the photons (baker/3_gap_weights.h):
//  - where the gathered light is noisy (16 paths, one in 20 finding light: a standard error of 1.09 times the value)
//    and the photons read the truth within 3%, the weight falls below 0.2 and the mix's RMS error is under 0.4 of
//    the gathered light's;
//  - where the photons read twice the truth (the gap's bias) and the gathered light is 5% noisy, the weight stays
//    above 0.95 and the mix is as good as the gathered light;
//  - a surface with no narrow-gap vertex keeps the gathered light (weight 1), and a weight of 1 gives the gathered
//    estimate bit for bit;
//  - in a bake (the grey slab 3 mm over a floor, test::WriteGapScene), the vertices mixed after the estimate read
//    what the field then says at the same points, bit for bit; the report counts the narrow-gap vertices and
//    their surfaces, with their mean weight;
//  - a surface smaller than its kernel, gathered at every point (the slab's sides), is weighed as the narrow gaps
//    are: the field holds its weight, and the report counts it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "baker/1_trace_photons.h"
#include "baker/bake.h"
#include "baker/2_bin_photons.h"
#include "baker/3_gap_weights.h"
#include "baker/3_irradiance_field.h"
#include "estimators/rng.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

NoisyIrradiance Grey(double value, double sigma) {
  return {Rgb{float(value), float(value), float(value)}, value > 0 ? sigma / value : 0.0};
}

// The truth along a surface's narrow-gap vertices [W/m^2]: 10 +- 5.
double Truth(int v) { return 10 + 5 * std::sin(0.1 * v); }

struct Errors {
  double gathered = 0, mixed = 0;  // RMS over the vertices [W/m^2]
};
Errors ErrorsOf(const std::vector<GapPair>& pairs, const GapWeight& w) {
  Errors e;
  for (size_t v = 0; v < pairs.size(); ++v) {
    const double t = Truth(int(v));
    const double g = Luminance(pairs[v].gathered.irradiance);
    const double mixed = Luminance(Blend(pairs[v].gathered, pairs[v].photons, w.alpha).value.irradiance);
    e.gathered += (g - t) * (g - t), e.mixed += (mixed - t) * (mixed - t);
  }
  return {std::sqrt(e.gathered / double(pairs.size())), std::sqrt(e.mixed / double(pairs.size()))};
}

// 200 narrow-gap vertices of surface 0, each gathered by 16 paths of which one in 20 finds 20 times the truth
// (mean the truth, a standard error of 1.09 times it), with the variance the paths themselves show (0 where none
// found light, as in a bake); the photons read the truth within 3%.
std::vector<GapPair> NoisyGatherOverFaithfulPhotons() {
  Rng rng(7, 1);
  std::vector<GapPair> pairs;
  for (int v = 0; v < 200; ++v) {
    const double t = Truth(v);
    double sum = 0, sum2 = 0;
    for (int k = 0; k < 16; ++k) {
      const double path = rng.Uniform() < 0.05f ? 20 * t : 0.0;
      sum += path, sum2 += path * path;
    }
    const double g = sum / 16, variance = (sum2 - 16 * g * g) / 15 / 16;
    const double p = t * (1 + 0.03 * (2 * rng.Uniform() - 1) * std::sqrt(3.0));
    pairs.push_back({0, Grey(g, std::sqrt(std::max(variance, 0.0))), Grey(p, 0.03 * t), {}});
  }
  return pairs;
}

// The photons read twice the truth; the gathered light is within 5% of it.
std::vector<GapPair> FaithfulGatherUnderBiasedPhotons() {
  Rng rng(7, 2);
  std::vector<GapPair> pairs;
  for (int v = 0; v < 200; ++v) {
    const double t = Truth(v), g = t * (1 + 0.05 * (2 * rng.Uniform() - 1) * std::sqrt(3.0));
    pairs.push_back({0, Grey(g, 0.05 * t), Grey(2 * t, 0.01 * t), {}});
  }
  return pairs;
}

TEST(GapWeights, NoisyGatheredLightFallsToFaithfulPhotons) {
  const std::vector<GapPair> pairs = NoisyGatherOverFaithfulPhotons();
  const GapWeight w = LearnGapWeights(pairs, 1)[0];
  const Errors e = ErrorsOf(pairs, w);
  std::printf("alpha %.3f, RMS error %.3f gathered, %.3f mixed\n", w.alpha, e.gathered, e.mixed);
  EXPECT_LT(w.alpha, 0.2);
  EXPECT_LT(e.mixed, 0.4 * e.gathered);
}

TEST(GapWeights, TheGapsBiasKeepsTheGatheredLight) {
  const std::vector<GapPair> pairs = FaithfulGatherUnderBiasedPhotons();
  const GapWeight w = LearnGapWeights(pairs, 1)[0];
  const Errors e = ErrorsOf(pairs, w);
  EXPECT_GT(w.alpha, 0.95);
  EXPECT_LT(e.mixed, 1.05 * e.gathered);
  double truth2 = 0;
  for (int v = 0; v < 200; ++v) truth2 += Truth(v) * Truth(v) / 200;
  EXPECT_NEAR(w.bias, std::sqrt(truth2), 0.03 * std::sqrt(truth2)) << "the photons' RMS bias: the truth's RMS";
}

TEST(GapWeights, ASurfaceWithoutNarrowGapsKeepsTheGatheredLight) {
  std::vector<GapPair> pairs = NoisyGatherOverFaithfulPhotons();
  pairs.push_back({});  // a vertex in no narrow gap
  const std::vector<GapWeight> w = LearnGapWeights(pairs, 3);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_LT(w[0].alpha, 0.2);
  EXPECT_EQ(w[1].alpha, 1);
  EXPECT_EQ(w[2].bias, 0);
  const NoisyIrradiance g = Grey(3, 1), p = Grey(4, 0.1);
  const BlendedGap whole = Blend(g, p, 1);
  EXPECT_EQ(whole.value.irradiance.g, g.irradiance.g);
  EXPECT_EQ(whole.value.relativeNoise, g.relativeNoise);
  EXPECT_EQ(whole.photonVariance, 0);
  const BlendedGap quarter = Blend(g, p, 0.25);
  EXPECT_FLOAT_EQ(quarter.value.irradiance.g, 0.25f * 3 + 0.75f * 4);
  EXPECT_NEAR(quarter.gatheredVariance, 0.0625 * 1, 1e-9);
  EXPECT_NEAR(quarter.photonVariance, 0.5625 * 0.01, 1e-9);
  EXPECT_FLOAT_EQ(quarter.photonPart.g, 3.0f);
}

TEST(GapWeights, MixedVerticesReadWhatTheFieldSays) {
  const test::TracedScene scene(test::WriteGapScene(test::TempDirectory("gap-weights")));
  const PhotonStore hits = TracePhotons(scene, {200'000, 1, kDefaultMaxBounces, false}, Log(true));
  const SurfaceBins bins = BinPhotons(scene.surfaces, hits);
  FieldSettings settings;
  settings.estimator.bandwidth = 0.1f;
  settings.direct = {DirectLight::kSampled, 16};
  settings.gaps.paths = 16;
  settings.gaps.smallArea = 1;  // the slab's sides (0.004 m^2) too, below h^2
  StageClock clock;
  IrradianceField field = BuildIrradianceField(scene, bins, settings, clock);
  const SplitMesh mesh = SplitBySurface(scene.scene, scene.surfaces);
  BakedMesh baked = EstimateIrradiance(field, mesh, Log(true), /*withNoise=*/true);
  size_t narrow = 0;
  for (const GapPair& pair : baked.gapPairs) narrow += pair.Present();
  ASSERT_GT(narrow, 50u) << "the floor under the slab, the slab's underside";
  WeighGatheredPaths(field, baked);
  EXPECT_TRUE(baked.gapPairs.empty());
  double lowest = 1;
  for (uint32_t s = 0; s < scene.surfaces.surfaces.size(); ++s) lowest = std::min(lowest, field.GapWeightOf(s).alpha);
  EXPECT_LT(lowest, 1) << "some surface's gathered light is mixed: the comparison below can fail";
  size_t sides = 0;  // the slab's four sides: 0.4 m x 1 cm, every one of their vertices gathered and weighed
  for (uint32_t s = 0; s < scene.surfaces.surfaces.size(); ++s)
    sides += std::abs(scene.surfaces.surfaces[s].area - 0.004) < 1e-4 && field.GapWeightOf(s).vertices == 4;
  EXPECT_EQ(sides, 4u);
  const BakedMesh again = EstimateIrradiance(field, mesh, Log(true));
  for (size_t v = 0; v < baked.irradiance.size(); ++v) {
    ASSERT_EQ(baked.irradiance[v].r, again.irradiance[v].r) << "vertex " << v;
    ASSERT_EQ(baked.irradiance[v].g, again.irradiance[v].g) << "vertex " << v;
    ASSERT_EQ(baked.irradiance[v].b, again.irradiance[v].b) << "vertex " << v;
  }
}

BakeReport::NarrowGaps WeighedInTheGapScene(float smallArea) {
  const std::string dir = test::TempDirectory("gap-weights-report");
  BakeOptions o;
  o.scenePath = test::WriteGapScene(dir);
  o.outputPath = dir + "/out.ply";
  o.photons = 200'000;
  o.estimator.bandwidth = 0.1f;
  o.direct.samples = 16;
  o.gaps.paths = 16;
  o.gaps.smallArea = smallArea;
  o.quiet = true;
  return BakeMesh(o, Log(true)).report.narrowGaps;
}

TEST(GapWeights, TheReportCountsTheNarrowGapsAndTheirWeight) {
  const BakeReport::NarrowGaps g = WeighedInTheGapScene(0);
  EXPECT_GT(g.vertices, 50u) << "the floor under the slab, the slab's underside, the ceiling over the light";
  EXPECT_GE(g.surfaces, 3u);
  EXPECT_GT(g.meanWeight, 0);
  EXPECT_LE(g.meanWeight, 1);
}

// The slab's four sides, smaller than their kernel (0.004 m^2 against h^2 = 0.01 m^2), gathered at each of their
// four vertices, are weighed as the narrow gaps are: four surfaces and 16 vertices more.
TEST(GapWeights, SurfacesSmallerThanTheirKernelAreWeighedToo) {
  const BakeReport::NarrowGaps gaps = WeighedInTheGapScene(0), sides = WeighedInTheGapScene(1);
  EXPECT_EQ(sides.surfaces, gaps.surfaces + 4);
  EXPECT_EQ(sides.vertices, gaps.vertices + 16);
}

}  // namespace
}  // namespace pb
