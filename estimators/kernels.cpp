#include "estimators/kernels.h"

#include <cmath>

#include "estimators/enum_names.h"
#include "estimators/quadrature.h"
#include "mesh/geometry.h"

namespace pb {
namespace {

constexpr double kPiD = 3.14159265358979323846;
const double kGaussianNorm = 2.0 / (kPiD * (1.0 - std::exp(-2.0)));

// x^n for a small n >= 0 by multiplication: the boundary integrals call these per quadrature node, and std::pow
// was a twentieth of a small bake's time.
double IntegerPower(double x, int n) {
  double result = 1;
  for (int i = 0; i < n; ++i) result *= x;
  return result;
}

// (p + 1)/pi (1 - t^2)^p has radial mass (1 - (1 - t^2)^(p+1)) / (2 pi).
double PolynomialRadialMass(int p, double t) { return (1.0 - IntegerPower(1.0 - t * t, p + 1)) / (2.0 * kPiD); }

}  // namespace

double KernelProfile(Kernel kernel, double t) {
  if (t >= 1.0) return 0.0;
  const double q = 1.0 - t * t;
  switch (kernel) {
    case Kernel::kUniform: return 1.0 / kPiD;
    case Kernel::kEpanechnikov: return 2.0 / kPiD * q;
    case Kernel::kBiweight: return 3.0 / kPiD * q * q;
    case Kernel::kTriweight: return 4.0 / kPiD * q * q * q;
    case Kernel::kCone: return 3.0 / kPiD * (1.0 - t);
    case Kernel::kGaussian: return kGaussianNorm * std::exp(-2.0 * t * t);
  }
  return 0.0;
}

float KernelDensity(Kernel kernel, float r2, float h) {
  const float t2 = r2 / (h * h);
  if (t2 >= 1.0f) return 0.0f;
  return WithSquaredProfile(kernel, [&](auto profile) { return profile(t2) / (h * h); });
}

double KernelRadialMass(Kernel kernel, double t) {
  t = std::min(std::max(t, 0.0), 1.0);
  switch (kernel) {
    case Kernel::kUniform: return PolynomialRadialMass(0, t);
    case Kernel::kEpanechnikov: return PolynomialRadialMass(1, t);
    case Kernel::kBiweight: return PolynomialRadialMass(2, t);
    case Kernel::kTriweight: return PolynomialRadialMass(3, t);
    case Kernel::kCone: return 3.0 / kPiD * (t * t / 2.0 - t * t * t / 3.0);
    case Kernel::kGaussian: return kGaussianNorm * (1.0 - std::exp(-2.0 * t * t)) / 4.0;
  }
  return 0.0;
}

double KernelRadialMoment(Kernel kernel, int n, double t) {
  t = std::min(std::max(t, 0.0), 1.0);
  // c (1 - s^2)^p = c sum_j C(p, j) (-1)^j s^(2j), so its moment is c sum_j C(p, j) (-1)^j t^(2j+n+2) / (2j+n+2).
  const auto polynomial = [&](int p) {
    double sum = 0, binomial = 1, power = IntegerPower(t, n + 2);
    for (int j = 0; j <= p; ++j, power *= t * t) {
      sum += (j % 2 ? -binomial : binomial) * power / (2 * j + n + 2);
      binomial = binomial * (p - j) / (j + 1);
    }
    return (p + 1) / kPiD * sum;
  };
  switch (kernel) {
    case Kernel::kUniform: return polynomial(0);
    case Kernel::kEpanechnikov: return polynomial(1);
    case Kernel::kBiweight: return polynomial(2);
    case Kernel::kTriweight: return polynomial(3);
    case Kernel::kCone: return 3.0 / kPiD * IntegerPower(t, n + 2) * (1.0 / (n + 2) - t / (n + 3));
    case Kernel::kGaussian: {
      const double e = std::exp(-2.0 * t * t);
      if (n == 0) return kGaussianNorm * (1.0 - e) / 4.0;
      if (n == 1) return kGaussianNorm * (-t * e / 4.0 + std::sqrt(kPiD / 2.0) / 8.0 * std::erf(std::sqrt(2.0) * t));
      return kGaussianNorm * (1.0 - (1.0 + 2.0 * t * t) * e) / 8.0;
    }
  }
  return 0.0;
}

double KernelRadialMassOverSquare(Kernel kernel, double t) {
  if (t >= 1.0) return KernelRadialMass(kernel, 1.0) / (t * t);
  const double x = t * t, q = 1.0 - x;
  // (1 - q^(p+1)) / x = sum_{j=0..p} q^j for the polynomial kernels.
  const auto geometric = [&](int p) {
    double sum = 0, power = 1;
    for (int j = 0; j <= p; ++j, power *= q) sum += power;
    return sum / (2.0 * kPiD);
  };
  switch (kernel) {
    case Kernel::kUniform: return geometric(0);
    case Kernel::kEpanechnikov: return geometric(1);
    case Kernel::kBiweight: return geometric(2);
    case Kernel::kTriweight: return geometric(3);
    case Kernel::kCone: return 3.0 / kPiD * (0.5 - t / 3.0);
    case Kernel::kGaussian: return x == 0 ? kGaussianNorm / 2.0 : -kGaussianNorm * std::expm1(-2.0 * x) / (4.0 * x);
  }
  return 0.0;
}

KernelMoments MomentsOf(Kernel kernel) {
  // In polar coordinates: integral f dA = 2 pi integral_0^1 f(t) t dt; x_1^2 averages to t^2 / 2 over angle.
  const auto roughness = [&](double t) { return 2.0 * kPiD * t * KernelProfile(kernel, t) * KernelProfile(kernel, t); };
  const auto moment2 = [&](double t) { return kPiD * t * t * t * KernelProfile(kernel, t); };
  return {GaussLegendre(roughness, 0.0, 1.0, 8), GaussLegendre(moment2, 0.0, 1.0, 8)};
}

std::optional<Kernel> ParseKernel(std::string_view name) { return ParseName(name, kAllKernels, KernelName); }

std::string KernelName(Kernel kernel) {
  switch (kernel) {
    case Kernel::kUniform: return "uniform";
    case Kernel::kEpanechnikov: return "epanechnikov";
    case Kernel::kBiweight: return "biweight";
    case Kernel::kTriweight: return "triweight";
    case Kernel::kCone: return "cone";
    case Kernel::kGaussian: return "gaussian";
  }
  return "?";
}

std::string KernelNames() { return JoinNames(kAllKernels, KernelName); }

}  // namespace pb
