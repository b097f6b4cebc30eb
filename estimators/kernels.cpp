#include "estimators/kernels.h"

#include "mesh/geometry.h"

namespace pb {

float KernelDensity(Kernel kernel, float r2, float h) {
  const float t2 = r2 / (h * h);
  if (t2 >= 1.0f) return 0.0f;
  switch (kernel) {
    case Kernel::kEpanechnikov:
      return 2.0f * kInvPi * (1.0f - t2) / (h * h);
  }
  return 0.0f;
}

std::optional<Kernel> ParseKernel(std::string_view name) {
  if (name == "epanechnikov") return Kernel::kEpanechnikov;
  return std::nullopt;
}

std::string KernelName(Kernel kernel) {
  switch (kernel) {
    case Kernel::kEpanechnikov:
      return "epanechnikov";
  }
  return "?";
}

std::string KernelNames() { return "epanechnikov"; }

}  // namespace pb
