// Geometric value types. Lengths are in metres; components are float, which is Embree's precision.
// Point3 is a position, Vector3 a displacement or direction, Normal3 a unit surface normal, Point2 a position
// in a surface chart (u,v) [m]. They are distinct types so that an offset or a transform cannot mix them up.
#pragma once

#include <array>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pb {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;

struct Vector3 {
  float x = 0, y = 0, z = 0;
};
struct Point3 {
  float x = 0, y = 0, z = 0;
};
struct Normal3 {
  float x = 0, y = 0, z = 1;
};
struct Point2 {
  float u = 0, v = 0;
};

inline Vector3 operator+(Vector3 a, Vector3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vector3 operator-(Vector3 a, Vector3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vector3 operator-(Vector3 a) { return {-a.x, -a.y, -a.z}; }
inline Vector3 operator*(Vector3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vector3 operator*(float s, Vector3 a) { return a * s; }
inline Vector3 operator-(Point3 a, Point3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Point3 operator+(Point3 p, Vector3 d) { return {p.x + d.x, p.y + d.y, p.z + d.z}; }
inline Point3 operator-(Point3 p, Vector3 d) { return {p.x - d.x, p.y - d.y, p.z - d.z}; }
inline Normal3 operator-(Normal3 n) { return {-n.x, -n.y, -n.z}; }

inline Vector3 AsVector(Normal3 n) { return {n.x, n.y, n.z}; }
inline float Dot(Vector3 a, Vector3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float Dot(Vector3 a, Normal3 n) { return Dot(a, AsVector(n)); }
inline float Dot(Normal3 a, Normal3 b) { return Dot(AsVector(a), AsVector(b)); }
inline Vector3 Cross(Vector3 a, Vector3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float LengthSquared(Vector3 a) { return Dot(a, a); }
inline float Length(Vector3 a) { return std::sqrt(Dot(a, a)); }
inline Vector3 Normalize(Vector3 a) { return a * (1.0f / Length(a)); }
inline Normal3 NormalFrom(Vector3 a) {
  const Vector3 n = Normalize(a);
  return {n.x, n.y, n.z};
}
inline float MaxAbsComponent(Point3 p) { return std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}); }

inline Point2 operator-(Point2 a, Point2 b) { return {a.u - b.u, a.v - b.v}; }
inline float LengthSquared(Point2 d) { return d.u * d.u + d.v * d.v; }
// Signed area [m^2] of the 2-D triangle (a, b, c), positive when counter-clockwise; in double precision.
inline double SignedArea(Point2 a, Point2 b, Point2 c) {
  return 0.5 * ((double(b.u) - a.u) * (double(c.v) - a.v) - (double(c.u) - a.u) * (double(b.v) - a.v));
}

// A triangle in a chart [m].
using Triangle2 = std::array<Point2, 3>;

// Axis-aligned bounds in a chart [m].
struct Bounds2 {
  Point2 lo{INFINITY, INFINITY};
  Point2 hi{-INFINITY, -INFINITY};
  void Extend(Point2 p) {
    lo = {std::min(lo.u, p.u), std::min(lo.v, p.v)};
    hi = {std::max(hi.u, p.u), std::max(hi.v, p.v)};
  }
};

// An orthonormal frame around a unit normal; local z is the normal. Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited" (JCGT 6(1)): branch-free and continuous except at n.z = -1.
struct Frame {
  Vector3 s, t;
  Normal3 n;
  static Frame FromNormal(Normal3 n) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    return {{1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x}, {b, sign + n.y * n.y * a, -n.y}, n};
  }
  Vector3 ToWorld(Vector3 local) const { return s * local.x + t * local.y + AsVector(n) * local.z; }
  Vector3 ToLocal(Vector3 w) const { return {Dot(w, s), Dot(w, t), Dot(w, n)}; }
};

}  // namespace pb
