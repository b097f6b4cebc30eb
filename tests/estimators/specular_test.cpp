// Ideal specular scattering (estimators/specular.h, estimators/scatter.h): the Fresnel equations at their known
// points, Snell's law, and chi-square tests that the lobe chosen per event (reflect, refract, absorb; diffuse,
// mirror, absorb) has the probabilities of the Fresnel equations and the material, binned over incident angle.
#include <gtest/gtest.h>

#include <cmath>

#include "estimators/quadrature.h"
#include "estimators/rng.h"
#include "estimators/scatter.h"
#include "tests/chi2.h"

namespace pb {
namespace {

constexpr double kSignificance = 1e-3;
const Normal3 kFront{0, 0, 1};

Vector3 FromCosine(float cosTheta, bool above) {
  const float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
  return {sinTheta, 0, above ? cosTheta : -cosTheta};
}

Material Glass(float ior, Rgb transmittance) {
  Material m{"glass", MaterialClass::kGlass};
  m.ior = ior;
  m.transmittance = transmittance;
  return m;
}

TEST(Fresnel, KnownValues) {
  EXPECT_NEAR(FresnelDielectric(1.0f, 1.5f), 0.04, 1e-6) << "normal incidence ((eta-1)/(eta+1))^2";
  EXPECT_NEAR(FresnelDielectric(1.0f, 1 / 1.5f), 0.04, 1e-6) << "the same from inside";
  // Brewster's angle tan(theta) = eta: the p-polarised part vanishes, so F = rs^2 / 2.
  const float brewster = std::atan(1.5f), cosB = std::cos(brewster);
  const float cosT = *RefractedCosine(cosB, 1.5f);
  const float rs = (cosB - 1.5f * cosT) / (cosB + 1.5f * cosT);
  EXPECT_NEAR(FresnelDielectric(cosB, 1.5f), 0.5f * rs * rs, 1e-6);
  EXPECT_NEAR(FresnelDielectric(0.0f, 1.5f), 1.0, 1e-6) << "grazing incidence reflects everything";
  // Total internal reflection beyond the critical angle sin(theta_c) = 1/1.5.
  const float cosCritical = std::sqrt(1 - 1 / (1.5f * 1.5f));
  EXPECT_EQ(FresnelDielectric(cosCritical - 1e-3f, 1 / 1.5f), 1.0f);
  EXPECT_LT(FresnelDielectric(cosCritical + 1e-3f, 1 / 1.5f), 1.0f);
  EXPECT_EQ(FresnelDielectric(0.7f, 1.0f), 0.0f) << "index-matched: no interface";
}

TEST(Fresnel, ReciprocalAcrossTheInterface) {
  for (float cosI = 0.05f; cosI < 1; cosI += 0.05f) {
    const float cosT = *RefractedCosine(cosI, 1.5f);
    EXPECT_NEAR(FresnelDielectric(cosI, 1.5f), FresnelDielectric(cosT, 1 / 1.5f), 1e-5) << cosI;  // float rounding near grazing
  }
}

TEST(Refract, ObeysSnellAndStaysInThePlaneOfIncidence) {
  for (float cosI = 0.05f; cosI <= 1; cosI += 0.05f) {
    const Vector3 wo = FromCosine(cosI, true);
    const float cosT = *RefractedCosine(cosI, 1.5f);
    const Vector3 wt = Refract(wo, kFront, 1.5f, cosT);
    EXPECT_NEAR(Length(wt), 1.0f, 1e-6);
    EXPECT_NEAR(wt.z, -cosT, 1e-6) << "leaves on the other side";
    EXPECT_NEAR(-wt.x * 1.5f, wo.x, 1e-6) << "n_i sin_i = n_t sin_t, continuing forward";
    EXPECT_EQ(wt.y, 0.0f);
    const Vector3 wr = Reflect(wo, kFront);
    EXPECT_NEAR(wr.x, -wo.x, 1e-6);
    EXPECT_NEAR(wr.z, wo.z, 1e-6);
  }
}

std::string CellLine(int bin, size_t outcome, double observed, double expected) {
  return "bin " + std::to_string(bin) + " outcome " + std::to_string(outcome) + ": " + std::to_string(observed) +
         " vs " + std::to_string(expected) + "\n";
}

// Pearson's chi-square over (angle bin x outcome) cells with each bin's sample count fixed: dof = bins x
// (outcomes - 1). `expected(cosLo, cosHi)` gives the outcome probabilities averaged over the bin (uniform cos).
template <size_t kOutcomes, typename Expected, typename Outcome>
void ExpectSplitMatches(Expected&& expected, Outcome&& outcome, uint64_t seed) {
  constexpr int kBins = 20, kPerBin = 20000;
  double chi2 = 0;
  int dof = 0;
  std::string table;
  for (int bin = 0; bin < kBins; ++bin) {
    const double lo = double(bin) / kBins, hi = double(bin + 1) / kBins;
    std::array<double, kOutcomes> counts{};
    for (int i = 0; i < kPerBin; ++i) {
      Rng rng(seed, uint64_t(bin) * kPerBin + i);
      const float cosI = float(lo + (hi - lo) * rng.Uniform());
      ++counts[outcome(cosI, rng)];
    }
    const std::array<double, kOutcomes> p = expected(lo, hi);
    for (size_t k = 0; k < kOutcomes; ++k) {
      const double e = p[k] * kPerBin;
      table += CellLine(bin, k, counts[k], e);
      if (e == 0) {
        EXPECT_EQ(counts[k], 0) << "an outcome of probability 0 happened, bin " << bin;
        continue;
      }
      chi2 += (counts[k] - e) * (counts[k] - e) / e;
      ++dof;
    }
    --dof;  // the bin's total is fixed
  }
  EXPECT_GT(test::RegularizedGammaQ(dof / 2.0, chi2 / 2.0), kSignificance) << "chi2 " << chi2 << " dof " << dof
                                                                            << "\n" << table;
}

double MeanFresnel(double lo, double hi, float eta) {
  return GaussLegendre([&](double c) { return double(FresnelDielectric(float(c), eta)); }, lo, hi, 4) / (hi - lo);
}

void GlassSplitTest(float ior, bool fromOutside, Rgb transmittance, uint64_t seed) {
  const Material glass = Glass(ior, transmittance);
  const float eta = fromOutside ? ior : 1 / ior;
  const double t = transmittance.Max();
  ExpectSplitMatches<3>(
      [&](double lo, double hi) {
        const double f = MeanFresnel(lo, hi, eta);
        return std::array<double, 3>{f, (1 - f) * t, (1 - f) * (1 - t)};
      },
      [&](float cosI, Rng& rng) {
        const ScatterSample s = SampleScatter(glass, glass.albedo, FromCosine(cosI, fromOutside), kFront, TransportMode::kImportance,
                                              rng.Uniform(), rng.Uniform2());
        return s.event == ScatterEvent::kFresnelReflection ? 0 : s.event == ScatterEvent::kRefraction ? 1 : 2;
      },
      seed);
}

TEST(ScatterChi2, GlassFromOutsideSplitsByFresnel) { GlassSplitTest(1.5f, true, {1, 1, 1}, 11); }
TEST(ScatterChi2, GlassFromInsideSplitsByFresnelWithTotalInternalReflection) {
  GlassSplitTest(1.5f, false, {1, 1, 1}, 12);
}
TEST(ScatterChi2, TintedGlassAbsorbsWhatItDoesNotTransmit) { GlassSplitTest(1.33f, true, {0.2f, 0.6f, 0.4f}, 13); }

TEST(ScatterChi2, MirrorSplitsByKdAndKs) {
  Material mirror{"mirror", MaterialClass::kMirror};
  mirror.albedo = {0.2f, 0.3f, 0.1f};
  mirror.specular = {0.5f, 0.6f, 0.4f};
  ExpectSplitMatches<3>([](double, double) { return std::array<double, 3>{0.3, 0.6, 0.1}; },
                        [&](float cosI, Rng& rng) {
                          const ScatterSample s = SampleScatter(mirror, mirror.albedo, FromCosine(cosI, true), kFront,
                                                                TransportMode::kImportance, rng.Uniform(), rng.Uniform2());
                          if (s.event == ScatterEvent::kMirror) {
                            EXPECT_NEAR(s.weight.g, 1.0f, 1e-6);  // Ks / max(Ks)
                            EXPECT_NEAR(s.wi.z, cosI, 1e-6);
                          }
                          return s.event == ScatterEvent::kDiffuse ? 0 : s.event == ScatterEvent::kMirror ? 1 : 2;
                        },
                        14);
}

TEST(Scatter, RefractionScalesRadianceByEtaSquaredButNotFlux) {
  const Material glass = Glass(1.5f, {0.8f, 0.8f, 0.8f});
  const Vector3 outside = FromCosine(0.9f, true);
  const float u = 0.5f;  // past F (about 0.04) and below F + (1 - F) 0.8: refracts
  const ScatterSample flux = SampleScatter(glass, glass.albedo, outside, kFront, TransportMode::kImportance, u, {});
  const ScatterSample in = SampleScatter(glass, glass.albedo, outside, kFront, TransportMode::kRadiance, u, {});
  ASSERT_EQ(flux.event, ScatterEvent::kRefraction);
  ASSERT_EQ(in.event, ScatterEvent::kRefraction);
  EXPECT_TRUE(in.transmitted);
  EXPECT_NEAR(flux.weight.r, 1.0f, 1e-6) << "Tf / max(Tf): flux crosses unscaled";
  EXPECT_NEAR(in.weight.r, 1.0f / (1.5f * 1.5f), 1e-6) << "radiance from inside, seen outside, drops by eta^2";
  // The reverse crossing, a path inside arriving back along the refracted ray, gains eta^2: the round trip is neutral.
  const ScatterSample out = SampleScatter(glass, glass.albedo, in.wi, kFront, TransportMode::kRadiance, u, {});
  ASSERT_EQ(out.event, ScatterEvent::kRefraction);
  EXPECT_NEAR(in.weight.r * out.weight.r, 1.0f, 1e-5);
  EXPECT_NEAR(Dot(out.wi, outside), 1.0f, 1e-5) << "refraction is reversible";
}

TEST(Scatter, DiffuseClassIsExactlyTheDiffuseEvent) {
  Material matte{"matte"};
  matte.albedo = {0.7f, 0.5f, 0.2f};
  for (uint64_t i = 0; i < 1000; ++i) {
    Rng a(3, i), b(3, i);
    const ScatterSample general = SampleScatter(matte, matte.albedo, FromCosine(0.6f, false), kFront, TransportMode::kImportance,
                                                a.Uniform(), a.Uniform2());
    const ScatterSample diffuse = ScatterDiffuse(matte.albedo, -kFront, b.Uniform(), b.Uniform2());
    ASSERT_EQ(general.event, diffuse.event);
    EXPECT_EQ(general.wi.x, diffuse.wi.x);
    EXPECT_EQ(general.weight.r, diffuse.weight.r);
    if (!general.Absorbed()) {
      EXPECT_LT(general.wi.z, 0) << "leaves on the side it arrived from";
    }
  }
}

}  // namespace
}  // namespace pb
