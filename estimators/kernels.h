// Radially symmetric 2-D density kernels K_h(r) [1/m^2] with support radius (bandwidth) h [m], normalised so
// that their integral over the plane is 1: integral of K_h(|x|) dA = 1. A photon of flux phi [W] spreads
// phi K_h [W/m^2] of irradiance around its hit (Silverman 1986, "Density Estimation", ch. 4).
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace pb {

enum class Kernel {
  kEpanechnikov,  // K(t) = 2/pi (1 - t^2), t = r/h < 1
};

// K_h(r) for r^2 = r2 [m^2] and bandwidth h [m]; zero for r >= h.
float KernelDensity(Kernel kernel, float r2, float h);

std::optional<Kernel> ParseKernel(std::string_view name);
std::string KernelName(Kernel kernel);
std::string KernelNames();  // "epanechnikov", comma-separated, for --help

}  // namespace pb
