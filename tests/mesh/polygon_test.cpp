// Polygon triangulation (mesh/polygon.h): the triangles of any simple polygon tile it, by area and orientation.
#include "mesh/polygon.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace pb {
namespace {

// Signed area of triangle (a, b, c) along the unit normal n [m^2].
double SignedArea(const PolygonCorner& a, const PolygonCorner& b, const PolygonCorner& c, const PolygonCorner& n) {
  const PolygonCorner area = PolygonAreaVector({a, b, c});
  return area[0] * n[0] + area[1] * n[1] + area[2] * n[2];
}

PolygonCorner Unit(PolygonCorner v) {
  const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / l, v[1] / l, v[2] / l};
}

// Expects the triangulation of `polygon` to have n - 2 triangles, each facing the polygon's front (non-negative
// signed area), adding up to the polygon's area: with no triangle turned over, they cannot overlap and still add up.
void ExpectTiles(const std::vector<PolygonCorner>& polygon, double area, const std::string& what) {
  const PolygonTriangulation cut = TriangulatePolygon(polygon);
  ASSERT_EQ(cut.triangles.size(), polygon.size() - 2) << what;
  EXPECT_FALSE(cut.irregular) << what;
  const PolygonCorner n = Unit(PolygonAreaVector(polygon));
  double sum = 0;
  for (const auto& [a, b, c] : cut.triangles) {
    const double t = SignedArea(polygon[a], polygon[b], polygon[c], n);
    EXPECT_GE(t, -1e-12 * area) << what << ": triangle " << a << " " << b << " " << c << " is turned over";
    sum += t;
  }
  EXPECT_NEAR(sum, area, 1e-9 * area) << what;
}

// The L-shaped 3 m^2 floor of the issue (Blender's export): a fan from its first corner would cover 3.5 m^2 and
// add a back-facing 0.5 m^2 triangle.
TEST(Polygon, AnLShapedFloorKeepsItsAreaAndSide) {
  const std::vector<PolygonCorner> l = {{0, 0, 0}, {2, 0, 0}, {2, 0, -1}, {1, 0, -1}, {1, 0, -2}, {0, 0, -2}};
  // Counter-clockwise seen from +y? The area vector says which side is the front.
  const PolygonCorner n = PolygonAreaVector(l);
  EXPECT_NEAR(std::abs(n[1]), 3.0, 1e-12);
  // Rotate the start to the reflex corner's neighbour, where a fan goes wrong.
  std::vector<PolygonCorner> fromReflex(l.begin() + 4, l.end());
  fromReflex.insert(fromReflex.end(), l.begin(), l.begin() + 4);
  ExpectTiles(l, 3.0, "L");
  ExpectTiles(fromReflex, 3.0, "L from another corner");
  EXPECT_TRUE(TriangulatePolygon(fromReflex).concave);
}

TEST(Polygon, ConvexPolygonsAreCutAsAFan) {
  const std::vector<PolygonCorner> hexagon = {{1, 0, 0}, {0.5, 0.8, 0}, {-0.5, 0.8, 0}, {-1, 0, 0}, {-0.5, -0.8, 0},
                                              {0.5, -0.8, 0}};
  const PolygonTriangulation cut = TriangulatePolygon(hexagon);
  ASSERT_EQ(cut.triangles.size(), 4u);
  EXPECT_FALSE(cut.concave);
  for (uint32_t i = 0; i < 4; ++i) EXPECT_EQ(cut.triangles[i], (std::array<uint32_t, 3>{0, i + 1, i + 2}));
}

// A random star-shaped polygon of n corners (a corner at every angle, at a random radius: concave almost
// everywhere), in a random plane, `offset` from the origin, wound either way; and its area [m^2].
std::pair<std::vector<PolygonCorner>, double> RandomStar(std::mt19937& rng, int n, double offset, bool clockwise) {
  std::uniform_real_distribution<double> u(0, 1);
  const PolygonCorner axis = Unit({u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5});
  // An orthonormal frame (t, b) of the plane normal to `axis`.
  const PolygonCorner helper = std::abs(axis[0]) < 0.9 ? PolygonCorner{1, 0, 0} : PolygonCorner{0, 1, 0};
  const PolygonCorner t = Unit({axis[1] * helper[2] - axis[2] * helper[1], axis[2] * helper[0] - axis[0] * helper[2],
                                axis[0] * helper[1] - axis[1] * helper[0]});
  const PolygonCorner b{axis[1] * t[2] - axis[2] * t[1], axis[2] * t[0] - axis[0] * t[2], axis[0] * t[1] - axis[1] * t[0]};
  std::vector<PolygonCorner> polygon;
  double area = 0;
  std::vector<double> radius(static_cast<size_t>(n));
  for (double& r : radius) r = 0.2 + u(rng);
  for (int i = 0; i < n; ++i) {
    const double angle = 2 * M_PI * i / n * (clockwise ? -1 : 1);
    const double x = radius[size_t(i)] * std::cos(angle), y = radius[size_t(i)] * std::sin(angle);
    polygon.push_back({offset + x * t[0] + y * b[0], offset + x * t[1] + y * b[1], offset + x * t[2] + y * b[2]});
    const int j = (i + 1) % n;
    area += 0.5 * radius[size_t(i)] * radius[size_t(j)] * std::sin(2 * M_PI / n);
  }
  return {polygon, area};
}

