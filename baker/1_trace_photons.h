// Stage 1: photon tracing (the paper's "How to trace a particle"; Shirley et al. 1995).
// Each light emits N_i = n Phi_i / Phi photons of flux Phi_i / N_i [W] (RGB). A photon is traced with Embree
// until it is absorbed or leaves the scene; at every surface it reaches, a PhotonHit is stored with the flux
// that arrived. Diffuse reflection samples the cosine lobe; Russian roulette survives with probability
// q = max(Kd) and divides the flux by q, so the expected flux stays exact.
//
// Determinism: photon i draws only from Rng(seed, i); photons are traced in fixed blocks whose hits are
// concatenated in block order, so the hit list is identical for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "baker/progress.h"
#include "mesh/color.h"
#include "mesh/geometry.h"
#include "mesh/lights.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

// One photon arriving at a surface. Its world position is Scene::PointAt(triangle, b1, b2) and its normal
// Scene::FrontNormal(triangle), both reconstructed exactly from what is stored. 48 bytes.
struct PhotonHit {
  Rgb power;             // flux arriving [W]
  Vector3 wi;            // unit, world, pointing back toward where the photon came from
  uint32_t surface = 0;  // SurfaceSet index
  uint32_t triangle = 0; // Scene::triangles index
  Point2 uv;             // position in the surface's chart [m]
  float b1 = 0, b2 = 0;  // barycentrics on `triangle`
  bool OnFront(const Scene& scene) const { return Dot(wi, scene.AreaVector(triangle)) > 0; }
};

struct TraceSettings {
  uint64_t photons = 0;
  uint64_t seed = 1;
  uint32_t maxBounces = 10'000;
};

struct TraceStats {
  std::vector<uint64_t> photonsPerLight;
  uint64_t emitted = 0;    // photons leaving lights
  uint64_t hits = 0;       // PhotonHits stored
  uint64_t absorbed = 0;   // photons ended by Russian roulette
  uint64_t escaped = 0;    // photons that left the scene
  uint64_t truncated = 0;  // photons cut at maxBounces (should be 0)
  RgbSum powerEmitted;     // [W], sum of the photons' initial flux
  RgbSum powerAbsorbed;    // [W], sum over hits of flux * (1 - Kd): the expected absorption
  RgbSum powerEscaped;     // [W]
  void Add(const TraceStats& block);
};

// The hits of all photons, kept in the per-block arrays they were traced into (no merged copy: merging
// 10^7 hits cost a zero-filled allocation and a page fault per 4 KiB). Block order = photon order.
struct PhotonHits {
  std::vector<std::vector<PhotonHit>> blocks;
  TraceStats stats;

  template <typename F>
  void ForEach(F&& visit) const {
    for (const auto& block : blocks)
      for (const PhotonHit& hit : block) visit(hit);
  }
};

PhotonHits TracePhotons(const Scene& scene, const SurfaceSet& surfaces, const std::vector<AreaLight>& lights,
                        const RayScene& rays, const TraceSettings& settings, const Log& log);

}  // namespace pb
