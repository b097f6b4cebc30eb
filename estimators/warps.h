// Warps from the unit square [0,1)^2 to sampling domains, as Sample / Pdf / Invert sets (pbrt-v4 style).
// Each pdf states its measure: disk and triangle pdfs are per unit area of the domain, hemisphere pdfs are per
// unit solid angle [1/sr]. Directions are in a local frame whose z axis is the surface normal.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>

#include "mesh/geometry.h"

namespace pb {

// Shirley & Chiu 1997, "A Low Distortion Map Between Disk and Square": concentric map onto the unit disk.
// pdf = 1/pi per unit disk area.
Point2 SampleUniformDiskConcentric(Point2 u);
Point2 InvertUniformDiskConcentric(Point2 p);

// Cosine-weighted hemisphere (Malley's method on the concentric disk): pdf = cos(theta)/pi [1/sr].
struct DirectionSample {
  Vector3 direction;  // unit, local frame, z >= 0
  float pdf = 0;      // [1/sr]
};
DirectionSample SampleCosineHemisphere(Point2 u);
inline float CosineHemispherePdf(float cosTheta) { return cosTheta > 0 ? cosTheta * kInvPi : 0.0f; }
Point2 InvertCosineHemisphere(Vector3 localDirection);
// Direction k of n fixed ones about +z, cosine-weighted on a golden-angle spiral (u = (k + 1/2) / n, r = sqrt(u),
// phi = k pi (3 - sqrt 5)): probes that are the same for every caller (covers, portals), not random samples.
Vector3 CosineSpiralDirection(int k, int n);

// Uniform directions over the unit sphere (pdf 1/(4 pi) [1/sr]) and over the hemisphere z >= 0 (pdf 1/(2 pi)),
// by Archimedes' hat-box theorem: z is uniform.
DirectionSample SampleUniformSphere(Point2 u);
DirectionSample SampleUniformHemisphere(Point2 u);

// A spot light's directions about the z axis in proportion to glTF's falloff (mesh/scene.h): f = 1 inside the
// inner cone, ((cos t - cos outer) / (cos inner - cos outer))^2 between the cones, 0 beyond. In z = cos t the
// density is uniform above cos inner and quadratic between: with probability (1 - ci) / (1 - ci + (ci - co) / 3)
// z is uniform on [ci, 1], else z = co + (ci - co) u^(1/3). pdf = f / SpotSolidAngle [1/sr] (mesh/lights.h).
DirectionSample SampleSpotCone(Point2 u, float cosInner, float cosOuter);

// Uniform point on a triangle as barycentrics (b1, b2), point = (1-b1-b2) p0 + b1 p1 + b2 p2.
// pdf = 1/A per unit triangle area. Invert maps the barycentrics back to the square.
struct Barycentrics {
  float b1 = 0, b2 = 0;
};
Barycentrics SampleUniformTriangle(Point2 u);
Point2 InvertUniformTriangle(Barycentrics b);

// Arvo 1995, "Stratified sampling of spherical triangles" (SIGGRAPH): directions uniform over the solid angle
// that a triangle subtends at a point, pdf = 1 / Omega [1/sr]. The map is area-preserving (u.u picks the area of
// a sub-triangle, u.v a point along an arc of it), so strata of the square stay strata of the solid angle.
// Omega = 2 atan2(|a . (b x c)|, 1 + a.b + b.c + c.a) for the unit directions a, b, c to the corners
// (Van Oosterom and Strackee 1983). Everything is computed in double precision; From() refuses a triangle whose
// solid angle is below 1e-9 sr or whose point lies in its plane.
class SphericalTriangle {
 public:
  static std::optional<SphericalTriangle> From(Point3 p, Point3 v0, Point3 v1, Point3 v2);
  double SolidAngle() const { return area_; }  // [sr]
  Vector3 Sample(Point2 u) const;              // unit, world frame

 private:
  std::array<double, 3> a_{}, b_{};       // unit directions to two corners
  std::array<double, 3> towardC_{};       // the unit tangent at a of the arc from a to the third corner, c
  double area_ = 0, alpha_ = 0;           // Omega, and the angle at a between the arcs to b and c
  double cosAlpha_ = 1, sinAlpha_ = 0, cosC_ = 1;  // cos c = a . b, the side opposite c
};

// Picks index i with probability (cdf[i] - cdf[i-1]) from a non-decreasing CDF whose last entry is 1.
// Returns the index, its probability (pmf, dimensionless) and u rescaled to [0,1) within the chosen interval,
// so one uniform number can drive two decisions. Empty when the CDF is empty.
struct DiscreteSample {
  uint32_t index = 0;
  double pmf = 0;
  float uRemapped = 0;
};
std::optional<DiscreteSample> SampleDiscreteCdf(std::span<const double> cdf, float u);

}  // namespace pb
