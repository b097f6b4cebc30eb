// Surfaces: maximal sets of edge-connected, (nearly) coplanar triangles of one material. Each has an
// orthonormal chart that maps a point of its plane to (u,v) in metres, so that a density per unit (u,v) area is
// a density per unit surface area [1/m^2]. Photon hits and vertex irradiance are indexed by surface.
//
// Coplanarity: a triangle joins a surface when its front normal is within `maxNormalAngleDegrees` of the
// surface's first triangle. The default of 1 degree keeps the published Cornell box's slightly twisted left
// wall (about 0.35 degrees) as one surface. Curved meshes become one surface per facet until charts land.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "mesh/geometry.h"
#include "mesh/scene.h"

namespace pb {

// Maps points to (u,v) [m] by orthogonal projection onto the plane through `origin` spanned by u and v.
struct SurfaceChart {
  Point3 origin;
  Frame frame;  // frame.s and frame.t are the u and v axes; frame.n is the front normal.
  Point2 ToUv(Point3 p) const {
    const Vector3 d = p - origin;
    return {Dot(d, frame.s), Dot(d, frame.t)};
  }
};

struct Surface {
  uint32_t material = 0;
  std::vector<uint32_t> triangles;  // indices into Scene::triangles, ascending.
  SurfaceChart chart;
  double area = 0;  // [m^2]
};

struct SurfaceSet {
  std::vector<Surface> surfaces;
  std::vector<uint32_t> surfaceOfTriangle;       // Scene::triangles index -> surface index.
  std::vector<std::array<Point2, 3>> cornerUv;  // Scene::triangles index -> its corners' (u,v) in its surface's chart [m]

  // Chart position [m] of the point with barycentrics (b1, b2) on `triangle`.
  Point2 UvAt(uint32_t triangle, float b1, float b2) const {
    const auto& c = cornerUv[triangle];
    const float b0 = 1.0f - b1 - b2;
    return {b0 * c[0].u + b1 * c[1].u + b2 * c[2].u, b0 * c[0].v + b1 * c[1].v + b2 * c[2].v};
  }
};

SurfaceSet BuildSurfaces(const Scene& scene, float maxNormalAngleDegrees = 1.0f);

}  // namespace pb
