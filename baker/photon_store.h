// The photon store: what stage 1 (baker/1_trace_photons.h) traced, as plain data that the photon file
// (baker/files/photon_file.h) saves and reads back and stage 2 bins.
//
// Photons are stored by attenuation, the paper's second way: a hit keeps the fraction of its light's photon
// flux that arrived (1 at emission, times each event's weight), and its flux [W] is Phi_l / N_l times that,
// with N_l the photons light l has emitted so far. "This method allows us to increase the number of photons
// emitted by each light source": ExtendPhotons adds photons to a store, and every earlier photon's flux follows.
#pragma once

#include <cstdint>
#include <vector>

#include "baker/runtime/huge_pages.h"
#include "mesh/color.h"
#include "mesh/geometry.h"
#include "mesh/octahedral.h"

namespace pb {

// One photon arriving at a surface, in 28 bytes. Reconstructed exactly from what is stored: its world position
// Scene::PointAt(Triangle(), b1, b2), its normal Scene::FrontNormal(Triangle()), its surface
// SurfaceSet::surfaceOfTriangle[Triangle()] and its chart position SurfaceSet::UvAt(Triangle(), b1, b2) [m].
// Its incoming direction is quantised (mesh/octahedral.h, within 8e-5 rad); the side it arrived on is exact.
struct PhotonHit {
  Rgb attenuation;            // the fraction of the photon's emitted flux that arrived, per channel, exact
  uint32_t wiOctahedral = 0;  // unit world direction back toward where the photon came from
  uint32_t triangleSide = 0;  // Scene::triangles index in bits 0-30; bit 31 set when it arrived on the front side
  float b1 = 0, b2 = 0;       // barycentrics on the triangle

  static constexpr uint32_t kFrontBit = 1u << 31;
  PhotonHit() = default;
  PhotonHit(Rgb attenuation_, Vector3 wi, uint32_t triangle, bool front, float b1_, float b2_)
      : attenuation(attenuation_), wiOctahedral(EncodeOctahedral(wi)), triangleSide(triangle | (front ? kFrontBit : 0)), b1(b1_), b2(b2_) {}
  uint32_t Triangle() const { return triangleSide & ~kFrontBit; }
  bool OnFront() const { return (triangleSide & kFrontBit) != 0; }
  Vector3 Wi() const { return DecodeOctahedral(wiOctahedral); }
};
static_assert(sizeof(PhotonHit) == 28, "the compact photon record of issue 3");

// The most a photon carries, per channel, as a fraction of its emitted flux. An event's weight is a colour over
// the probability of its lobe (estimators/scatter.h), so a photon carrying A in some channel took lobe choices of
// probability at most 1/A; only a mirror whose diffuse and mirror colours peak in different channels has weights
// above 1 (up to 2). The tracer truncates a photon that would pass this bound (its flux is tallied as forbidden),
// and a photon file with a record beyond it is refused, so that sums of hits stay far inside float's range.
inline constexpr float kMostPhotonAttenuation = 65536;

// The hits of one block of photons, in photon order, in huge-page memory (baker/runtime/huge_pages.h).
using HitBlock = std::vector<PhotonHit, HugePageAllocator<PhotonHit>>;

// Photons per block: the unit of parallel work and of deterministic ordering, counted within one light's
// stream. Large enough that a block's hits (about 2.5 per photon in a room, 28 bytes each) fill a few huge
// pages; 16 blocks per million photons still balance 2 to 16 threads.
inline constexpr uint64_t kBlockPhotons = 65536;

// The random stream of photon j of light l: up to 2^40 photons per light.
inline uint64_t PhotonStream(size_t light, uint64_t j) { return uint64_t(light) << 40 | j; }

// Photons [first, end) of light `light`'s stream; first is a multiple of kBlockPhotons and end - first <= it.
struct BlockRange {
  uint32_t light = 0;
  uint64_t first = 0, end = 0;
  bool Full() const { return end - first == kBlockPhotons; }
};

// What happened to photons. In a block the flux sums are in attenuation units (each photon leaves its light
// carrying 1 per channel); PhotonStore::stats holds them in watts.
struct TraceStats {
  uint64_t emitted = 0;    // photons leaving lights
  uint64_t hits = 0;       // PhotonStore stored
  uint64_t absorbed = 0;   // photons ended by Russian roulette
  uint64_t escaped = 0;    // photons that left the scene
  uint64_t forbidden = 0;  // photons dropped because their next event is an effect the plan turned off
  uint64_t truncated = 0;  // photons cut at maxBounces (0 unless --max-bounces is set low)
  // Events, by kind. A purely diffuse scene has only diffuse bounces.
  uint64_t diffuseBounces = 0, mirrorReflections = 0, fresnelReflections = 0, refractions = 0;
  uint64_t causticHits = 0;  // hits stored on a diffuse surface right after a specular event (L..S D)
  RgbSum fluxEmitted;       // [W], sum of the photons' initial flux
  RgbSum fluxAbsorbed;      // [W], sum over events of the flux the material absorbs on average
  RgbSum fluxEscaped;       // [W]
  RgbSum fluxForbidden;     // [W], flux dropped by forbidden effects and by the bounce limit
  uint64_t SpecularEvents() const { return mirrorReflections + fresnelReflections + refractions; }
  // Adds `block`'s counts, and its flux sums times `flux` per channel (1 to add like units).
  void Add(const TraceStats& block, Rgb flux = {1, 1, 1});
};

// The photon store: the hits of all photons by attenuation, kept in the per-block arrays they were traced into
// (no merged copy: merging 10^7 hits cost a zero-filled allocation and a page fault per 4 KiB). Blocks are
// ordered by light, then by photon.
struct PhotonStore {
  std::vector<HitBlock> blocks;
  std::vector<BlockRange> ranges;       // ranges[b]: the photons of blocks[b]
  std::vector<TraceStats> blockStats;   // blockStats[b]: in attenuation units, summed in photon order
  std::vector<Rgb> lightPower;          // Phi_l [W] of each light
  std::vector<uint64_t> emitted;        // N_l: photons light l has emitted into the store
  TraceStats stats;                     // in watts: each light's blocks, in order, times its photon flux

  // Phi_l / N_l [W]: the flux of one photon of light l, and of a hit of attenuation 1.
  Rgb PhotonFlux(size_t light) const { return emitted[light] ? lightPower[light] / float(emitted[light]) : Rgb{}; }

  // Visits every hit, in store order, with the flux [W] it brought: visit(const PhotonHit&, Rgb flux).
  template <typename F>
  void ForEach(F&& visit) const {
    for (size_t b = 0; b < blocks.size(); ++b) {
      const Rgb flux = PhotonFlux(ranges[b].light);
      for (const PhotonHit& hit : blocks[b]) visit(hit, hit.attenuation * flux);
    }
  }
  // The hits the blocks hold: stats.hits less those a HitSink took while tracing (baker/1_trace_photons.h).
  uint64_t StoredHits() const {
    uint64_t count = 0;
    for (const HitBlock& block : blocks) count += block.size();
    return count;
  }
  // Recomputes `stats` from the blocks.
  void Summarise();
};

}  // namespace pb
