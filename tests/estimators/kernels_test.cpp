// Kernels are densities per unit area [1/m^2]: each must integrate to 1 over the plane, be non-negative, and
// vanish outside its support radius h.
#include "estimators/kernels.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mesh/geometry.h"

namespace pb {
namespace {

// Integral over the disk of radius h in polar coordinates, by the midpoint rule in r (exact in angle, since
// the kernel is radial), in double precision.
double RadialIntegral(Kernel kernel, float h, int steps) {
  double sum = 0;
  const double dr = double(h) / steps;
  for (int i = 0; i < steps; ++i) {
    const double r = (i + 0.5) * dr;
    sum += double(KernelDensity(kernel, float(r * r), h)) * 2.0 * M_PI * r * dr;
  }
  return sum;
}

TEST(Kernels, EpanechnikovIntegratesToOneAtEveryBandwidth) {
  for (float h : {1e-3f, 0.05f, 1.0f, 30.0f}) EXPECT_NEAR(RadialIntegral(Kernel::kEpanechnikov, h, 200000), 1.0, 1e-6);
}

TEST(Kernels, EpanechnikovIntegratesToOneOnACartesianGrid) {
  // An independent check of the radial symmetry assumption: sum over a square grid, no polar coordinates.
  const float h = 0.05f;
  const int n = 2000;
  const double cell = 2.0 * h / n;
  double sum = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = -h + (i + 0.5) * cell, y = -h + (j + 0.5) * cell;
      sum += KernelDensity(Kernel::kEpanechnikov, float(x * x + y * y), h) * cell * cell;
    }
  EXPECT_NEAR(sum, 1.0, 1e-4);  // the square grid cuts the disk's rim: error ~ (cell / h)
}

TEST(Kernels, EpanechnikovShapeAndSupport) {
  const float h = 0.2f;
  EXPECT_FLOAT_EQ(KernelDensity(Kernel::kEpanechnikov, 0.0f, h), 2.0f / (kPi * h * h));
  EXPECT_EQ(KernelDensity(Kernel::kEpanechnikov, h * h, h), 0.0f);
  EXPECT_EQ(KernelDensity(Kernel::kEpanechnikov, 4 * h * h, h), 0.0f);
  float previous = INFINITY;
  for (int i = 0; i <= 100; ++i) {
    const float r = h * float(i) / 100.0f, k = KernelDensity(Kernel::kEpanechnikov, r * r, h);
    EXPECT_GE(k, 0.0f);
    EXPECT_LE(k, previous);  // "lump" shaped: non-increasing in r
    previous = k;
  }
}

TEST(Kernels, NamesRoundTrip) {
  EXPECT_EQ(ParseKernel(KernelName(Kernel::kEpanechnikov)), Kernel::kEpanechnikov);
  EXPECT_FALSE(ParseKernel("gauss").has_value());
}

}  // namespace
}  // namespace pb
