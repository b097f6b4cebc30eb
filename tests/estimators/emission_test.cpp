// Photon emission (estimators/emission.h): each sample's weight Le cos(theta) / (pdfArea pdfDirection) is the
// light's flux Phi = pi Ke A exactly, which lets the tracer give every photon Phi / N; the position is uniform
// over the light's area (chi-square over its triangles, whose areas differ 3:1) and the direction cosine-
// distributed about the front normal (chi-square over cos^2(theta), uniform in [0, 1] for a cosine lobe).
#include <gtest/gtest.h>

#include <cmath>

#include "estimators/emission.h"
#include "tests/chi2.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

// A lamp of radiance 2 made of two triangles, of areas 0.5 and 1.5 m^2, facing down over a grey floor.
std::string UnevenLamp(const std::string& dir) {
  test::WriteText(dir + "/lamp.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 2 2 2\n");
  test::WriteText(dir + "/lamp.obj",
                  "mtllib lamp.mtl\nv -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\nusemtl floor\nf 1 4 3 2\n"
                  "v 0 1 0\nv 1 1 0\nv 1 1 1\nv 4 1 1\nusemtl lamp\nf 5 6 7\nf 5 8 7\n");
  return dir + "/lamp.obj";
}

TEST(Emission, EverySampleCarriesTheLightsFluxAndMatchesItsPdfs) {
  const test::TracedScene scene(UnevenLamp(test::TempDirectory("emission")));
  ASSERT_EQ(scene.lights.size(), 1u);
  const Light& light = scene.lights[0];
  ASSERT_NEAR(light.area, 2.0, 1e-6);
  const double phi = Luminance(light.Power());
  constexpr int kSamples = 200'000, kCells = 20;
  std::vector<double> byTriangle(2, 0), expectedByTriangle(2, 0), byCosine(kCells, 0);
  for (size_t k = 0; k < 2; ++k) expectedByTriangle[k] = kSamples * scene.scene.Area(light.triangles[k]) / light.area;
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(11, uint64_t(i));
    const EmissionSample e = SampleEmission(scene.scene, light, rng);
    const double cosine = Dot(e.direction, AsVector(e.normal));
    ASSERT_GT(cosine, 0);
    const double weight = Luminance(light.radiance) * cosine / (double(e.pdfArea) * e.pdfDirection);
    ASSERT_NEAR(weight / phi, 1.0, 1e-5) << "sample " << i;
    byTriangle[e.triangle == light.triangles[0] ? 0 : 1] += 1;
    byCosine[std::min(kCells - 1, int(cosine * cosine * kCells))] += 1;
  }
  const test::Chi2Result triangles = test::Chi2Test(byTriangle, expectedByTriangle);
  EXPECT_GT(triangles.pValue, 1e-3) << triangles.histograms;
  const test::Chi2Result lobe = test::Chi2Test(byCosine, std::vector<double>(kCells, double(kSamples) / kCells));
  EXPECT_GT(lobe.pValue, 1e-3) << lobe.histograms;
}

}  // namespace
}  // namespace pb
