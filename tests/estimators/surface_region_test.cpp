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

using Loop = std::vector<std::array<double, 2>>;

// The L-shaped polygon [0,1]^2 minus (0.5,1]^2, counter-clockwise.
const Loop kLShape = {{0, 0}, {1, 0}, {1, 0.5}, {0.5, 0.5}, {0.5, 1}, {0, 1}};

// Independent reference for x strictly inside the region bounded by `loops`: in polar coordinates about x, march
// each ray through the loops' edges and add [G(t_out) - G(t_in)] dtheta over its inside intervals (exact in r), by
// the midpoint rule in theta.
// Its mass and moments: along each ray, the inside intervals add G_n(t_out) - G_n(t_in) times 1, u or u u^T.
KernelMomentsAt PolarMoments(Point2 x, Kernel kernel, double h, const std::vector<Loop>& loops, int angles = 20000) {
  KernelMomentsAt m;
  for (int a = 0; a < angles; ++a) {
    const double theta = (a + 0.5) * 2 * M_PI / angles, dx = std::cos(theta), dy = std::sin(theta);
    std::vector<double> crossings;
    for (const Loop& loop : loops)
      for (size_t i = 0; i < loop.size(); ++i) {
        const auto p = loop[i], q = loop[(i + 1) % loop.size()];
        const double ex = q[0] - p[0], ey = q[1] - p[1], wx = p[0] - x.u, wy = p[1] - x.v;
        const double denominator = dx * ey - dy * ex;
        if (denominator == 0) continue;
        const double t = (wx * ey - wy * ex) / denominator, s = (wx * dy - wy * dx) / denominator;
        if (t > 0 && s >= 0 && s < 1) crossings.push_back(t);
      }
    std::sort(crossings.begin(), crossings.end());
    double enter = 0;
    bool inside = true;
    double g[3] = {0, 0, 0};
    for (double t : crossings) {
      if (inside)
        for (int n = 0; n < 3; ++n) g[n] += KernelRadialMoment(kernel, n, t / h) - KernelRadialMoment(kernel, n, enter / h);
      inside = !inside;
      enter = t;
    }
    const double w = 2 * M_PI / angles;
    m.mass += g[0] * w;
    m.first[0] += g[1] * dx * w;
    m.first[1] += g[1] * dy * w;
    m.second[0] += g[2] * dx * dx * w;
    m.second[1] += g[2] * dx * dy * w;
    m.second[2] += g[2] * dy * dy * w;
  }
  return m;
}

double PolarMass(Point2 x, Kernel kernel, double h, const std::vector<Loop>& loops = {kLShape}, int angles = 20000) {
  return PolarMoments(x, kernel, h, loops, angles).mass;
}

void ExpectMoments(const KernelMomentsAt& actual, const KernelMomentsAt& expected, double tolerance, const std::string& where) {
  EXPECT_NEAR(actual.mass, expected.mass, tolerance) << where;
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(actual.first[k], expected.first[k], tolerance) << where << " first " << k;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(actual.second[k], expected.second[k], tolerance) << where << " second " << k;
}

class RegionEveryKernel : public testing::TestWithParam<Kernel> {};

