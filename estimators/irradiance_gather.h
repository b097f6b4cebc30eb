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
// ScatteredIrradiance gathers only the light that has scattered at least once, E_s = pi L_s, and ends each path
// at the first diffuse hit where a ScatteredLightField (the photons) can be read: there it adds
// Kd / pi (E_d(y) + E_s(y)), with E_d(y) by one light sample and E_s(y) read from the field. Paths that meet
// surfaces closer than the field's detail (a 1 mm gap between books) go on bouncing, as above, until they reach
// a surface the field can speak for: one level of final gathering (Jensen 1996, "Global illumination using
// photon maps", section 3: the photon map read only where the gathered ray has gone far).
//
// Guided (bake --guide-photons; Jensen 1995, as render's photon sampling, estimators/importance_cache.h): the first
// direction w is drawn from the importance map of the cache's cell at x, where one faces x's way, and weighted
// L_s cos / pdf instead of pi L_s; elsewhere, and without a cache, from the cosine lobe. The same numbers are
// drawn either way, so an unguided gather is what it was bit for bit.
//
// The relative noise is the S paths' standard error over their mean. Deterministic for a given Rng stream.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <utility>

#include "estimators/importance_cache.h"
#include "estimators/light_sampler.h"
#include "estimators/rng.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"

namespace pb {

// What the photons know where a gathered path meets a surface: the irradiance there of the light that has
// scattered at least once [W/m^2], or nothing where it is not to be trusted: a back face, or a hit whose
// distance from the path's last vertex (hit.t [m]) is below the field's own detail there.
class ScatteredLightField {
 public:
  virtual ~ScatteredLightField() = default;
  virtual std::optional<Rgb> ScatteredAt(const RayHit& hit, bool onFront) const = 0;
};

class IrradianceGatherer {
 public:
  // All must outlive the gatherer.
  // `guide`, when given, draws the first directions (and must outlive the gatherer too).
  static constexpr uint32_t kMaxDepth = 1000;  // surfaces a path meets at most: a safety cap
  IrradianceGatherer(const Scene& scene, const RayScene& rays, const LightSampler& lights,
                     uint32_t maxDepth = kMaxDepth, const ImportanceCache* guide = nullptr);

  // E at point p (local coordinates [m]) on the side of unit normal n, from `paths` paths. With `moments`, the
  // paths' moments (estimators/incident_moments.h: each path's first direction, and its light sample's) are added
  // to it; E is the same bit for bit.
  DirectSample Irradiance(Point3 p, Normal3 n, uint32_t paths, Rng& rng, IncidentMoments* moments = nullptr) const {
    return Gather(p, n, paths, rng, true, nullptr, moments);
  }
  // E_s at p, the irradiance of light scattered at least once, from `paths` paths ended where `field` is read.
  DirectSample ScatteredIrradiance(Point3 p, Normal3 n, uint32_t paths, Rng& rng, const ScatteredLightField& field,
                                   IncidentMoments* moments = nullptr) const {
    return Gather(p, n, paths, rng, false, &field, moments);
  }
  // E_s at p with as many paths as reach relative standard error `target`: a pilot of kPilotPaths, from a stream
  // of its own, predicts the count S = kPilotPaths (r / target)^2 from its relative error r (independent paths:
  // the error falls as S^-1/2), clamped to [kPilotPaths, maxPaths]; a pilot that met no light (deep in a gap,
  // where H is 10^-4 of the mouth's) takes 4 kPilotPaths. E_s then comes from S fresh paths alone; the
  // pilot is not averaged in, since the count depends on it (as LightSampler::AdaptiveIrradiance). Unbiased; the
  // returned noise is the fresh paths', and `samples` counts the pilot's paths too.
  static constexpr uint32_t kPilotPaths = 64;
  DirectSample AdaptiveScatteredIrradiance(Point3 p, Normal3 n, double target, uint32_t maxPaths, Rng& rng,
                                           const ScatteredLightField& field, IncidentMoments* moments = nullptr) const;
  // The rays its paths have cast so far, over every thread: each segment and each light sample (the work the
  // rounds weigh against the shadow rays' and the photons', baker/photons/progressive.h). A count, not a time, so
  // that what is planned from it is the same on any machine.
  uint64_t RaysCast() const { return raysCast_.load(std::memory_order_relaxed); }

 private:
  // The mean over `paths` paths of E_d (one light sample, when `direct`) + pi L_s.
  DirectSample Gather(Point3 p, Normal3 n, uint32_t paths, Rng& rng, bool direct, const ScatteredLightField* field,
                      IncidentMoments* moments) const;
  // A first direction (local, about the normal) for u, and its cos / pdf [sr]: from the map, or the cosine lobe.
  static std::pair<Vector3, float> FirstDirection(const ImportanceMap* map, Point2 u);
  // L_s along the ray from p (already offset) in direction d: radiance that scattered at least once [W/(m^2 sr)];
  // with a field, ended at the first diffuse hit where it can be read.
  // `rays` counts the rays it casts.
  Rgb ScatteredRadiance(Point3 origin, Vector3 d, Rng& rng, const ScatteredLightField* field, uint64_t& rays) const;

  const Scene& scene_;
  const RayScene& rays_;
  const LightSampler& lights_;
  uint32_t maxDepth_;
  const ImportanceCache* guide_;
  mutable std::atomic<uint64_t> raysCast_{0};
};

}  // namespace pb
