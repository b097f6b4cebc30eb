// Where a walker's ray meets a surface, read once for the three walkers that go on from there: the photon tracer
// (baker/1_trace_photons.cpp), the path tracer (baker/render/path_tracer.cpp) and the irradiance gatherer
// (estimators/irradiance_gather.cpp). Each then scatters by estimators/scatter.h and leaves by NextOrigin.
//   front:    the triangle's unit front normal (its winding's);
//   onFront:  the ray arrived on the front side (travelling against `front`);
//   side:     the unit normal on the side the ray arrived from;
//   albedo:   the diffuse reflectance Kd at the point, its texture applied (Scene::AlbedoAt), dimensionless;
//   point:    the hit point [m], world space.
#pragma once

#include "mesh/geometry.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"

namespace pb {

struct SurfaceHit {
  RayHit ray;
  Normal3 front;
  bool onFront = false;
  Normal3 side;
  const Material* material = nullptr;
  Rgb albedo;
  Point3 point;

  // The surface the ray of unit `direction` met at `hit`.
  static SurfaceHit Meet(const Scene& scene, const RayHit& hit, Vector3 direction) {
    SurfaceHit s;
    s.ray = hit;
    s.front = scene.FrontNormal(hit.triangle);
    s.onFront = Dot(direction, s.front) < 0;
    s.side = s.onFront ? s.front : -s.front;
    s.material = &scene.MaterialOf(hit.triangle);
    s.albedo = scene.AlbedoAt(*s.material, hit.triangle, hit.b1, hit.b2);
    s.point = scene.PointAt(hit.triangle, hit.b1, hit.b2);
    return s;
  }

  // The origin of the next ray: off the side the path leaves by, the arrival side unless it was transmitted.
  Point3 NextOrigin(const RayScene& rays, bool transmitted) const {
    return rays.SpawnPoint(point, transmitted ? -side : side);
  }
};

}  // namespace pb
