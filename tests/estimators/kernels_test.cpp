// Kernels are densities per unit area [1/m^2]: each must integrate to 1 over the plane, be non-negative,
// radially symmetric, non-increasing in r, and vanish outside its support radius h. Their radial mass and
// moments, used by boundary correction and automatic bandwidth, must agree with direct integration.
#include "estimators/kernels.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mesh/geometry.h"

namespace pb {
namespace {

class EveryKernel : public testing::TestWithParam<Kernel> {};

// Integral over the disk of radius h in polar coordinates by the midpoint rule in r, in double precision.
double RadialIntegral(Kernel kernel, float h, int steps, double power = 1.0, double weightExponent = 0.0) {
  double sum = 0;
  const double dr = double(h) / steps;
  for (int i = 0; i < steps; ++i) {
    const double r = (i + 0.5) * dr;
    const double k = KernelDensity(kernel, float(r * r), h);
    sum += std::pow(k, power) * std::pow(r, weightExponent) * 2.0 * M_PI * r * dr;
  }
  return sum;
}

TEST_P(EveryKernel, IntegratesToOneAtEveryBandwidth) {
  for (float h : {1e-3f, 0.05f, 1.0f, 30.0f}) EXPECT_NEAR(RadialIntegral(GetParam(), h, 200000), 1.0, 1e-6) << h;
}

TEST_P(EveryKernel, IntegratesToOneOnACartesianGridWithoutAssumingSymmetry) {
  // Sum over a square grid, in x and y: no polar coordinates, so an asymmetric kernel would show.
  const float h = 0.05f;
  const int n = 2000;
  const double cell = 2.0 * h / n;
  double sum = 0, firstMoment = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = -h + (i + 0.5) * cell, y = -h + (j + 0.5) * cell;
      const double k = KernelDensity(GetParam(), float(x * x + y * y), h) * cell * cell;
      sum += k;
      firstMoment += k * (x + 2 * y);
    }
  EXPECT_NEAR(sum, 1.0, 2e-4);  // the square grid cuts the disk's rim: error ~ (cell / h)
  EXPECT_NEAR(firstMoment / h, 0.0, 1e-6);  // centred: no drift in any direction
}

TEST_P(EveryKernel, IsRadiallySymmetricNonNegativeAndNonIncreasing) {
  const float h = 0.2f;
  float previous = INFINITY;
  for (int i = 0; i <= 100; ++i) {
    const float r = h * float(i) / 100.0f, k = KernelDensity(GetParam(), r * r, h);
    EXPECT_GE(k, 0.0f);
    EXPECT_LE(k, previous * (1 + 1e-6f));
    previous = k;
    // The same r along any direction gives the same value: the profile depends on |x| only. (At r = h the
    // rounding of x^2 + y^2 decides which side of the support edge a point falls on, so the rim is left out.)
    if (i == 100) continue;
    for (float angle : {0.3f, 1.7f, 4.0f}) {
      const float x = r * std::cos(angle), y = r * std::sin(angle);
      EXPECT_NEAR(KernelDensity(GetParam(), x * x + y * y, h), k, 1e-4f * k + 1e-6f);
    }
  }
  EXPECT_EQ(KernelDensity(GetParam(), h * h, h), 0.0f);
  EXPECT_EQ(KernelDensity(GetParam(), 4 * h * h, h), 0.0f);
}

// integral_0^min(t, 1) k(s) s^(n+1) ds by the midpoint rule.
double DirectRadialMoment(Kernel kernel, int n, double t) {
  double direct = 0;
  const int steps = 100000;
  const double tt = std::min(t, 1.0);
  for (int i = 0; i < steps; ++i) {
    const double s = (i + 0.5) * tt / steps;
    direct += KernelProfile(kernel, s) * std::pow(s, n + 1) * tt / steps;
  }
  return direct;
}

TEST_P(EveryKernel, RadialMassIsTheIntegralOfTheProfile) {
  for (double t : {0.0, 0.1, 0.5, 0.9, 1.0, 2.0})
    EXPECT_NEAR(KernelRadialMass(GetParam(), t), DirectRadialMoment(GetParam(), 0, t), 1e-9) << t;
  EXPECT_NEAR(KernelRadialMass(GetParam(), 1.0), 1.0 / (2.0 * M_PI), 1e-12);
}

TEST_P(EveryKernel, RadialMomentsAreIntegralsOfTheProfile) {
  for (int n = 0; n < 3; ++n)
    for (double t : {0.0, 0.1, 0.5, 0.9, 1.0, 2.0})
      EXPECT_NEAR(KernelRadialMoment(GetParam(), n, t), DirectRadialMoment(GetParam(), n, t), 1e-9) << "n = " << n << ", t = " << t;
  EXPECT_DOUBLE_EQ(KernelRadialMoment(GetParam(), 0, 0.7), KernelRadialMass(GetParam(), 0.7));
}

TEST_P(EveryKernel, MomentsMatchDirectIntegration) {
  const KernelMoments m = MomentsOf(GetParam());
  EXPECT_NEAR(m.roughness, RadialIntegral(GetParam(), 1.0f, 200000, 2.0), 1e-5);
  EXPECT_NEAR(m.moment2, RadialIntegral(GetParam(), 1.0f, 200000, 1.0, 2.0) / 2.0, 1e-6);  // <x_1^2> = <r^2>/2
}

TEST_P(EveryKernel, NameRoundTrips) { EXPECT_EQ(ParseKernel(KernelName(GetParam())), GetParam()); }

INSTANTIATE_TEST_SUITE_P(Kernels, EveryKernel, testing::ValuesIn(kAllKernels),
                         [](const testing::TestParamInfo<Kernel>& info) { return KernelName(info.param); });

TEST(Kernels, KnownClosedFormValues) {
  const float h = 0.2f;
  EXPECT_FLOAT_EQ(KernelDensity(Kernel::kEpanechnikov, 0.0f, h), 2.0f / (kPi * h * h));
  EXPECT_FLOAT_EQ(KernelDensity(Kernel::kUniform, 0.01f, h), 1.0f / (kPi * h * h));
  EXPECT_NEAR(MomentsOf(Kernel::kEpanechnikov).roughness, 4.0 / (3.0 * M_PI), 1e-12);  // used by closed-form test
  EXPECT_NEAR(MomentsOf(Kernel::kUniform).moment2, 0.25, 1e-12);
}

TEST(Kernels, UnknownNamesAreRefused) {
  EXPECT_FALSE(ParseKernel("gauss").has_value());
  EXPECT_FALSE(ParseKernel("").has_value());
  EXPECT_NE(KernelNames().find("triweight"), std::string::npos);
}

}  // namespace
}  // namespace pb
