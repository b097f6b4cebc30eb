// An estimate of irradiance and its noise, as every estimator of the light at a point gives it: H [W/m^2] per
// colour channel, and the standard error of H's luminance relative to that luminance (dimensionless; 0 when the
// luminance is 0). Independent estimates add (IndependentSum): their irradiances add, and so do the variances of
// their luminances, sigma_i = relativeNoise_i x luminance_i.
#pragma once

#include <cmath>

#include "mesh/color.h"

namespace pb {

struct NoisyIrradiance {
  Rgb irradiance;            // [W/m^2]
  double relativeNoise = 0;  // standard error of the luminance over the luminance; 0 when that is 0

  // The variance of the luminance [(W/m^2)^2].
  double Variance() const { return std::pow(relativeNoise * Luminance(irradiance), 2); }
};

// The sum of independent estimates of parts of one irradiance (the photons', the shadow rays', a sky's).
class IndependentSum {
 public:
  explicit IndependentSum(const NoisyIrradiance& first) : irradiance_(first.irradiance), variance_(first.Variance()) {}

  void Add(const NoisyIrradiance& part) {
    irradiance_ = irradiance_ + part.irradiance;
    variance_ += part.Variance();
  }
  double Variance() const { return variance_; }
  NoisyIrradiance Total() const {
    const double mean = Luminance(irradiance_);
    return {irradiance_, mean > 0 ? std::sqrt(variance_) / mean : 0.0};
  }

 private:
  Rgb irradiance_;
  double variance_;
};

}  // namespace pb
