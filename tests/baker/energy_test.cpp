// Energy bookkeeping in a closed box with grey albedo rho = 0.5 everywhere.
// - The photons' initial flux sums to the lights' Phi = pi Ke A (to float rounding of Phi / N).
// - Absorbed flux, tallied per hit as phi (1 - rho), equals the emitted flux within 0.5%: every photon is
//   eventually absorbed. The tally's relative standard deviation is sqrt(rho / ((1 - rho) N)) = 0.1% at N = 1M,
//   so 0.5% is 5 sigma.
// - No photon escapes a closed box: a leak through a corner would show here (bound stated below).
#include <gtest/gtest.h>

#include <cmath>

#include "baker/bake.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

TEST(Energy, ClosedBoxAbsorbsWhatItEmits) {
  const std::string dir = test::TempDirectory("energy");
  BakeOptions o;
  o.scenePath = test::WriteClosedBox(dir, 1.0f, 0.5f, 0.2f, 10.0f);
  o.outputPath = dir + "/out.ply";
  o.photons = 1'000'000;
  const BakeReport r = Bake(o, Log(true));

  ASSERT_EQ(r.lights.size(), 1u);
  const double phi = M_PI * 10.0 * 0.2 * 0.2;  // pi Ke A [W]
  EXPECT_NEAR(r.lights[0].power.g, phi, 1e-5 * phi);
  EXPECT_NEAR(r.trace.fluxEmitted.g, phi, 1e-6 * phi) << "photon flux must sum to the light's Phi";
  EXPECT_EQ(r.trace.emitted, o.photons);
  EXPECT_NEAR(r.trace.fluxAbsorbed.g / r.trace.fluxEmitted.g, 1.0, 0.005);
  EXPECT_LE(r.trace.escaped, o.photons / 100000) << "light leaks out of a closed box";
  EXPECT_EQ(r.trace.truncated, 0u);
  // Every photon ends by absorption or escape.
  EXPECT_EQ(r.trace.absorbed + r.trace.escaped, r.trace.emitted);
}

// Red walls (Kd 0.99 0 0) and a green light (its back, Kd 0 0.99 0): a photon that met both carries nothing, and
// ends there as absorbed; it had bounced on with no flux, about a hundred more times (survival 0.99), storing empty
// hits. No stored hit is empty, and every photon still ends absorbed or escaped.
TEST(Energy, APhotonThatCarriesNothingEnds) {
  const std::string dir = test::TempDirectory("energy-empty-photons");
  const std::string scene = test::WriteClosedBox(dir, 1.0f, 0.5f, 0.2f, 10.0f);
  test::WriteText(dir + "/box.mtl", "newmtl wall\nKd 0.99 0 0\nnewmtl light\nKd 0 0.99 0\nKe 10 10 10\n");
  const test::TracedScene traced(scene);
  const PhotonStore store = traced.Trace(20'000, 1);
  uint64_t empty = 0;
  store.ForEach([&](const PhotonHit& hit, Rgb) { empty += hit.attenuation.IsBlack(); });
  EXPECT_EQ(empty, 0u);
  EXPECT_EQ(store.stats.absorbed + store.stats.escaped, store.stats.emitted);
  EXPECT_EQ(store.stats.truncated, 0u);
}

// --max-bounces N: in a closed box whose every surface (the light too) has albedo rho, survival = rho keeps each
// hit's flux at Phi / n, and the flux that reaches surfaces is Phi (1 + rho + ... + rho^N): the stored hits per
// photon are (1 - rho^(N+1)) / (1 - rho). Per photon their count is a geometric variable cut at N + 1, of variance
// at most rho / (1 - rho)^2; the bound is 5 sigma of the mean. The cut photons' flux joins the forbidden flux, so
// emitted = absorbed + escaped + forbidden still holds.
TEST(Energy, BounceLimitStoresTheTruncatedNeumannSeries) {
  const std::string dir = test::TempDirectory("energy-bounces");
  const double rho = 0.5;
  BakeOptions o;
  o.direct.mode = DirectLight::kPhotons;  // the photons' count of every bounce, the first included
  o.scenePath = test::WriteClosedBox(dir, 1.0f, float(rho), 0.2f, 10.0f);
  o.outputPath = dir + "/out.ply";
  o.photons = 200'000;
  const double sigma = std::sqrt(rho / ((1 - rho) * (1 - rho)) / double(o.photons));
  for (uint32_t bounces : {0u, 1u, 3u, kDefaultMaxBounces}) {
    o.maxBounces = bounces;
    const BakeReport r = Bake(o, Log(true));
    const double expected = (1 - std::pow(rho, bounces + 1.0)) / (1 - rho);
    EXPECT_NEAR(double(r.trace.hits) / double(r.trace.emitted), expected, 5 * sigma) << bounces << " bounces";
    const TraceStats& t = r.trace;
    const double balanceSigma = std::sqrt(rho / ((1 - rho) * double(o.photons)));  // the absorbed tally's, above
    EXPECT_NEAR((t.fluxAbsorbed.g + t.fluxEscaped.g + t.fluxForbidden.g) / t.fluxEmitted.g, 1.0, 5 * balanceSigma)
        << bounces << " bounces";
    if (bounces < 3) {
      EXPECT_GT(t.truncated, 0u);
    }
    if (bounces == kDefaultMaxBounces) {
      EXPECT_EQ(t.truncated, 0u);
    }
  }
}

TEST(Energy, PhotonsSplitAcrossLightsInProportionToPower) {
  const std::string dir = test::TempDirectory("energy-split");
  BakeOptions o;
  o.scenePath = test::WriteTwoLamps(dir);
  o.outputPath = dir + "/out.ply";
  o.photons = 100'001;
  const BakeReport r = Bake(o, Log(true));
  ASSERT_EQ(r.lights.size(), 2u);
  // N_i = floor(n Phi_i / Phi): 100001 / 4 = 25000.25 and 75000.75.
  EXPECT_EQ(r.lights[0].photons, 25000u);
  EXPECT_EQ(r.lights[1].photons, 75000u);
  EXPECT_EQ(r.trace.emitted, 100'000u);
  EXPECT_NEAR(r.trace.fluxEmitted.g, M_PI * (1.0 + 3.0), 1e-5);
}

}  // namespace
}  // namespace pb
