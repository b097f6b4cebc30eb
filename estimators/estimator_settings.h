// Which density estimator reads the photons on a surface, and with what: the kind (kernel, histogram, knn), the
// kernel, h [m] (the kernel's support radius or the histogram's bucket side; none: chosen per surface from its
// photons, estimators/bandwidth.h), k, and the boundary correction.
// The estimators themselves: estimators/density_estimator.h.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "estimators/kernels.h"

namespace pb {

enum class EstimatorKind { kKernel, kHistogram, kNearest };
inline constexpr std::array kAllEstimators = {EstimatorKind::kKernel, EstimatorKind::kHistogram,
                                              EstimatorKind::kNearest};

std::optional<EstimatorKind> ParseEstimator(std::string_view name);
std::string EstimatorName(EstimatorKind kind);
std::string EstimatorNames();  // comma-separated, for --help and error messages

struct EstimatorSettings {
  EstimatorKind kind = EstimatorKind::kKernel;
  Kernel kernel = Kernel::kEpanechnikov;
  // h [m]: kernel support radius, or histogram bucket side; none (--h auto): chosen per surface from its photons.
  // An estimator is built with the surface's own h, always given.
  std::optional<float> bandwidth = 0.05f;
  uint32_t neighbours = 50;   // k of the knn estimator, >= 2
  bool edgeCorrection = true;  // renormalise by the part of the kernel, bucket or disc on the surface
  bool localLinear = true;     // the kernel estimator at edges: a local linear fit (kernel_estimator.h), not only renormalised
};

}  // namespace pb