// Local linear estimation needs the kernel's first and second moments over the region, from the same boundary
// integral as its mass: checked against the polar march inside an L-shape and a square with a hole, and against
// their half-plane values on an edge (first = 2 G_1(1) times the inward normal, second = (pi / 2) G_2(1) I).
TEST_P(RegionEveryKernel, MomentsMatchBruteForceAndHalfPlanes) {
  const Kernel k = GetParam();
  std::vector<Triangle2> l = {{Point2{0, 0}, Point2{1, 0}, Point2{1, 0.5f}},
                              {Point2{0, 0}, Point2{1, 0.5f}, Point2{0.5f, 0.5f}},
                              {Point2{0, 0}, Point2{0.5f, 0.5f}, Point2{0, 1}},
                              {Point2{0, 1}, Point2{0.5f, 0.5f}, Point2{0.5f, 1}}};
  const SurfaceRegion region(l);
  Rng rng(5, 0);
  for (int i = 0; i < 10; ++i) {
    Point2 x{rng.Uniform(), rng.Uniform()};
    if (x.u > 0.5f && x.v > 0.5f) x = {x.u / 2, x.v};
    const double h = 0.05 + 0.4 * rng.Uniform();
    ExpectMoments(region.Moments(x, k, h), PolarMoments(x, k, h, {kLShape}), 2e-5,
                  "L, x = (" + std::to_string(x.u) + ", " + std::to_string(x.v) + "), h = " + std::to_string(h));
  }
  const std::vector<Triangle2> middle = {{Point2{0.4f, 0.4f}, Point2{0.6f, 0.4f}, Point2{0.6f, 0.6f}},
                                         {Point2{0.4f, 0.4f}, Point2{0.6f, 0.6f}, Point2{0.4f, 0.6f}}};
  const SurfaceRegion holed(Square(0, 1, 3), middle);
  const Loop outer = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, hole = {{0.4, 0.4}, {0.4, 0.6}, {0.6, 0.6}, {0.6, 0.4}};
  for (const Point2 x : {Point2{0.3f, 0.4f}, Point2{0.7f, 0.55f}, Point2{0.5f, 0.25f}, Point2{0.1f, 0.9f}})
    for (double h : {0.15, 0.35})
      ExpectMoments(holed.Moments(x, k, h), PolarMoments(x, k, h, {outer, hole}), 2e-5,
                    "holed, x = (" + std::to_string(x.u) + ", " + std::to_string(x.v) + "), h = " + std::to_string(h));
  const double g1 = KernelRadialMoment(k, 1, 1), g2 = KernelRadialMoment(k, 2, 1);
  const SurfaceRegion square(Square(0, 1, 4));
  ExpectMoments(square.Moments({0.5f, 0.0f}, k, 0.1), {0.5, {0, 2 * g1}, {M_PI / 2 * g2, 0, M_PI / 2 * g2}}, 1e-9,
                "on the bottom edge");
  ExpectMoments(square.Moments({0.25f, 1.0f}, k, 0.1), {0.5, {0, -2 * g1}, {M_PI / 2 * g2, 0, M_PI / 2 * g2}}, 1e-9,
                "on the top edge, at an interior vertex");
  ExpectMoments(square.Moments({0.5f, 0.5f}, k, 0.1), {1, {0, 0}, {M_PI * g2, 0, M_PI * g2}}, 1e-12, "inside");
  EXPECT_NEAR(square.Moments({0.0f, 0.0f}, k, 0.1).mass, 0.25, 1e-9) << "a corner";
  EXPECT_NEAR(square.Moments({0.0f, 0.0f}, k, 0.1).first[0], g1, 1e-9) << "a corner: integral of cos over a quarter";
}

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

