// The same light at any scale (issue 38): the box baked in millimetres, metres and kilometres (--scale 1e-3, 1,
// 1e3, with h scaled alike) reads the same irradiance, with sampled direct light and with photons alone: its
// lights are given by their radiance, so H, an integral of radiance over solid angle, does not change with scale. The photons follow the same streams at every scale, so the photon part differs by float rounding only;
// the direct samples' streams are keyed by chart positions, which differ, so each scale's mean over the 1,204
// vertices carries its own sampling noise (~0.1% here at 64 shadow rays). Tolerance 1%: an absolute 0.2 mm step
// of the shadow rays' start (fixed since) read the millimetre box 5% high, and a 4 mm floor 39%.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "baker/0_prepare_scene.h"
#include "baker/bake.h"
#include "baker/presets.h"
#include "baker/files/image_io.h"
#include "mesh/errors.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

// The box at `scale` metres per unit, baked with h = `h` metres at scale 1, scaled alike.
BakeOptions ScaledBox(double scale, double h, uint64_t photons) {
  BakeOptions o;
  o.scenePath = PB_SOURCE_DIR "/data/box/box.obj";
  o.outputPath = test::TempDirectory("scale") + "/out.ply";
  o.photons = photons;
  o.scale = float(scale);
  o.estimator.bandwidth = float(h * scale);
  return o;
}

// The mean of the values' green channel.
double MeanGreen(const std::vector<Rgb>& values) {
  double sum = 0;
  for (const Rgb& h : values) sum += h.g;
  return values.empty() ? 0.0 : sum / double(values.size());
}

// The mean over the box's vertices of H's green channel [W/m^2].
double MeanScaledIrradiance(double scale, DirectLight direct) {
  BakeOptions o = ScaledBox(scale, 0.05, 200'000);
  o.direct.mode = direct;
  o.direct.samples = 64;
  return MeanGreen(BakeMesh(o, Log(true)).mesh.irradiance);
}

TEST(Scale, TheBoxReadsTheSameLightInMillimetresMetresAndKilometres) {
  for (const DirectLight direct : {DirectLight::kSampled, DirectLight::kPhotons}) {
    const double metres = MeanScaledIrradiance(1, direct);
    for (const double scale : {1e-3, 1e3})
      EXPECT_NEAR(MeanScaledIrradiance(scale, direct) / metres, 1.0, 0.01) << "scale " << scale << ", direct "
                                                                           << int(direct);
  }
}

// Every estimator, and the irradiance maps (texel scaled with the scene), read the same light at any scale too.
// With photons alone every scale traces the same photons, so the means differ by float rounding: 0.5%.
BakeResult BakeScaledBox(double scale, EstimatorKind kind, Kernel kernel, const std::string& maps = "") {
  BakeOptions o = ScaledBox(scale, 0.08, 50'000);
  o.estimator.kind = kind, o.estimator.kernel = kernel;
  o.direct.mode = DirectLight::kPhotons;
  o.mapsDirectory = maps;
  o.texel = float(0.04 * scale);
  return BakeMesh(o, Log(true));  // the maps committed
}

TEST(Scale, EveryEstimatorAndTheMapsReadTheSameLightAtAnyScale) {
  const std::pair<EstimatorKind, Kernel> estimators[] = {{EstimatorKind::kKernel, Kernel::kEpanechnikov},
                                                         {EstimatorKind::kKernel, Kernel::kGaussian},
                                                         {EstimatorKind::kHistogram, Kernel::kEpanechnikov},
                                                         {EstimatorKind::kNearest, Kernel::kEpanechnikov}};
  const auto mean = [](double scale, EstimatorKind kind, Kernel kernel) {
    return MeanGreen(BakeScaledBox(scale, kind, kernel).mesh.irradiance);
  };
  for (const auto& [kind, kernel] : estimators) {
    const double metres = mean(1, kind, kernel);
    ASSERT_GT(metres, 0);
    for (const double scale : {1e-3, 1e3})
      EXPECT_NEAR(mean(scale, kind, kernel) / metres, 1.0, 0.005) << "scale " << scale << ", estimator " << int(kind);
  }
  const auto mapMean = [](double scale) {
    const std::string maps = test::TempDirectory("scale-maps");
    const BakeResult r = BakeScaledBox(scale, EstimatorKind::kKernel, Kernel::kEpanechnikov, maps);
    std::vector<Rgb> texels;
    for (const std::string& path : r.report.maps.paths) {
      const Image map = ReadExr(path);
      texels.insert(texels.end(), map.pixels.begin(), map.pixels.end());
    }
    return MeanGreen(texels);
  };
  const double metres = mapMean(1);
  ASSERT_GT(metres, 0);
  for (const double scale : {1e-3, 1e3}) EXPECT_NEAR(mapMean(scale) / metres, 1.0, 0.005) << "maps, scale " << scale;
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
  ASSERT_FALSE(metres.report.options.estimator.bandwidth.has_value());  // --h auto
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
    o.estimator.bandwidth = autoBandwidth ? std::nullopt : std::optional(0.1f);
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

// A scene far from a room's size in metres is told about units: the box at --scale 1e3, 1.7 km across, which --scale
// millimetres, centimetres or inches would need; at 1e-3 (1.7 mm) and 1e-6, the power of ten that brings it back
// (it once suggested shrinking it further); at 1 nothing.
TEST(Scale, AKilometreOrAMillimetreAcrossIsToldAboutUnits) {
  const std::map<float, std::string> hints = {{1e-6f, "bake with --scale 1e+06 (it would be 1.74 m across)"},
                                              {1e-3f, "bake with --scale 1000 (it would be 1.74 m across)"},
                                              {1.0f, ""},
                                              {1e3f, "--scale 0.001, 0.01 or 0.0254"}};
  for (const auto& [scale, hint] : hints) {
    StageClock clock;
    const PreparedScene p = PrepareScene(SceneSettings{PB_SOURCE_DIR "/data/box/box.obj", scale, {}}, clock);
    bool units = false, told = false;
    for (const std::string& w : p.warnings)
      units |= w.find("lengths are read as metres") != std::string::npos,
          told |= !hint.empty() && w.find(hint) != std::string::npos;
    EXPECT_EQ(units, !hint.empty()) << scale;
    EXPECT_EQ(told, !hint.empty()) << scale;
  }
}

// A scene so small that its lamp's area underflows float loses the lamp with its other zero-area faces: the error
// that it has no light says so, with its size (it said only that no face used Ke > 0).
TEST(Scale, ALampLostToFloatIsNamedInTheNoLightError) {
  const std::string dir = test::TempDirectory("scale-tiny-lamp");
  test::WriteText(dir + "/tiny.mtl", "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n");
  test::WriteText(dir + "/tiny.obj", "mtllib tiny.mtl\nv 0 0 0\nv 1e-9 0 0\nv 1e-9 0 -1e-9\nv 0 0 -1e-9\n"
                                     "v 0 1e-10 0\nv 0 1e-10 -1e-10\nv 1e-10 1e-10 0\n"
                                     "usemtl grey\nf 1 2 3 4\nusemtl lamp\nf 5 6 7\n");
  StageClock clock;
  try {
    PrepareScene(SceneSettings{dir + "/tiny.obj", 1, {}}, clock);
    FAIL() << "a scene without its lamp baked";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no face uses a material with Ke > 0, and no light is declared (of its faces, "
                                         "1 were skipped as zero-area, in a scene 1.42e-09 m across"),
              std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pb
