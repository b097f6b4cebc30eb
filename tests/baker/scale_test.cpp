// The same light at any scale (issue 38): the box baked in millimetres, metres and kilometres (--scale 1e-3, 1,
// 1e3, with h scaled alike) reads the same irradiance, with sampled direct light and with photons alone: its
// lights are given by their radiance, so H, an integral of radiance over solid angle, does not change with scale. The photons follow the same streams at every scale, so the photon part differs by float rounding only;
// the direct samples' streams are keyed by chart positions, which differ, so each scale's mean over the 1,204
// vertices carries its own sampling noise (~0.1% here at 64 shadow rays). Tolerance 1%: an absolute 0.2 mm step
// of the shadow rays' start (fixed since) read the millimetre box 5% high, and a 4 mm floor 39%.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "baker/0_prepare_scene.h"
#include "baker/bake.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

// The mean over the box's vertices of H's green channel [W/m^2].
double MeanScaledIrradiance(double scale, DirectLight direct) {
  BakeOptions o;
  o.scenePath = PB_SOURCE_DIR "/data/box/box.obj";
  o.outputPath = test::TempDirectory("scale") + "/out.ply";
  o.photons = 200'000;
  o.scale = float(scale);
  o.autoBandwidth = false;
  o.estimator.bandwidth = float(0.05 * scale);
  o.direct.mode = direct;
  o.direct.samples = 64;
  const BakedMesh mesh = BakeMesh(o, Log(true)).mesh;
  double sum = 0;
  for (const Rgb& h : mesh.irradiance) sum += h.g;
  return sum / double(mesh.irradiance.size());
}

TEST(Scale, TheBoxReadsTheSameLightInMillimetresMetresAndKilometres) {
  for (const DirectLight direct : {DirectLight::kSampled, DirectLight::kPhotons}) {
    const double metres = MeanScaledIrradiance(1, direct);
    for (const double scale : {1e-3, 1e3})
      EXPECT_NEAR(MeanScaledIrradiance(scale, direct) / metres, 1.0, 0.01) << "scale " << scale << ", direct "
                                                                           << int(direct);
  }
}

// At the defaults (no h given: --h auto, and the cover lattice from the scene's diagonal) the box in millimetres
// and kilometres is the box in metres: each surface's h and covered area scale with it (h within 1%: the photons'
// positions differ by float rounding; covered areas within 2% of the floor's), and its mean H agrees as above.
TEST(Scale, AtTheDefaultsHAndCoversScaleWithTheScene) {
  const auto bake = [](double scale) {
    BakeOptions o;
    o.scenePath = PB_SOURCE_DIR "/data/box/box.obj";
    o.outputPath = test::TempDirectory("scale-defaults") + "/out.ply";
    o.photons = 200'000;
    o.scale = float(scale);
    o.direct.samples = 64;
    ApplySceneDefaults(o, {.photons = true});
    return BakeMesh(o, Log(true));
  };
  const BakeResult metres = bake(1);
  ASSERT_TRUE(metres.report.options.autoBandwidth);
  const double floor = metres.report.surfaces[0].area;
  for (const double scale : {1e-3, 1e3}) {
    const BakeResult scaled = bake(scale);
    ASSERT_EQ(scaled.report.surfaces.size(), metres.report.surfaces.size());
    for (size_t s = 0; s < metres.report.surfaces.size(); ++s) {
      const SurfaceReport &m = metres.report.surfaces[s], &x = scaled.report.surfaces[s];
      EXPECT_NEAR(x.bandwidth / scale / m.bandwidth, 1.0, 0.01) << "surface " << s << ", scale " << scale;
      EXPECT_NEAR(x.coveredArea / (scale * scale), m.coveredArea, 0.02 * floor) << "surface " << s << ", scale " << scale;
    }
    double sumM = 0, sumX = 0;
    for (size_t v = 0; v < metres.mesh.irradiance.size(); ++v)
      sumM += metres.mesh.irradiance[v].g, sumX += scaled.mesh.irradiance[v].g;
    EXPECT_NEAR(sumX / sumM, 1.0, 0.01) << "scale " << scale;
  }
}

// The same scene lit 10^28 times brighter reads 10^28 times the light with the same relative noise: its photons
// carry 10^22 W each, whose squares (10^44 W^2) overflowed the float noise sums, and the bake read noise NaN and
// traced to --max-photons (issue 39). With photons alone (so that the kernel's noise is the bake's), kernel
// estimator binned and not (--h auto, or h 0.1 m), the ratios agree to float rounding.
TEST(Scale, AFaintAndABlindingLightReadTheSameRelativeNoise) {
  const auto bake = [](float radiance, bool autoBandwidth) {
    BakeOptions o;
    o.scenePath = test::WriteSquareLightOverFloor(test::TempDirectory("blinding"), 0.5f, radiance, 1.0f, 4.0f, 20, 0.5f);
    o.outputPath = test::TempDirectory("blinding-out") + "/out.ply";
    o.photons = 100'000;
    o.direct.mode = DirectLight::kPhotons;
    o.autoBandwidth = autoBandwidth;
    o.estimator.bandwidth = 0.1f;
    return BakeMesh(o, Log(true));
  };
  for (const bool autoBandwidth : {false, true}) {
    const BakeResult faint = bake(1, autoBandwidth), blinding = bake(1e28f, autoBandwidth);
    ASSERT_GT(faint.report.noise, 0);
    EXPECT_NEAR(blinding.report.noise / faint.report.noise, 1.0, 1e-4) << "auto h " << autoBandwidth;
    double sumFaint = 0, sumBlinding = 0;
    for (size_t v = 0; v < faint.mesh.irradiance.size(); ++v) {
      ASSERT_TRUE(std::isfinite(blinding.mesh.irradiance[v].g));
      sumFaint += faint.mesh.irradiance[v].g, sumBlinding += blinding.mesh.irradiance[v].g;
    }
    EXPECT_NEAR(sumBlinding / sumFaint / 1e28, 1.0, 1e-4) << "auto h " << autoBandwidth;
  }
}

// A scene far from a room's size in metres (the box at --scale 1e3 is 1.7 km across, at 1e-3 1.7 mm) is told
// which --scale millimetres, centimetres or inches would need; at 1 it is not.
TEST(Scale, AKilometreOrAMillimetreAcrossIsToldAboutUnits) {
  for (const float scale : {1e-3f, 1.0f, 1e3f}) {
    StageClock clock;
    const PreparedScene p = PrepareScene(SceneSettings{PB_SOURCE_DIR "/data/box/box.obj", scale, {}}, clock);
    bool told = false;
    for (const std::string& w : p.warnings) told |= w.find("--scale 0.001, 0.01 or 0.0254") != std::string::npos;
    EXPECT_EQ(told, scale != 1.0f) << scale;
  }
}

}  // namespace
}  // namespace pb