// The far boundary is not integrated edge by edge but through the angle it subtends (surface_region.h); these
// regions make that angle count: a 720-gon has hundreds of edges beyond h, and a square with a square hole has
// a second loop that the cut from x crosses or passes, sometimes exactly through its corners.
TEST_P(RegionEveryKernel, MatchesBruteForceWhereTheBoundaryIsLongOrHasAHole) {
  Loop polygon;
  std::vector<Triangle2> fan;
  constexpr int kCorners = 720;
  const auto corner = [](int i) {
    const double a = 2 * M_PI * (i % kCorners) / kCorners;
    return std::array<double, 2>{0.5 + 0.5 * std::cos(a), 0.5 + 0.5 * std::sin(a)};
  };
  for (int i = 0; i < kCorners; ++i) {
    const auto p = corner(i), q = corner(i + 1);
    polygon.push_back({double(float(p[0])), double(float(p[1]))});
    fan.push_back({Point2{0.5f, 0.5f}, Point2{float(p[0]), float(p[1])}, Point2{float(q[0]), float(q[1])}});
  }
  const SurfaceRegion disc(fan);
  EXPECT_EQ(disc.BoundaryEdgeCount(), size_t(kCorners));
  const Loop outer = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, hole = {{0.4, 0.4}, {0.4, 0.6}, {0.6, 0.6}, {0.6, 0.4}};
  const Point2 o[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, i[4] = {{0.4f, 0.4f}, {0.6f, 0.4f}, {0.6f, 0.6f}, {0.4f, 0.6f}};
  std::vector<Triangle2> frame;
  for (int k = 0; k < 4; ++k) {
    frame.push_back({o[k], o[(k + 1) % 4], i[(k + 1) % 4]});
    frame.push_back({o[k], i[(k + 1) % 4], i[k]});
  }
  const SurfaceRegion holed(frame);
  EXPECT_NEAR(holed.Area(), 0.96, 1e-6);
  const Kernel k = GetParam();
  // On the cut through the hole's corners (v = 0.4 and 0.6), beside the hole, and in from the outer corners.
  for (const Point2 x : {Point2{0.3f, 0.4f}, Point2{0.35f, 0.6f}, Point2{0.8f, 0.4f}, Point2{0.7f, 0.5f},
                         Point2{0.5f, 0.3f}, Point2{0.5f, 0.75f}, Point2{0.1f, 0.5f}, Point2{0.9f, 0.9f}})
    for (double h : {0.05, 0.15, 0.35})
      EXPECT_NEAR(holed.KernelMass(x, k, h), PolarMass(x, k, h, {outer, hole}), 1e-6)
          << "square with a hole, x = (" << x.u << ", " << x.v << "), h = " << h;
  // A tent: 200 short edges along its floor, and two long slanted ones that each span many cells of the grid.
  std::vector<Triangle2> tent;
  Loop tentLoop;
  for (int n = 0; n < 200; ++n) {
    tent.push_back({Point2{0.3f, 1}, Point2{n / 200.0f, 0}, Point2{(n + 1) / 200.0f, 0}});
    tentLoop.push_back({double(n / 200.0f), 0});
  }
  tentLoop.push_back({1, 0});
  tentLoop.push_back({0.3, 1});
  const SurfaceRegion tentRegion(tent);
  for (const Point2 x : {Point2{0.3f, 0.5f}, Point2{0.5f, 0.2f}, Point2{0.3f, 0.85f}})
    for (double h : {0.05, 0.15, 0.25})
      EXPECT_NEAR(tentRegion.KernelMass(x, k, h), PolarMass(x, k, h, {tentLoop}), 1e-6)
          << "tent, x = (" << x.u << ", " << x.v << "), h = " << h;
  // The same square with its hole given as holes (SurfaceRegion(triangles, holes)): the whole square, less two
  // triangles of its middle; and a notch, a hole against the square's left edge, whose edges there cancel.
  const std::vector<Triangle2> middle = {{Point2{0.4f, 0.4f}, Point2{0.6f, 0.4f}, Point2{0.6f, 0.6f}},
                                         {Point2{0.4f, 0.4f}, Point2{0.6f, 0.6f}, Point2{0.4f, 0.6f}}};
  const SurfaceRegion cut(Square(0, 1, 5), middle);
  EXPECT_NEAR(cut.Area(), 0.96, 1e-6);
  EXPECT_NEAR(cut.OverlapArea({{0.3f, 0.3f}, {0.5f, 0.5f}}), 0.04 - 0.01, 1e-6);
  for (const Point2 x : {Point2{0.3f, 0.4f}, Point2{0.7f, 0.5f}, Point2{0.5f, 0.3f}, Point2{0.4f, 0.5f}})
    for (double h : {0.05, 0.15, 0.35}) {
      const double expected = x.u == 0.4f ? PolarMass({0.399999f, 0.5f}, k, h, {outer, hole}) : PolarMass(x, k, h, {outer, hole});
      EXPECT_NEAR(cut.KernelMass(x, k, h), expected, x.u == 0.4f ? 1e-5 : 1e-6)
          << "square less two triangles, x = (" << x.u << ", " << x.v << "), h = " << h;
    }
  const std::vector<Triangle2> notchTriangles = {{Point2{0, 0.4f}, Point2{0.3f, 0.4f}, Point2{0.3f, 0.6f}},
                                                 {Point2{0, 0.4f}, Point2{0.3f, 0.6f}, Point2{0, 0.6f}}};
  const SurfaceRegion notched(Square(0, 1, 5), notchTriangles);
  const Loop notch = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0.6}, {0.3, 0.6}, {0.3, 0.4}, {0, 0.4}};
  for (const Point2 x : {Point2{0.1f, 0.3f}, Point2{0.4f, 0.5f}, Point2{0.05f, 0.65f}})
    for (double h : {0.05, 0.2})
      EXPECT_NEAR(notched.KernelMass(x, k, h), PolarMass(x, k, h, {notch}), 1e-6)
          << "notched square, x = (" << x.u << ", " << x.v << "), h = " << h;
  Rng rng(11, 0);
  for (int n = 0; n < 8; ++n) {
    const double r = 0.5 * std::sqrt(rng.Uniform()) * 0.98, a = 2 * M_PI * rng.Uniform(), h = 0.02 + 0.3 * rng.Uniform();
    const Point2 x{float(0.5 + r * std::cos(a)), float(0.5 + r * std::sin(a))};
    EXPECT_NEAR(disc.KernelMass(x, k, h), PolarMass(x, k, h, {polygon}, 40000), 1e-6)
        << "720-gon, x = (" << x.u << ", " << x.v << "), h = " << h;
  }
}