TEST(Polygon, RandomStarPolygonsInAnyPlaneTileTheirArea) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const auto [polygon, area] = RandomStar(rng, 4 + int(u(rng) * 60), trial % 2 ? 1e4 : 0, trial % 3 == 0);
    ExpectTiles(polygon, area, "star " + std::to_string(trial));
  }
}

// Above 64 corners a simple polygon is cut by constrained Delaunay triangulation in O(n log n): a star of 65,536
// corners (half of them reflex) took ear clipping over 100 s, and now takes a fraction of a second.
TEST(Polygon, LargeConcavePolygonsAreCutInNLogN) {
  std::mt19937 rng(11);
  for (const int n : {65, 300, 4096, 65536}) {
    const auto [polygon, area] = RandomStar(rng, n, n % 2 ? 1e3 : 0, n == 300);
    ExpectTiles(polygon, area, "star of " + std::to_string(n));
    EXPECT_TRUE(TriangulatePolygon(polygon).concave);
  }
}

// A large polygon that touches itself (a square with a square hole, joined by a bridge walked both ways, as CAD
// exports write holes) repeats corners, which the Delaunay cut cannot keep apart; it is ear-clipped.
TEST(Polygon, LargePolygonsThatTouchThemselvesAreEarClipped) {
  std::vector<PolygonCorner> keyhole;
  const int side = 30;  // corners per side of each square: 242 corners, within what is ear-clipped
  const auto square = [&](double half, bool clockwise) {
    for (int i = 0; i <= 4 * side; ++i) {
      const int k = clockwise ? 4 * side - i : i;
      const int s = (k / side) % 4, f = k % side;
      const double a = -half + 2 * half * f / side;
      const PolygonCorner p = s == 0 ? PolygonCorner{a, -half, 0} : s == 1 ? PolygonCorner{half, a, 0}
                              : s == 2 ? PolygonCorner{-a, half, 0} : PolygonCorner{-half, -a, 0};
      keyhole.push_back(p);
    }
  };
  square(2, false);  // the outer square, closed back at its first corner (-2, -2)
  square(1, true);   // the hole, from (-1, -1) round and back, clockwise
  ASSERT_GT(keyhole.size(), 64u);
  ExpectTiles(keyhole, 16 - 4, "a square with a hole");
}

// A large polygon whose edges cross has no triangulation of its corners; it is cut as a fan (in linear time) and
// the loader warns.
TEST(Polygon, LargeSelfCrossingPolygonsAreCutAsAFan) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<PolygonCorner> scribble;
  for (int i = 0; i < 65536; ++i) scribble.push_back({u(rng), u(rng), 0});
  const PolygonTriangulation cut = TriangulatePolygon(scribble);
  EXPECT_TRUE(cut.irregular);
  ASSERT_EQ(cut.triangles.size(), scribble.size() - 2);
}

// Corners on a straight line (a rectangle with a corner in the middle of a side, as exporters write T-junctions).
TEST(Polygon, CollinearCornersGiveZeroAreaTrianglesOnly) {
  const std::vector<PolygonCorner> u = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1.5, 1, 0}, {1.5, 0.5, 0},
                                        {0.5, 0.5, 0}, {0.5, 1, 0}, {0, 1, 0}};
  ExpectTiles(u, 2 - 0.5, "U with a collinear corner");
}

// A polygon whose edges cross (a bow tie) has no valid triangulation; it is still cut into n - 2 triangles of its
// own corners, each corner used, and the loop ends.
TEST(Polygon, SelfCrossingPolygonsAreStillCut) {
  const std::vector<PolygonCorner> bowtie = {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 2, 0}, {-1, -1, 0}};
  const PolygonTriangulation cut = TriangulatePolygon(bowtie);
  ASSERT_EQ(cut.triangles.size(), 4u);
  std::vector<int> used(bowtie.size());
  for (const auto& triangle : cut.triangles)
    for (uint32_t c : triangle) {
      ASSERT_LT(c, bowtie.size());
      ++used[c];
    }
  for (int count : used) EXPECT_GE(count, 1);
}

}  // namespace
}  // namespace pb
