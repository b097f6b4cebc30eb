// A prepared scene (baker/0_prepare_scene.h) for tests that trace photons directly rather than through Bake().
#pragma once

#include <string>
#include <vector>

#include "baker/0_prepare_scene.h"
#include "baker/1_trace_photons.h"
#include "mesh/obj_loader.h"

namespace pb::test {

struct TracedScene : PreparedScene {
  explicit TracedScene(Scene loaded) : PreparedScene(Prepare(std::move(loaded))) {}
  explicit TracedScene(const std::string& objPath) : TracedScene(LoadObj(objPath).scene) {}

  TransportPlan Plan(const std::string& effects = "auto") const {
    return PlanTransport(scene, surfaces, lights, ParseEffectOverrides(effects));
  }
  PhotonStore Trace(uint64_t photons, uint64_t seed, uint32_t maxBounces = kDefaultMaxBounces) const {
    return TracePhotons(*this, {photons, seed, maxBounces}, Log(true));
  }

 private:
  static PreparedScene Prepare(Scene scene) {
    StageClock clock;
    return PrepareScene(std::move(scene), {}, clock);
  }
};

}  // namespace pb::test