INSTANTIATE_TEST_SUITE_P(Region, RegionEveryKernel, testing::ValuesIn(kAllKernels),
                         [](const testing::TestParamInfo<Kernel>& info) { return KernelName(info.param); });

// A star of 2,048 long spikes: each row of the region's grid is crossed by hundreds of edges that span it, which
// the cut's crossings count from per-row sums (a 65,536-corner star spent 15 s of its estimate scanning rows).
// Contains agrees with a brute-force count over every edge, inside, outside, level with corners and beyond the
// grid's bounds; KernelMass with the polar march.
TEST(SurfaceRegion, AStarsManySpanningEdgesAreCountedFromTheRowSums) {
  constexpr int kSpikes = 2048;
  Loop star;
  std::vector<Triangle2> fan;
  for (int i = 0; i < 2 * kSpikes; ++i) {
    const double a = M_PI * i / kSpikes, r = i % 2 ? 0.3 : 1.0;
    star.push_back({double(float(r * std::cos(a))), double(float(r * std::sin(a)))});
  }
  for (size_t i = 0; i < star.size(); ++i) {
    const auto p = star[i], q = star[(i + 1) % star.size()];
    fan.push_back({Point2{0, 0}, Point2{float(p[0]), float(p[1])}, Point2{float(q[0]), float(q[1])}});
  }
  const SurfaceRegion region(fan);
  const auto inside = [&](Point2 x) {  // even-odd over every edge
    bool in = false;
    for (size_t i = 0; i < star.size(); ++i) {
      const auto p = star[i], q = star[(i + 1) % star.size()];
      if ((p[1] > x.v) != (q[1] > x.v) && x.u < p[0] + (x.v - p[1]) / (q[1] - p[1]) * (q[0] - p[0])) in = !in;
    }
    return in;
  };
  Rng rng(5, 0);
  std::vector<Point2> points;
  for (int n = 0; n < 4000; ++n) points.push_back({float(2.4 * rng.Uniform() - 1.2), float(2.4 * rng.Uniform() - 1.2)});
  for (size_t i = 0; i < star.size(); i += 7)  // level with a corner, a little beside it
    for (float du : {-0.004f, 0.004f}) points.push_back({float(star[i][0]) + du, float(star[i][1])});
  int in = 0;
  for (const Point2 x : points) {
    in += inside(x);
    EXPECT_EQ(region.Contains(x), inside(x)) << "x = (" << x.u << ", " << x.v << ")";
  }
  EXPECT_GT(in, 500);  // the points fall both sides of the boundary
  EXPECT_GT(int(points.size()) - in, 500);
  // Inside a spike, with a kernel that reaches its neighbours: the far edges' angle comes from the row sums.
  const Point2 x{0.6f, 0.0f};
  EXPECT_NEAR(region.KernelMass(x, Kernel::kEpanechnikov, 0.05), PolarMass(x, Kernel::kEpanechnikov, 0.05, {star}), 1e-4);
}

