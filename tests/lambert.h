// Lambert's polygon formula: the irradiance [W/m^2] at a point with normal n from a Lambertian polygon of
// radiance L [W/(m^2 sr)], E(x) = (L / 2) * sum_i beta_i (n . unit(R_i x R_{i+1})), with R_i the unit vectors
// from x to the polygon's corners and beta_i the angle between consecutive R_i. Used as the closed form of
// the square-light-over-black-floor test scene (tests/test_scenes.h).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace pb::test {

struct V3 {
  double x, y, z;
};
inline V3 Sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 CrossD(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double DotD(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 Unit(V3 a) {
  const double l = std::sqrt(DotD(a, a));
  return {a.x / l, a.y / l, a.z / l};
}

inline double LambertPolygonIrradiance(V3 x, V3 n, const std::vector<V3>& polygon, double L) {
  double sum = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const V3 a = Unit(Sub(polygon[i], x)), b = Unit(Sub(polygon[(i + 1) % polygon.size()], x));
    const double beta = std::acos(std::clamp(DotD(a, b), -1.0, 1.0));
    sum += beta * DotD(n, Unit(CrossD(a, b)));
  }
  return 0.5 * L * std::fabs(sum);
}

// The scene of WriteSquareLightOverFloor(dir, 1, 1, 1, ...): E at floor point (x, 0, z).
inline double SquareLightIrradiance(double x, double z) {
  static const std::vector<V3> light = {{-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5}};
  return LambertPolygonIrradiance({x, 0, z}, {0, 1, 0}, light, 1.0);
}

}  // namespace pb::test
