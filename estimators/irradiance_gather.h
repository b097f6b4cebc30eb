// Unbiased Monte Carlo irradiance at a surface point [W/m^2]: what a path tracer's vertex bake computes, and the
// reference that photonbake's estimates are measured against (bake --reference SPP). Each of S paths gives
//   E = E_d(x) + pi L_s(x, w),   w cosine-distributed about x's normal (pdf cos / pi),
// E_d by one light sample (estimators/light_sampler.h, next-event estimation) and L_s the radiance arriving along
// w that has scattered at least once. The path goes on through the scene by each material's own event choice
// (estimators/scatter.h, radiance mode, Russian roulette folded in); where it scatters diffusely, one light
// sample adds Kd / pi E_d of the hit point; where it scatters specularly (mirror, glass), the emission it meets
// next is counted, since no light sample covers that path. Emission met right after x or after a diffuse bounce
// is not counted: the light samples already did. So every path of light is counted once (Veach 1997, ch. 10,
// with only the light sample at diffuse vertices; Kajiya 1986).
//
// The relative noise is the S paths' standard error over their mean. Deterministic for a given Rng stream.
#pragma once

#include <cstdint>

#include "estimators/light_sampler.h"
#include "estimators/rng.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"

namespace pb {

class IrradianceGatherer {
 public:
  // All must outlive the gatherer.
  IrradianceGatherer(const Scene& scene, const RayScene& rays, const LightSampler& lights, uint32_t maxDepth = 1000);

  // E at point p (local coordinates [m]) on the side of unit normal n, from `paths` paths.
  DirectSample Irradiance(Point3 p, Normal3 n, uint32_t paths, Rng& rng) const;

 private:
  // L_s along the ray from p (already offset) in direction d: radiance that scattered at least once [W/(m^2 sr)].
  Rgb ScatteredRadiance(Point3 origin, Vector3 d, Rng& rng) const;

  const Scene& scene_;
  const RayScene& rays_;
  const LightSampler& lights_;
  uint32_t maxDepth_;
};

}  // namespace pb
