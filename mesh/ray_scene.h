// The Embree 3 ray-tracing scene behind one RAII class. Rays are in world space [m]; a hit reports the
// distance t [m] along a unit direction, the triangle (Scene::triangles index) and Embree's barycentrics
// (b1, b2), with the point at (1 - b1 - b2) p0 + b1 p1 + b2 p2.
//
// Every ray sets tnear, tfar, mask and flags explicitly. Rays are incoherent, so the COHERENT context flag is
// never set (it is 2.5x slower for them), and the scene is not ROBUST (5-15% slower); self-intersection is
// avoided by SpawnPoint's offset along the normal instead.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "mesh/geometry.h"
#include "mesh/scene.h"
#include "mesh/work_progress.h"

// Embree's device and scene handles (RTCDevice, RTCScene), declared here so that only ray_scene.cpp includes
// <embree3/rtcore.h>: nothing above this header compiles Embree's API.
struct RTCDeviceTy;
struct RTCSceneTy;

namespace pb {

struct RayHit {
  float t = 0;  // [m]
  uint32_t triangle = 0;
  float b1 = 0, b2 = 0;
};

class RayScene {
 public:
  // Builds the BVH (Embree's); `progress`, when given, hears the build in thousandths of it (a million triangles
  // take a second or more).
  explicit RayScene(const Scene& scene, const WorkProgress& progress = {});
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // The nearest hit with t in [0, tFar) along unit `direction`, or nothing if the ray leaves the scene.
  std::optional<RayHit> Intersect(Point3 origin, Vector3 direction, float tFar = INFINITY) const;
  // Whether anything lies along unit `direction` with t in [0, tFar): Intersect(...).has_value(), by Embree's
  // any-hit query (rtcOccluded1), which stops at the first hit it finds. For shadow rays.
  bool Occluded(Point3 origin, Vector3 direction, float tFar = INFINITY) const;

  // Whether a ray from `origin` (a SpawnPoint off a surface of normal n) into n's hemisphere, cut at t = `reach`,
  // could meet anything: false proves that every such ray misses, by one point query instead of the rays (Embree's
  // rtcPointQuery). Conservative: a triangle counts when its bounding box comes within `reach` of the origin and a
  // corner lies on n's side of it, less a quarter of the spawn offset for rounding, so that the surface the
  // origin was spawned from, and the coplanar triangles beside it, do not count. True, too, when more than 512
  // triangles lie within reach: looking at each would cost more than the rays it spares.
  bool MayMeetInFront(Point3 origin, Normal3 n, float reach) const;

  // Appends to `out` every triangle (Scene::triangles index) whose bounding box comes within `radius` [m] of
  // `centre`, each once, in ascending order after those already there; some farther ones may be among them (one
  // point query, rtcPointQuery: O(log triangles + found)).
  void TrianglesNear(Point3 centre, float radius, std::vector<uint32_t>& out) const;

  // The offset SpawnPoint moves a point by [m].
  float SpawnOffset() const { return spawnOffset_; }

  // A ray origin for leaving the surface at `p` on the side `side` faces: p moved off the surface by an
  // offset proportional to the scene's largest coordinate, so that the ray cannot re-hit its own triangle.
  Point3 SpawnPoint(Point3 p, Normal3 side) const { return p + AsVector(side) * spawnOffset_; }

 private:
  RTCDeviceTy* device_ = nullptr;
  RTCSceneTy* scene_ = nullptr;
  float spawnOffset_ = 0;
  const float* vertices_ = nullptr;   // Embree's copies (x, y, z per vertex), which live as long as scene_
  const uint32_t* indices_ = nullptr;  // three per triangle
};

}  // namespace pb