// Interior edges cancel, and the 4 n edges of a gridded square's sides join into its 4 sides: the moments' cost at
// a point is that of the region's corners, not of the grid it was cut on.
TEST(SurfaceRegion, InteriorEdgesCancelAndStraightRunsJoinSoTheBoundaryIsFour) {
  EXPECT_EQ(SurfaceRegion(Square(0, 1, 1)).BoundaryEdgeCount(), 4u);
  EXPECT_EQ(SurfaceRegion(Square(0, 1, 5)).BoundaryEdgeCount(), 4u);
  EXPECT_EQ(SurfaceRegion(Square(0, 4, 160)).BoundaryEdgeCount(), 4u);
  EXPECT_NEAR(SurfaceRegion(Square(0, 2, 5)).Area(), 4.0, 1e-5);
}

// A gridded square with a gridded square hole: 8 edges, the outer sides and the hole's, and the same moments as
// the one-cell square with a one-cell hole, for points near corners and sides (a run must not join across a corner).
TEST(SurfaceRegion, AGriddedFaceWithAHoleReadsAsItsCorners) {
  const std::vector<Triangle2> hole = Square(1.0f, 2.0f, 40), coarseHole = Square(1.0f, 2.0f, 1);
  std::vector<Triangle2> face = Square(0, 4, 160), coarse = Square(0, 4, 1);
  const SurfaceRegion fine(face, hole), plain(coarse, coarseHole);
  EXPECT_EQ(fine.BoundaryEdgeCount(), 8u);
  for (const Point2 x : {Point2{0.02f, 0.03f}, Point2{0.9f, 1.5f}, Point2{2.05f, 2.1f}, Point2{3.99f, 0.5f}, Point2{0.7f, 0.7f}})
    ExpectMoments(fine.Moments(x, Kernel::kEpanechnikov, 0.4), plain.Moments(x, Kernel::kEpanechnikov, 0.4), 1e-9,
                  "x = (" + std::to_string(x.u) + ", " + std::to_string(x.v) + ")");
}

// A boundary that bends by less than the joining tolerance at each corner, but turns through 90 degrees in all
// (a quarter disc of 256 corners on a 1 m radius): its corners are kept, and its mass matches the polar march.
TEST(SurfaceRegion, ARunBendingSlowlyIsNotJoinedAcrossItsTurn) {
  constexpr int kCorners = 256;
  std::vector<Triangle2> fan;
  Loop loop = {{0, 0}};
  for (int k = 0; k < kCorners; ++k) {
    const double a0 = M_PI / 2 * k / kCorners, a1 = M_PI / 2 * (k + 1) / kCorners;
    fan.push_back({Point2{0, 0}, Point2{float(std::cos(a0)), float(std::sin(a0))}, Point2{float(std::cos(a1)), float(std::sin(a1))}});
    loop.push_back({std::cos(a0), std::sin(a0)});
  }
  loop.push_back({0, 1});
  const SurfaceRegion region(fan);
  EXPECT_GE(region.BoundaryEdgeCount(), size_t(kCorners));  // the arc's edges, and the two radii joined or not
  const Point2 x{0.6f, 0.6f};
  EXPECT_NEAR(region.KernelMass(x, Kernel::kEpanechnikov, 0.3), PolarMass(x, Kernel::kEpanechnikov, 0.3, {loop}), 1e-4);
}

// Charts put -0 where a projection rounds to zero (the box's back wall has corners at v = -0). atan2 tells -0
// from +0, so a corner at -0 on the cut once got the angle -pi while counted as above it: the box's floor corner
// read 4x too dark.
TEST(SurfaceRegion, NegativeZeroCoordinatesAreZero) {
  const float z = -0.0f;
  const std::vector<Triangle2> square = {{Point2{z, z}, Point2{-1, z}, Point2{-1, -1}}, {Point2{z, z}, Point2{-1, -1}, Point2{z, -1}}};
  const SurfaceRegion region(square);
  for (const Point2 x : {Point2{0, 0}, Point2{z, z}})
    EXPECT_NEAR(region.KernelMass(x, Kernel::kEpanechnikov, 0.1), 0.25, 1e-9) << "the corner";
  EXPECT_NEAR(region.KernelMass({-0.5f, z}, Kernel::kEpanechnikov, 0.1), 0.5, 1e-9) << "an edge";
  EXPECT_NEAR(region.KernelMass({z, -0.5f}, Kernel::kEpanechnikov, 0.1), 0.5, 1e-9) << "an edge";
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
