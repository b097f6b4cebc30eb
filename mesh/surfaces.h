// Surfaces: the units on which photon hits are binned and irradiance is estimated. Each is an edge-connected
// set of triangles of one material with a chart that maps it to (u,v) in metres, so that a density per unit
// (u,v) area is a density per unit surface area [1/m^2] (exactly on planar charts, up to the chart's area
// distortion on curved ones). Photon hits and vertex irradiance are indexed by surface.
//
// How triangles are grouped:
//   1. Flood across shared edges (positions welded by exact coordinates) between triangles of the same material
//      whose normals differ by less than `creaseDegrees` (a sharper edge is a crease and bounds a surface), while
//      every normal stays within `coneDegrees` of the first triangle's, so no chart wraps around an object.
//   2. A group whose normals all lie within `planarDegrees` of its mean normal is planar: its chart is the
//      orthogonal projection onto its plane (isometric). The published Cornell box's left wall, twisted by
//      0.35 degrees, stays one planar surface at the default of 1 degree.
//   3. Any other group is curved: it must be a topological disc, and its chart is a least-squares conformal map
//      (mesh/lscm.h, CGAL) scaled to its area. A group that is not a disc, that CGAL cannot map, or whose
//      worst triangle area distortion max(A_uv/A, A/A_uv) exceeds `maxAreaDistortion`, is cut in two across
//      its longest extent, and each part is tried again.
// A sliver whose normal float rounding could turn by more than `planarDegrees` (a polygon of thousands of corners,
// fan-triangulated, has slivers that rounding flips over) has no normal to trust: it joins whichever group reaches
// it across an edge, and does not vote on planarity.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "mesh/geometry.h"
#include "mesh/scene.h"
#include "mesh/work_progress.h"

namespace pb {

// Maps points to (u,v) [m] by orthogonal projection onto the plane through `origin` spanned by u and v.
struct SurfaceChart {
  Point3 origin;
  Frame frame;  // frame.s and frame.t are the u and v axes; frame.n is the (mean) front normal.
  Point2 ToUv(Point3 p) const {
    const Vector3 d = p - origin;
    return {Dot(d, frame.s), Dot(d, frame.t)};
  }
};

struct Surface {
  uint32_t material = 0;
  std::vector<uint32_t> triangles;  // indices into Scene::triangles, ascending.
  SurfaceChart chart;               // the projection of a planar surface; the mean plane of a curved one.
  double area = 0;                  // [m^2]
  bool planar = true;
  double areaDistortion = 1;  // worst over its triangles of max(A_uv / A, A / A_uv); 1 when planar
};

struct SurfaceOptions {
  float planarDegrees = 1.0f;
  float creaseDegrees = 40.0f;
  float coneDegrees = 60.0f;
  double maxAreaDistortion = 1.5;
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
  size_t CurvedCount() const;
  double WorstAreaDistortion() const;
};

// `placed`, when given, is told the work done in triangle passes, of two in all: the scene's triangles when they
// are grouped into smooth pieces, then each surface's as it is made.
SurfaceSet BuildSurfaces(const Scene& scene, const SurfaceOptions& options = {}, const WorkProgress& placed = {});

}  // namespace pb
