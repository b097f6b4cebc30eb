// Radially symmetric 2-D density kernels K_h(r) [1/m^2] with support radius (bandwidth) h [m], normalised so
// that their integral over the plane is 1: integral of K_h(|x|) dA = 1. A photon of flux phi [W] spreads
// phi K_h [W/m^2] of irradiance around its hit (the paper's "Kernel estimators"; Silverman 1986, "Density
// Estimation for Statistics and Data Analysis", ch. 4, for the family and its moments).
//
// With t = r / h < 1 (all vanish for t >= 1):
//   uniform       1/pi                         epanechnikov  (2/pi) (1 - t^2)
//   biweight      (3/pi) (1 - t^2)^2           triweight     (4/pi) (1 - t^2)^3
//   cone          (3/pi) (1 - t)               gaussian      exp(-2 t^2) * 2 / (pi (1 - e^-2)),
// all divided by h^2. The gaussian has sigma = h/2, truncated at h = 2 sigma and renormalised.
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

namespace pb {

enum class Kernel { kUniform, kEpanechnikov, kBiweight, kTriweight, kCone, kGaussian };
inline constexpr std::array kAllKernels = {Kernel::kUniform, Kernel::kEpanechnikov, Kernel::kBiweight,
                                           Kernel::kTriweight, Kernel::kCone,     Kernel::kGaussian};

// 2 / (pi (1 - e^-2)): the truncated gaussian's normalisation.
inline const float kGaussianNormF = float(2.0 / (3.14159265358979323846 * (1.0 - std::exp(-2.0))));

// Calls f(k) with the kernel's profile as an inline function of the squared radius, k(t2) = h^2 K_h(r) for
// t2 = r^2 / h^2 < 1, and returns what f returns. The switch is made once, outside f: loops over many photons
// (estimators/kernel_estimator.cpp) then pay no dispatch per photon.
inline constexpr float kInvPiF = 0.31830988618379067154f;

template <typename F>
auto WithSquaredProfile(Kernel kernel, F&& f) {
  switch (kernel) {
    case Kernel::kUniform: return f([](float) { return kInvPiF; });
    case Kernel::kEpanechnikov: return f([](float t2) { return 2.0f * kInvPiF * (1.0f - t2); });
    case Kernel::kBiweight: return f([](float t2) { return 3.0f * kInvPiF * (1.0f - t2) * (1.0f - t2); });
    case Kernel::kTriweight:
      return f([](float t2) { return 4.0f * kInvPiF * (1.0f - t2) * (1.0f - t2) * (1.0f - t2); });
    case Kernel::kCone: return f([](float t2) { return 3.0f * kInvPiF * (1.0f - std::sqrt(t2)); });
    case Kernel::kGaussian: return f([](float t2) { return kGaussianNormF * std::exp(-2.0f * t2); });
  }
  return f([](float) { return 0.0f; });
}

// K_h(r) for r^2 = r2 [m^2] and bandwidth h [m]; zero for r >= h.
float KernelDensity(Kernel kernel, float r2, float h);

// The dimensionless profile k(t) = h^2 K_h(t h), t >= 0.
double KernelProfile(Kernel kernel, double t);

// Radial mass G(t) = integral_0^t k(s) s ds: the mass inside radius t h is 2 pi G(t), so G(1) = 1 / (2 pi).
// Used to integrate a kernel over a polygon exactly in r (estimators/surface_region.h).
double KernelRadialMass(Kernel kernel, double t);

// Radial moments G_n(t) = integral_0^t k(s) s^(n+1) ds for n = 0, 1, 2 (G_0 is G above), closed forms for every
// kernel. Integrated over angle they give the kernel's moments over a region: its mass (n = 0), first moment
// (n = 1, times the unit direction) and second moment (n = 2, times the direction's outer product), in units of h
// (estimators/surface_region.h, KernelMoments).
double KernelRadialMoment(Kernel kernel, int n, double t);

// G(t) / t^2, evaluated without cancellation (its limit k(0)/2 at t = 0). Smooth in t^2, which makes the
// boundary integral of estimators/surface_region.cpp a smooth integrand.
double KernelRadialMassOverSquare(Kernel kernel, double t);

// Constants of the asymptotic error of a kernel estimate (Silverman 1986, sec. 4.3), for h = 1:
//   roughness = integral K^2 dA      (variance: Var H ~ flux-squared density * roughness / h^2)
//   moment2   = integral x_1^2 K dA  (bias: E H - H ~ h^2 moment2 laplacian(H) / 2)
struct KernelMoments {
  double roughness = 0;
  double moment2 = 0;
};
KernelMoments MomentsOf(Kernel kernel);

std::optional<Kernel> ParseKernel(std::string_view name);
std::string KernelName(Kernel kernel);
std::string KernelNames();  // comma-separated, for --help and error messages

}  // namespace pb
