// A loaded scene with what photon tracing needs beside it (surfaces, lights, the Embree scene), for tests that
// trace photons directly rather than through Bake().
#pragma once

#include <string>
#include <vector>

#include "baker/0_plan_transport.h"
#include "baker/1_trace_photons.h"
#include "mesh/lights.h"
#include "mesh/obj_loader.h"
#include "mesh/ray_scene.h"
#include "mesh/surfaces.h"

namespace pb::test {

struct TracedScene {
  Scene scene;
  SurfaceSet surfaces;
  std::vector<AreaLight> lights;
  RayScene rays;

  explicit TracedScene(Scene loaded)
      : scene(std::move(loaded)), surfaces(BuildSurfaces(scene)), lights(CollectLights(scene, surfaces)), rays(scene) {}
  explicit TracedScene(const std::string& objPath) : TracedScene(LoadObj(objPath).scene) {}

  TransportPlan Plan(const std::string& effects = "auto") const {
    return PlanTransport(scene, surfaces, lights, ParseEffectOverrides(effects));
  }
  PhotonHits Trace(uint64_t photons, uint64_t seed, uint32_t maxBounces = 10'000) const {
    return TracePhotons(scene, lights, rays, Plan(), {photons, seed, maxBounces}, Log(true));
  }
};

}  // namespace pb::test
