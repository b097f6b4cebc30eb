#include "baker/3_gap_weights.h"

#include <algorithm>
#include <cmath>

namespace pb {

namespace {

// A surface's sums over its narrow-gap vertices.
struct GapSums {
  double count = 0, squaredDifference = 0, gatheredVariance = 0, photonVariance = 0;
};

GapWeight WeightOf(const GapSums& s) {
  if (s.count == 0) return {};
  const double gathered = s.gatheredVariance / s.count, photons = s.photonVariance / s.count;
  const double bias2 = std::max(s.squaredDifference / s.count - gathered - photons, 0.0);
  const double all = bias2 + photons + gathered;
  return {all > 0 ? (bias2 + photons) / all : 1.0, std::sqrt(bias2), uint32_t(s.count)};
}

}  // namespace

std::vector<GapWeight> LearnGapWeights(const std::vector<GapPair>& pairs, size_t surfaces) {
  std::vector<GapSums> sums(surfaces);
  for (const GapPair& pair : pairs) {
    if (!pair.Present() || pair.surface >= surfaces) continue;
    GapSums& s = sums[pair.surface];
    const double difference = Luminance(pair.gathered.irradiance) - Luminance(pair.photons.irradiance);
    s.count += 1;
    s.squaredDifference += difference * difference;
    s.gatheredVariance += pair.gathered.Variance(), s.photonVariance += pair.photons.Variance();
  }
  std::vector<GapWeight> weights(surfaces);
  std::transform(sums.begin(), sums.end(), weights.begin(), WeightOf);
  return weights;
}

BlendedGap Blend(const NoisyIrradiance& gathered, const NoisyIrradiance& photons, double alpha) {
  if (alpha >= 1) return {gathered, gathered.Variance(), 0, {}};
  const auto a = float(alpha);
  const Rgb photonPart = photons.irradiance * (1 - a);
  const Rgb value = photonPart + gathered.irradiance * a;  // a convex mix of two estimates of light: not negative
  const double gatheredVariance = alpha * alpha * gathered.Variance();
  const double photonVariance = (1 - alpha) * (1 - alpha) * photons.Variance();
  const double mean = Luminance(value);
  return {{value, mean > 0 ? std::sqrt(gatheredVariance + photonVariance) / mean : 0.0},
          gatheredVariance,
          photonVariance,
          photonPart};
}

}  // namespace pb
