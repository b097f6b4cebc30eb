#include "estimators/cover_probe.h"

#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "estimators/warps.h"

namespace pb {
namespace {

// kCoverRays directions about +z, cosine-weighted on a golden-angle spiral: the same for every point.
std::array<Vector3, kCoverRays> HemisphereSpiral() {
  std::array<Vector3, kCoverRays> d;
  for (int k = 0; k < kCoverRays; ++k) d[k] = CosineSpiralDirection(k, kCoverRays);
  return d;
}

std::vector<Triangle2> ChartTriangles(const SurfaceSet& surfaces, uint32_t s) {
  std::vector<Triangle2> triangles;
  for (uint32_t t : surfaces.surfaces[s].triangles) triangles.push_back(surfaces.cornerUv[t]);
  return triangles;
}

// Halves [0, 1] kBisections times toward where `covered` changes along a -> b.
template <typename Covered>
float BisectBy(const Covered& covered, Point2 a, Point2 b, bool coveredAtA) {
  float lo = 0, hi = 1;
  for (int k = 0; k < CoverProbe::kBisections; ++k) {
    const float mid = 0.5f * (lo + hi);
    const Point2 m{a.u + mid * (b.u - a.u), a.v + mid * (b.v - a.v)};
    (covered(m) == coveredAtA ? lo : hi) = mid;
  }
  return coveredAtA ? lo : hi;  // on the covered side: no photon that reached the surface lands in the cover
}

}  // namespace

Point2 Between(Point2 a, Point2 b, double t) {
  return {float(a.u + t * (double(b.u) - a.u)), float(a.v + t * (double(b.v) - a.v))};
}

CoverProbe::CoverProbe(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t surface)
    : scene_(scene), surfaces_(surfaces), rays_(rays), surfaceIndex_(surface), directions_(HemisphereSpiral()),
      whole_(ChartTriangles(surfaces, surface)) {}

namespace {

// Faces that touch within this many spawn offsets (2^-11 of the scene's largest coordinate: 2.4 mm in a 5 m room)
// count as touching: a cabinet's side flush with the wall it stands against, or sunk into it by less.
constexpr float kTouchingOffsets = 128;

// Whether point y lies in triangle `t` (within a millionth of its size), both in the triangle's plane.
bool InTriangle(const Scene& scene, uint32_t t, Point3 y) {
  const Point3 p0 = scene.Corner(t, 0);
  const Vector3 e1 = scene.Corner(t, 1) - p0, e2 = scene.Corner(t, 2) - p0, v = y - p0;
  const float d11 = Dot(e1, e1), d12 = Dot(e1, e2), d22 = Dot(e2, e2), v1 = Dot(v, e1), v2 = Dot(v, e2);
  const float det = d11 * d22 - d12 * d12;
  if (!(det > 0)) return false;
  const float b1 = (d22 * v1 - d12 * v2) / det, b2 = (d11 * v2 - d12 * v1) / det;
  constexpr float kSlack = -1e-6f;
  return b1 >= kSlack && b2 >= kSlack && b1 + b2 <= 1 - kSlack;
}

// Whether one of the triangles `near` touches point x (not `skip`, not one of `own`'s, nor glass with `glassIsOpen`):
// x within `reach` of its plane and over it, its unit normal n with n . along > minCosine.
bool TouchedAt(const Scene& scene, const SurfaceSet& surfaces, std::span<const uint32_t> near, float reach,
               uint32_t own, Point3 x, Vector3 along, float minCosine, uint32_t skip, bool glassIsOpen) {
  for (const uint32_t t : near) {
    if (t == skip || surfaces.surfaceOfTriangle[t] == own) continue;
    if (glassIsOpen && scene.materials[scene.triangles[t].material].kind == MaterialClass::kGlass) continue;
    const Vector3 n = Normalize(scene.AreaVector(t));
    if (!(Dot(n, along) > minCosine)) continue;
    const float apart = Dot(x - scene.Corner(t, 0), n);  // x's height over its plane
    if (std::abs(apart) <= reach && InTriangle(scene, t, x - n * apart)) return true;
  }
  return false;
}

// The triangles within `radius` of x (RayScene::TrianglesNear), in a buffer of the calling thread's.
std::span<const uint32_t> TrianglesNear(const RayScene& rays, Point3 x, float radius) {
  thread_local std::vector<uint32_t> near;
  near.clear();
  rays.TrianglesNear(x, radius, near);
  return near;
}

// Whether the ray, having met the front of triangle `hit` at point x, finds there the back of another triangle: one
// facing along the ray that touches x. Two faces that touch, one of them the side of a closed object pressed against
// the other (a bath along a wall, seen from the floor under it): which of two coincident triangles a ray meets first
// is the BVH's choice, and the object's closed side is what decides.
bool BackTouchesTheFront(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t own,
                         Point3 origin, Vector3 d, const RayHit& hit, bool glassIsOpen) {
  const float reach = kTouchingOffsets * rays.SpawnOffset();
  const Point3 x = origin + d * hit.t;
  return TouchedAt(scene, surfaces, TrianglesNear(rays, x, reach), reach, own, x, d, 0, hit.triangle, glassIsOpen);
}

// Whether point p of surface `own`, facing along n, is pressed face to face against another surface: a triangle
// facing back at it (normals opposed within 2.6 degrees) touches p (the bath's side against the wall, its bottom on
// the floor). No light reaches p; rays spawned off p would start behind the other face and find the light beyond it.
constexpr float kOpposed = 0.999f;
bool PressedAgainst(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t own, Point3 p,
                    Normal3 n, bool glassIsOpen) {
  const float reach = kTouchingOffsets * rays.SpawnOffset();
  return TouchedAt(scene, surfaces, TrianglesNear(rays, p, reach), reach, own, p, AsVector(n) * -1.0f, kOpposed,
                   UINT32_MAX, glassIsOpen);
}

// The same, at p and at four points kInsetOffsets spawn offsets from it along the chart's axes: the cover's lattice
// takes only what lies that far inside the other face, so that its contact line is found inside the footprint and a
// vertex on that line stays open (it is where the floor beside the bath meets the bath, and its value is the light
// beside it). The four points, not a strict test at p alone, so that the other face's own inner edges (a wall cut
// into triangles) leave no gaps.
constexpr float kInsetOffsets = 8;
bool PressedWellInside(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t own, Point3 p,
                       const Frame& frame) {
  const float reach = kTouchingOffsets * rays.SpawnOffset(), inset = kInsetOffsets * rays.SpawnOffset();
  const std::span<const uint32_t> near = TrianglesNear(rays, p, reach + inset);
  const Vector3 against = AsVector(frame.n) * -1.0f;
  for (const Vector3 step : {Vector3{}, frame.s * inset, frame.s * -inset, frame.t * inset, frame.t * -inset})
    if (!TouchedAt(scene, surfaces, near, reach, own, p + step, against, kOpposed, UINT32_MAX, false)) return false;
  return true;
}

// Whether the ray first meets the back of a triangle of a surface other than `own` (or a front that such a back
// touches: BackTouchesTheFront), passing through own's on a planar surface (its triangles may leave its mean plane by
// millimetres); on a curved one, whose smooth normal turns some directions into its own neighbouring triangles, the
// first triangle met decides, own or not. With
// `glassIsOpen`, a glass triangle met lets the ray out, either side (light passes it). Without `touching`, a front is
// a front (the test made point by point in the estimate, where a point query at every front met would cost more than
// the rays: the conference room's estimate took 31 s against 8).
bool MeetsABack(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t own, Point3 origin,
                Vector3 d, bool glassIsOpen, bool touching) {
  constexpr int kPassesThroughOwn = 4;
  const bool planar = surfaces.surfaces[own].planar;
  for (int pass = 0; pass < kPassesThroughOwn; ++pass) {
    const std::optional<RayHit> hit = rays.Intersect(origin, d);
    if (!hit) return false;
    const Vector3 area = scene.AreaVector(hit->triangle);
    if (glassIsOpen && scene.materials[scene.triangles[hit->triangle].material].kind == MaterialClass::kGlass) return false;
    if (!planar || surfaces.surfaceOfTriangle[hit->triangle] != own)
      return Dot(area, d) > 0 ||
             (touching && BackTouchesTheFront(scene, surfaces, rays, own, origin, d, *hit, glassIsOpen));
    origin = rays.SpawnPoint(origin + d * hit->t, NormalFrom(Dot(area, d) > 0 ? area : area * -1.0f));
  }
  return false;
}

// All but one of the directions, turned into the world by `frame`, meet a back from p.
bool AllButOneMeetABack(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t own, Point3 p,
                        const Frame& frame, const std::array<Vector3, kCoverRays>& directions, bool glassIsOpen,
                        bool touching) {
  int open = 0;
  for (const Vector3& local : directions) {
    if (!MeetsABack(scene, surfaces, rays, own, rays.SpawnPoint(p, frame.n), frame.ToWorld(local), glassIsOpen, touching))
      ++open;
    if (open > 1) return false;
  }
  return true;
}

}  // namespace

bool PressedAt(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t surface, Point3 p,
               Normal3 n) {
  return PressedAgainst(scene, surfaces, rays, surface, p, n, true);
}

bool EnclosedAt(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t surface, Point3 p,
                Normal3 n) {
  static const std::array<Vector3, kCoverRays> directions = HemisphereSpiral();
  return AllButOneMeetABack(scene, surfaces, rays, surface, p, Frame::FromNormal(n), directions, true, false);
}

// The point is on the surface's mean plane, which a surface planar to within a degree can leave by millimetres
// (the box's twisted red wall): a ray passes through the surface's own triangles.
bool CoverProbe::CoveredAt(Point2 uv) const {
  if (!whole_.Contains(uv)) return false;
  const SurfaceChart& chart = surfaces_.surfaces[surfaceIndex_].chart;
  const Point3 p = chart.origin + chart.frame.s * uv.u + chart.frame.t * uv.v;
  return PressedWellInside(scene_, surfaces_, rays_, surfaceIndex_, p, chart.frame) ||
         AllButOneMeetABack(scene_, surfaces_, rays_, surfaceIndex_, p, chart.frame, directions_, false, true);
}

// Where the open end is off the surface, the cover usually runs up to the surface's edge (a face inside a closed
// object): the edge is found by the containment test alone, and one ray test just inside it confirms that the
// cover reaches it (else the rays decide every step).
float CoverProbe::Bisect(Point2 a, Point2 b, bool coveredAtA) const {
  if (!whole_.Contains(coveredAtA ? b : a)) {
    const float edge = BisectBy([&](Point2 m) { return whole_.Contains(m); }, a, b, coveredAtA);
    if (CoveredAt(Between(a, b, edge))) return edge;
  }
  return BisectBy([&](Point2 m) { return CoveredAt(m); }, a, b, coveredAtA);
}

}  // namespace pb
