// SurfaceRegion::KernelMass is the fraction of a kernel that lies on a surface. It is checked against known
// values (1 inside, 1/2 on a straight edge, 1/4 at a square corner, 1/6 at a 60-degree corner) and against brute
// force polar integration over a concave L-shaped region, for every kernel.
#include "estimators/surface_region.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "estimators/rng.h"

namespace pb {
namespace {

std::vector<Triangle2> Square(float lo, float hi, int cells) {  // [lo,hi]^2 cut into cells x cells x 2 triangles
  std::vector<Triangle2> t;
  const float step = (hi - lo) / float(cells);
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const Point2 a{lo + i * step, lo + j * step}, b{lo + (i + 1) * step, lo + j * step},
          c{lo + (i + 1) * step, lo + (j + 1) * step}, d{lo + i * step, lo + (j + 1) * step};
      t.push_back({a, b, c});
      t.push_back({a, d, c});  // clockwise on purpose: orientation must not matter
    }
  return t;
}

// The L-shaped polygon [0,1]^2 minus (0.5,1]^2, counter-clockwise.
const std::vector<std::array<double, 2>> kLShape = {{0, 0}, {1, 0}, {1, 0.5}, {0.5, 0.5}, {0.5, 1}, {0, 1}};

// Independent reference for x strictly inside the L: in polar coordinates about x, march each ray through the
// polygon's edges and add 2 pi * [G(t_out) - G(t_in)] / (2 pi) dtheta over its inside intervals (exact in r),
// by the midpoint rule in theta.
double PolarMass(Point2 x, Kernel kernel, double h, int angles = 20000) {
  double sum = 0;
  for (int a = 0; a < angles; ++a) {
    const double theta = (a + 0.5) * 2 * M_PI / angles, dx = std::cos(theta), dy = std::sin(theta);
    std::vector<double> crossings;
    for (size_t i = 0; i < kLShape.size(); ++i) {
      const auto p = kLShape[i], q = kLShape[(i + 1) % kLShape.size()];
      const double ex = q[0] - p[0], ey = q[1] - p[1], wx = p[0] - x.u, wy = p[1] - x.v;
      const double denominator = dx * ey - dy * ex;
      if (denominator == 0) continue;
      const double t = (wx * ey - wy * ex) / denominator, s = (wx * dy - wy * dx) / denominator;
      if (t > 0 && s >= 0 && s < 1) crossings.push_back(t);
    }
    std::sort(crossings.begin(), crossings.end());
    double enter = 0, mass = 0;
    bool inside = true;
    for (double t : crossings) {
      if (inside) mass += KernelRadialMass(kernel, t / h) - KernelRadialMass(kernel, enter / h);
      inside = !inside;
      enter = t;
    }
    sum += mass;
  }
  return sum * 2 * M_PI / angles;
}

class RegionEveryKernel : public testing::TestWithParam<Kernel> {};

TEST_P(RegionEveryKernel, KnownFractionsInsideOnEdgesAndAtCorners) {
  const SurfaceRegion square(Square(0, 1, 4));
  const Kernel k = GetParam();
  EXPECT_DOUBLE_EQ(square.KernelMass({0.5f, 0.5f}, k, 0.1), 1.0);
  EXPECT_NEAR(square.KernelMass({0.4f, 0.4f}, k, 0.3), 1.0, 1e-12);   // near interior edges only: they cancel
  EXPECT_NEAR(square.KernelMass({0.5f, 0.0f}, k, 0.1), 0.5, 1e-9);    // on the middle of an edge
  EXPECT_NEAR(square.KernelMass({0.25f, 1.0f}, k, 0.1), 0.5, 1e-9);   // on an edge, at an interior vertex
  EXPECT_NEAR(square.KernelMass({0.0f, 0.0f}, k, 0.1), 0.25, 1e-9);   // square corner
  EXPECT_NEAR(square.KernelMass({1.0f, 1.0f}, k, 0.7), 0.25, 1e-9);
  EXPECT_NEAR(square.KernelMass({0.5f, 0.5f}, k, 0.5), 1.0, 1e-9);  // support touches all four edges
  const std::vector<Triangle2> equilateral = {{Point2{0, 0}, Point2{1, 0}, Point2{0.5f, float(std::sqrt(3.0) / 2)}}};
  const SurfaceRegion wedge(equilateral);
  EXPECT_NEAR(wedge.KernelMass({0, 0}, k, 0.2), 1.0 / 6.0, 1e-7);  // 60-degree corner
}

TEST_P(RegionEveryKernel, MatchesBruteForceOnAConcaveRegion) {
  std::vector<Triangle2> l = {{Point2{0, 0}, Point2{1, 0}, Point2{1, 0.5f}},
                              {Point2{0, 0}, Point2{1, 0.5f}, Point2{0.5f, 0.5f}},
                              {Point2{0, 0}, Point2{0.5f, 0.5f}, Point2{0, 1}},
                              {Point2{0, 1}, Point2{0.5f, 0.5f}, Point2{0.5f, 1}}};
  const SurfaceRegion region(l);
  EXPECT_NEAR(region.Area(), 0.75, 1e-7);
  Rng rng(7, 0);
  for (int i = 0; i < 12; ++i) {
    Point2 x{rng.Uniform(), rng.Uniform()};
    if (x.u > 0.5f && x.v > 0.5f) x = {x.u / 2, x.v};
    const double h = 0.05 + 0.4 * rng.Uniform();
    const double exact = PolarMass(x, GetParam(), h);
    EXPECT_NEAR(region.KernelMass(x, GetParam(), h), exact, 1e-6) << "x = (" << x.u << ", " << x.v << "), h = " << h;
  }
  EXPECT_NEAR(region.KernelMass({0.5f, 0.5f}, GetParam(), 0.1), 0.75, 1e-9);  // the reflex corner
}

INSTANTIATE_TEST_SUITE_P(Region, RegionEveryKernel, testing::ValuesIn(kAllKernels),
                         [](const testing::TestParamInfo<Kernel>& info) { return KernelName(info.param); });

TEST(SurfaceRegion, InteriorEdgesCancelSoTheBoundaryIsFour) {
  EXPECT_EQ(SurfaceRegion(Square(0, 1, 1)).BoundaryEdgeCount(), 4u);
  EXPECT_EQ(SurfaceRegion(Square(0, 1, 5)).BoundaryEdgeCount(), 20u);
  EXPECT_NEAR(SurfaceRegion(Square(0, 2, 5)).Area(), 4.0, 1e-5);
}

TEST(SurfaceRegion, TJunctionsCancelNumerically) {
  // Two cells of different subdivision share an edge that only one of them splits.
  std::vector<Triangle2> t = {{Point2{0, 0}, Point2{1, 0}, Point2{1, 1}}, {Point2{0, 0}, Point2{1, 1}, Point2{0, 1}}};
  for (const Triangle2& s : Square(0, 1, 2)) t.push_back({Point2{s[0].u + 1, s[0].v}, Point2{s[1].u + 1, s[1].v},
                                                          Point2{s[2].u + 1, s[2].v}});
  const SurfaceRegion region(t);
  EXPECT_NEAR(region.KernelMass({1.0f, 0.5f}, Kernel::kEpanechnikov, 0.3), 1.0, 1e-9);
  EXPECT_NEAR(region.KernelMass({1.0f, 0.0f}, Kernel::kEpanechnikov, 0.3), 0.5, 1e-9);
}

TEST(SurfaceRegion, OverlapAreaOfBoxes) {
  const SurfaceRegion square(Square(0, 1, 3));
  EXPECT_NEAR(square.OverlapArea({{-1, -1}, {2, 2}}), 1.0, 1e-6);
  EXPECT_NEAR(square.OverlapArea({{0.5f, -1}, {2, 2}}), 0.5, 1e-6);
  EXPECT_NEAR(square.OverlapArea({{0.9f, 0.9f}, {1.2f, 1.3f}}), 0.01, 1e-6);
  EXPECT_NEAR(TriangleBoxOverlapArea({Point2{0, 0}, Point2{1, 0}, Point2{0, 1}}, {{0, 0}, {0.5f, 0.5f}}), 0.25, 1e-7);
  EXPECT_NEAR(TriangleBoxOverlapArea({Point2{0, 0}, Point2{1, 0}, Point2{0, 1}}, {{0.5f, 0.5f}, {1, 1}}), 0.0, 1e-7);
}

}  // namespace
}  // namespace pb
