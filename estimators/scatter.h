// One scattering event at a surface, for every material class of mesh/scene.h: which lobe the path takes, its
// new direction and weight. The lobe is chosen by one uniform number with probabilities proportional to what the
// lobe reflects (Russian roulette folded into the choice), so an absorbed photon ends and a surviving one keeps
// its expected flux exactly (Shirley et al. 1995; Jensen 2001, "Realistic Image Synthesis Using Photon
// Mapping", section 5.2):
//   diffuse: P(diffuse) = max(Kd), weight Kd / max(Kd).
//   mirror:  P(diffuse) = max(Kd), P(mirror) = max(Ks) (both scaled down if they sum above 1), weights Kd / P
//            and Ks / P.
//   glass:   P(reflect) = F, P(refract) = (1 - F) max(Tf), weights 1 and Tf / max(Tf) (divided by eta^2 for
//            radiance, estimators/bsdf.h). F from estimators/specular.h; a photon on the front side enters.
// Every weight is dimensionless; expectedAbsorbed is the fraction of arriving flux the material absorbs on
// average at this event, per channel, for energy tallies.
#pragma once

#include <cstdint>

#include "estimators/bsdf.h"
#include "estimators/lambertian.h"
#include "estimators/specular.h"
#include "mesh/scene.h"

namespace pb {

enum class ScatterEvent : uint8_t { kAbsorbed, kDiffuse, kMirror, kFresnelReflection, kRefraction };

struct ScatterSample {
  ScatterEvent event = ScatterEvent::kAbsorbed;
  Vector3 wi;                // unit world direction the path continues in (unset when absorbed)
  Rgb weight;                // f cos / (pdf * P(event)); the carried flux or throughput is multiplied by it
  Rgb expectedAbsorbed;      // mean fraction of the arriving flux absorbed here, per channel
  bool transmitted = false;  // wi is on the side opposite to wo
  bool Absorbed() const { return event == ScatterEvent::kAbsorbed; }
  bool Specular() const { return event != ScatterEvent::kAbsorbed && event != ScatterEvent::kDiffuse; }
};

// The Lambertian lobe chosen with probability max(Kd): the only event of the diffuse class. `side` is the normal
// on the side the path arrived from; uEvent and uDirection are independent uniforms in [0, 1).
inline ScatterSample ScatterDiffuse(Rgb albedo, Normal3 side, float uEvent, Point2 uDirection) {
  ScatterSample s;
  s.expectedAbsorbed = Rgb{1, 1, 1} - albedo;
  const float survival = albedo.Max();
  if (uEvent >= survival) return s;
  s.event = ScatterEvent::kDiffuse;
  s.wi = SampleLambertian(albedo, side, uDirection).wi;
  s.weight = albedo / survival;
  return s;
}

// Any material class. albedo: the diffuse reflectance at the point (Kd, or Kd x its texture: Scene::AlbedoAt);
// wo: unit, pointing back along the arriving path; front: the triangle's front normal.
ScatterSample SampleScatter(const Material& material, Rgb albedo, Vector3 wo, Normal3 front, TransportMode mode,
                            float uEvent, Point2 uDirection);

}  // namespace pb
