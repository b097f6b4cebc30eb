// The RMS relative error of a light sampler's direct irradiance against a closed form, over a grid of points on a
// horizontal plane facing up: what the sampling tests compare samplers by. Each point draws from its own stream,
// so the grid's error is the same on any thread.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "estimators/light_sampler.h"
#include "tests/lambert.h"

namespace pb::test {

// side x side points at cell centres of [lo, hi]^2 in x and z, at height y [m], `samples` shadow rays each, seeded
// `seed`; exact(x) is the true irradiance there. Expects the mean relative error within 5 standard errors of 0
// (unbiased) and returns the RMS relative error.
inline double GridRmsError(const LightSampler& sampler, int side, double lo, double hi, double y, uint32_t samples,
                           uint64_t seed, const std::function<double(V3)>& exact) {
  double squares = 0, errors = 0;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      const double x = lo + (hi - lo) * (i + 0.5) / side, z = lo + (hi - lo) * (j + 0.5) / side;
      Rng rng(seed, uint64_t(i * side + j));
      const double e = sampler.Irradiance({float(x), float(y), float(z)}, {0, 1, 0}, samples, rng).irradiance.g;
      const double error = e / exact({x, y, z}) - 1;
      squares += error * error, errors += error;
    }
  const double n = double(side) * side, rms = std::sqrt(squares / n);
  EXPECT_LE(std::fabs(errors / n), 5 * rms / std::sqrt(n)) << "biased";
  return rms;
}

}  // namespace pb::test
