// Stage 1: photon tracing (the paper's "How to trace a particle"; Shirley et al. 1995).
// Each light that reaches a receiver (stage 0) emits N_i = floor(n Phi_i / Phi) photons (estimators/emission.h).
// A photon is traced with Embree through reflections and refractions until it is absorbed or leaves the scene;
// at every surface it reaches, a PhotonHit is stored. Each event picks one lobe of the material with Russian
// roulette folded in (estimators/scatter.h), so the expected flux stays exact.
//
// Photons are stored by attenuation (baker/photon_store.h), so ExtendPhotons can add photons to a store.
//
// Only the transport the plan asks for is compiled into the loop that runs: four instantiations of one photon
// loop, with or without diffuse bounces and with or without specular events. A purely diffuse scene runs a loop
// that never looks at Fresnel, refraction or the material class; a scene of black receivers stops at the first
// hit. A forbidden effect (--effects -NAME) drops the photon where it would happen and tallies the flux.
//
// Determinism: photon j of light l draws only from Rng(seed, PhotonStream(l, j)); each light's photons are
// traced in fixed blocks of its own stream (a block covers photons [k B, (k+1) B) of one light), and the hits are
// kept by light, then block. A store extended from n to m photons holds the same bytes as one traced with m at
// once: a light's last, partial block is continued in place, its double sums carried on in photon order.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "baker/0_plan_transport.h"
#include "baker/0_prepare_scene.h"
#include "baker/1_trace_settings.h"
#include "baker/1_trace_share.h"
#include "baker/photon_store.h"
#include "baker/runtime/progress.h"
#include "estimators/photon_map.h"
#include "mesh/color.h"
#include "mesh/geometry.h"
#include "mesh/lights.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {


// Hits reserved per photon before tracing: ~2.5 in a box, so that growth copies are rare (memory mapped, not yet
// touched, which a `ulimit -v` counts).
inline constexpr uint64_t kReservedHitsPerPhoton = 3;

// Receives each block's new hits, hits[from, end), on the thread that traced them, as soon as the block is done
// (the bake's PhotonBinner bins them while tracing goes on). It may remove the hits it takes, keeping the others in
// their order; the block's stats still count every hit. Called from many threads at once.
class HitSink {
 public:
  virtual ~HitSink() = default;
  virtual void Take(uint32_t light, HitBlock& hits, size_t from) const = 0;
};

struct TraceSettings {
  uint64_t photons = 0;  // n, over all lights
  uint64_t seed = 1;
  // Scattering events a photon may undergo after its first hit: 0 stores direct light only. A photon still going
  // after its last allowed event, or carrying more than kMostPhotonAttenuation, is truncated; its flux is tallied
  // with the forbidden flux.
  uint32_t maxBounces = kDefaultMaxBounces;
  // Whether a photon's first hit, straight from its light, is stored: false when the direct light is sampled at
  // the points instead (--direct sampled, estimators/light_sampler.h). Later hits are stored either way.
  bool storeDirect = true;
  const HitSink* sink = nullptr;  // none: every hit is stored
  const TraceShare* share = nullptr;  // none: this process traces every photon
};

// A store of no photons for these lights.
PhotonStore EmptyPhotonStore(const std::vector<Light>& lights);

// Traces settings.photons photons into a new store.
PhotonStore TracePhotons(const Scene& scene, const std::vector<Light>& lights, const RayScene& rays,
                        const TransportPlan& plan, const TraceSettings& settings, const Log& log);

// Extends `store` (traced with the same scene, plan, seed and maxBounces) so that each light has emitted
// max(N_l, its share of settings.photons) photons; Summarise()s it. Stops early, keeping every light's photons a
// prefix of its stream, when InterruptRequested() (baker/runtime/interrupt.h); returns false then.
bool ExtendPhotons(PhotonStore& store, const Scene& scene, const std::vector<Light>& lights,
                   const RayScene& rays, const TransportPlan& plan, const TraceSettings& settings, const Log& log);

// The same for a prepared scene: its lights, ray scene and plan.
PhotonStore TracePhotons(const PreparedScene& scene, const TraceSettings& settings, const Log& log);
bool ExtendPhotons(PhotonStore& store, const PreparedScene& scene, const TraceSettings& settings, const Log& log);

// Every stored hit as a photon map holds it (estimators/photon_map.h): its world position, incoming direction,
// flux and the normal of the side it arrived on.
std::vector<MapPhoton> MapPhotonsOf(const Scene& scene, const PhotonStore& hits);

}  // namespace pb
