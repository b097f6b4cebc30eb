// Large photon counts: 1e8 photons of equal flux summed in float stagnate once the sum is 2^24 times a photon's
// flux, so every tally of flux in photonbake (RgbSum: TraceStats, per-surface flux, the kernel sum) accumulates in
// double. This checks RgbSum against an exact reference over 1e8 photons, and shows that a float sum drifts.
#include <gtest/gtest.h>

#include "mesh/color.h"

namespace pb {
namespace {

TEST(Accumulation, HundredMillionPhotonsDoNotDrift) {
  constexpr uint64_t kPhotons = 100'000'000;
  const Rgb photon{0.7f / kPhotons, 0.5f / kPhotons, 0.3f / kPhotons};  // a 0.7/0.5/0.3 W light split 1e8 ways
  RgbSum tally;
  float naive = 0;
  for (uint64_t i = 0; i < kPhotons; ++i) {
    tally.Add(photon);
    naive += photon.r;
  }
  // The exact sum of 1e8 copies of the float photon.r, computed in double without accumulation.
  const double reference = double(photon.r) * double(kPhotons);
  EXPECT_NEAR(tally.r, reference, 1e-9 * reference);
  EXPECT_NEAR(tally.b, double(photon.b) * double(kPhotons), 1e-9 * reference);
  EXPECT_GT(std::abs(naive - reference), 0.05 * reference) << "a float sum would drift: the test can fail";
}

}  // namespace
}  // namespace pb
