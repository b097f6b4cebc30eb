// The rays of a surface's cover (estimators/surface_cover.h): whether a point of one planar surface's (u,v) chart
// [m] lies under other geometry, and where along a chart segment that changes, to 1 / 2^kBisections of its
// length. A point is covered when it is on the surface and all but one of kCoverRays fixed directions over its
// front (a cosine-weighted spiral) first meet the back of another surface's triangle, or a front that such a back
// touches (within 2^-11 of the scene's size: an object's side flush with a wall, or sunk into it that little); or
// when it, and four points a few spawn offsets around it, are pressed face to face against another surface (PressedAt).
#pragma once

#include <array>
#include <cstdint>

#include "estimators/surface_region.h"
#include "mesh/geometry.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

inline constexpr int kCoverRays = 16;

// Whether point p of `surface`, whose front faces along unit normal n, lies inside a closed object: all but one of
// the kCoverRays directions over its front first meet the back of another surface's triangle (the cover's test,
// made at one point: a baluster's end inside its handrail, a post's foot inside the floor, where no cover lattice is
// laid because the surface is curved or narrower than two of its spacings). p is the point rays start from. A front
// is a front here, touched or not: a point query at every front met, at every point, would cost more than the rays.
bool EnclosedAt(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t surface, Point3 p,
                Normal3 n);

// Whether point p of `surface`, facing along unit normal n, is pressed face to face against another surface: a
// triangle facing back at it (normals opposed within 2.6 degrees) lies within 2^-11 of the scene's size of p, over
// it (a bath's side against a wall, its bottom on the floor). No light reaches p, and rays spawned off p would start
// behind the other face. Glass does not press.
bool PressedAt(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t surface, Point3 p,
               Normal3 n);

// The point a + t (b - a), in double, rounded to float.
Point2 Between(Point2 a, Point2 b, double t);

class CoverProbe {
 public:
  static constexpr int kBisections = 10;  // the contact line to s / 1024

  CoverProbe(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t surface);

  // Whether chart point uv is on the surface and all but one of the rays from it, over the surface's front, first
  // meet a triangle's back. Off the surface nothing is covered, so a contact line that reaches the surface's edge
  // ends there.
  bool CoveredAt(Point2 uv) const;
  // Where along a -> b the cover changes, as a fraction of the way from a, on the covered side (a photon that
  // reached the surface never lands in the cover); a is covered or not as `coveredAtA` says, b the other.
  float Bisect(Point2 a, Point2 b, bool coveredAtA) const;
  // The surface's chart triangles.
  const SurfaceRegion& Whole() const { return whole_; }

 private:
  const Scene& scene_;
  const SurfaceSet& surfaces_;
  const RayScene& rays_;
  uint32_t surfaceIndex_;
  std::array<Vector3, kCoverRays> directions_;
  SurfaceRegion whole_;
};

}  // namespace pb
