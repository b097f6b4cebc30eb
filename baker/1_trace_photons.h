// Stage 1: photon tracing (the paper's "How to trace a particle"; Shirley et al. 1995).
// Each light that reaches a receiver (stage 0) emits N_i = n Phi_i / Phi photons of flux Phi_i / N_i [W] (RGB).
// A photon is traced with Embree through reflections and refractions until it is absorbed or leaves the scene;
// at every surface it reaches, a PhotonHit is stored with the flux that arrived. Each event picks one lobe of
// the material with Russian roulette folded in (estimators/scatter.h), so the expected flux stays exact.
//
// Only the transport the plan asks for is compiled into the loop that runs: four instantiations of one photon
// loop, with or without diffuse bounces and with or without specular events. A purely diffuse scene runs a loop
// that never looks at Fresnel, refraction or the material class; a scene of black receivers stops at the first
// hit. A forbidden effect (--effects -NAME) drops the photon where it would happen and tallies the flux.
//
// Determinism: photon j of light l draws only from Rng(seed, PhotonStream(l, j)); each light's photons are
// traced in fixed blocks of its own stream, and the hits are concatenated by light, then block. The hit list is
// identical for any thread count, and a light's first photons are the same photons whatever the total: a bake
// with more photons continues each light's stream (the ground for adding photons to a bake later).
#pragma once

#include <cstdint>
#include <vector>

#include "baker/0_plan_transport.h"
#include "baker/huge_pages.h"
#include "baker/progress.h"
#include "mesh/color.h"
#include "mesh/geometry.h"
#include "mesh/lights.h"
#include "mesh/octahedral.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

// One photon arriving at a surface, in 28 bytes. Reconstructed exactly from what is stored: its world position
// Scene::PointAt(Triangle(), b1, b2), its normal Scene::FrontNormal(Triangle()), its surface
// SurfaceSet::surfaceOfTriangle[Triangle()] and its chart position SurfaceSet::UvAt(Triangle(), b1, b2) [m].
// Its incoming direction is quantised (mesh/octahedral.h, within 8e-5 rad); the side it arrived on is exact.
struct PhotonHit {
  Rgb power;                  // flux arriving [W], exact
  uint32_t wiOctahedral = 0;  // unit world direction back toward where the photon came from
  uint32_t triangleSide = 0;  // Scene::triangles index in bits 0-30; bit 31 set when it arrived on the front side
  float b1 = 0, b2 = 0;       // barycentrics on the triangle

  static constexpr uint32_t kFrontBit = 1u << 31;
  PhotonHit() = default;
  PhotonHit(Rgb flux, Vector3 wi, uint32_t triangle, bool front, float b1_, float b2_)
      : power(flux), wiOctahedral(EncodeOctahedral(wi)), triangleSide(triangle | (front ? kFrontBit : 0)), b1(b1_), b2(b2_) {}
  uint32_t Triangle() const { return triangleSide & ~kFrontBit; }
  bool OnFront() const { return (triangleSide & kFrontBit) != 0; }
  Vector3 Wi() const { return DecodeOctahedral(wiOctahedral); }
};
static_assert(sizeof(PhotonHit) == 28, "the compact photon record of issue 3");

// The hits of one block of photons, in photon order, in huge-page memory (baker/huge_pages.h).
using HitBlock = std::vector<PhotonHit, HugePageAllocator<PhotonHit>>;

// Photons per block: the unit of parallel work and of deterministic ordering, counted within one light's
// stream. Large enough that a block's hits (about 2.5 per photon in a room, 28 bytes each) fill a few huge
// pages; 16 blocks per million photons still balance 2 to 16 threads.
inline constexpr uint64_t kBlockPhotons = 65536;

// The random stream of photon j of light l: up to 2^40 photons per light.
inline uint64_t PhotonStream(size_t light, uint64_t j) { return uint64_t(light) << 40 | j; }

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
  uint64_t forbidden = 0;  // photons dropped because their next event is an effect the plan turned off
  uint64_t truncated = 0;  // photons cut at maxBounces (should be 0)
  // Events, by kind. A purely diffuse scene has only diffuse bounces.
  uint64_t diffuseBounces = 0, mirrorReflections = 0, fresnelReflections = 0, refractions = 0;
  uint64_t causticHits = 0;  // hits stored on a diffuse surface right after a specular event (L..S D)
  RgbSum powerEmitted;       // [W], sum of the photons' initial flux
  RgbSum powerAbsorbed;      // [W], sum over events of the flux the material absorbs on average
  RgbSum powerEscaped;       // [W]
  RgbSum powerForbidden;     // [W], flux dropped by forbidden effects
  uint64_t SpecularEvents() const { return mirrorReflections + fresnelReflections + refractions; }
  void Add(const TraceStats& block);
};

// The hits of all photons, kept in the per-block arrays they were traced into (no merged copy: merging
// 10^7 hits cost a zero-filled allocation and a page fault per 4 KiB). Blocks are ordered by light, then by
// photon; blockLight[b] is the light whose photons block b holds.
struct PhotonHits {
  std::vector<HitBlock> blocks;
  std::vector<uint32_t> blockLight;
  TraceStats stats;

  template <typename F>
  void ForEach(F&& visit) const {
    for (const auto& block : blocks)
      for (const PhotonHit& hit : block) visit(hit);
  }
};

PhotonHits TracePhotons(const Scene& scene, const std::vector<AreaLight>& lights, const RayScene& rays,
                        const TransportPlan& plan, const TraceSettings& settings, const Log& log);

}  // namespace pb
