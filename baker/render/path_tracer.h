// The importance-driven path tracer of the particle-tracing paper's second half (Jensen 1995, "Importance
// Driven Path Tracing using the Photon Map"). A path starts at the camera and continues at each surface in a new
// direction until it is absorbed, leaves the scene or reaches maxDepth. Radiance [W/(m^2 sr)] is collected when
// a path reaches a light's front side (the paper's pure form: lights are hit, not sampled), or, with light
// sampling (next-event estimation, the default), also from one shadow ray to the lights at each hit with a
// diffuse lobe (estimators/light_sampler.h, one sample: Kd / pi E_d, the sky and the point, spot and sun lights
// included). At a diffuse surface the area lights are then found both ways, and multiple importance sampling
// (Veach and Guibas 1995, the power heuristic) weighs the shadow ray's sample by p_l^2 / (p_l^2 + p_d^2) and the
// emission the next direction meets by p_d^2 / (p_l^2 + p_d^2), with p_l the light sampler's pdf of the direction
// and p_d the direction sampler's (the cosine lobe or the importance map) [1/sr]. The sky, point, spot and sun
// lights come from the shadow rays alone, as does the light after a mirror-class surface's diffuse event; emission
// met straight from the camera or after a mirror or glass counts whole, and a path that escapes after one sees
// the sky. Every path of light is counted once. Both samplers share all of it, so that their comparison is about
// the directions alone.
//
// At a diffuse surface the path survives with probability max(Kd) (Russian roulette) and its direction comes from
// one of two samplers:
//   kBrdf:    cosine-weighted, the BRDF alone (the baseline); weight Kd / max(Kd).
//   kPhotons: the paper's importance map. Of the N nearest photons (estimators/photon_map.h), those that arrived
//             on a surface facing the same way (normals within about 25 degrees; a refinement of the paper, as in
//             Jensen's photon map lookups) each add power x BRDF (luminance) to the region of their incoming
//             direction; a floor fraction of the total is spread over all regions (estimators/importance_map.h).
//             The direction is drawn by the chosen warp and weighted by f cos / pdf, which holds the paper's
//             scale factor s = I / (I_k n). With a cache (estimators/importance_cache.h, the default), the map is
//             that of the hit's grid cell, built once before the paths; where none in its cell faces a hit's way
//             (a surface few photons reach), its direction comes from the cosine lobe. Without one, a hit builds
//             its own map from its N nearest photons, the paper's form.
// Mirrors and glass scatter by their own lobes (estimators/scatter.h) in radiance mode.
//
// Determinism: a pixel's samples draw from one stream keyed by (seed, pixel index) in order (baker/render/render.h), so
// an image does not depend on the thread count.
#pragma once

#include <cstdint>
#include <string>

#include "estimators/enum_names.h"
#include "estimators/importance_cache.h"
#include "estimators/importance_map.h"
#include "estimators/light_sampler.h"
#include "estimators/photon_map.h"
#include "estimators/rng.h"
#include "estimators/surface_hit.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"

namespace pb {

enum class DirectionSampling : uint8_t { kBrdf, kPhotons };
inline constexpr std::array<DirectionSampling, 2> kAllSamplings = {DirectionSampling::kBrdf, DirectionSampling::kPhotons};
std::string SamplingName(DirectionSampling s);
inline constexpr std::array<ImportanceWarp, 2> kAllWarps = {ImportanceWarp::kMipmap, ImportanceWarp::kInversion};
std::string WarpName(ImportanceWarp w);
inline std::optional<DirectionSampling> ParseSampling(std::string_view s) { return ParseName(s, kAllSamplings, SamplingName); }
inline std::optional<ImportanceWarp> ParseWarp(std::string_view s) { return ParseName(s, kAllWarps, WarpName); }
inline constexpr std::array<MapDomain, 2> kMapDomains = {MapDomain::kCosineHemisphere, MapDomain::kHemisphere};
std::string DomainName(MapDomain d);  // "cosine" or "solid-angle"
inline std::optional<MapDomain> ParseDomain(std::string_view s) { return ParseName(s, kMapDomains, DomainName); }

struct PathSettings {
  DirectionSampling sampling = DirectionSampling::kBrdf;
  // N: photons per importance map (a cached map's cell holds about N, an uncached map takes the N nearest); >= 1.
  // Defaults measured on the box and the empty office (docs/render.md, "Settings"): with light sampling, MIS and
  // maps cached on the grid, N = 800, 4 x 8 regions of equal projected solid angle and a 0.3 floor (from 250,000
  // photons) did as well at equal spp as N = 1,600 or a million photons, and better than N of 200 or 400;
  // finer maps are too sparse (rare floor-weighted samples become fireflies).
  uint32_t neighbours = 800;
  int thetaRegions = 4;           // importance map rows (bands from the normal, each the same measure)
  int phiRegions = 8;             // importance map columns (azimuth)
  float floorFraction = 0.3f;     // share of the total importance spread over all regions; [0, 1]
  ImportanceWarp warp = ImportanceWarp::kMipmap;
  MapDomain domain = MapDomain::kCosineHemisphere;  // regions of equal projected (or plain) solid angle
  // Maps cached on a grid of cells of about `neighbours` photons (estimators/importance_cache.h); off, a map is
  // built at every hit from its N nearest photons (the paper's form).
  bool mapCache = true;
  bool lightSampling = true;      // one shadow ray per diffuse hit (next-event estimation); off: lights are hit
  uint32_t maxDepth = 1000;       // safety cap on surfaces per path

  MapSettings Map() const { return {neighbours, thetaRegions, phiRegions, floorFraction, domain}; }
};

// Per-thread working memory, reused from path to path.
struct PathScratch {
  ImportanceMap map;
  std::vector<uint32_t> indices;
  std::vector<float> distance2;
  LightSampler::OneSampleScratch light;
  explicit PathScratch(const PathSettings& s) : map(s.thetaRegions, s.phiRegions, s.domain) {}
};

struct PathStats {
  uint64_t paths = 0, rays = 0;
  uint64_t importanceMaps = 0;    // maps found (or built) at diffuse hits by photon sampling
  uint64_t cosineFallbacks = 0;   // of them, none: the cache held no map facing the hit's way (the cosine lobe)
  double importanceSeconds = 0;   // thread-seconds spent finding maps (or building them), estimated from 1 in 16
  void Add(const PathStats& o);
};

class PathTracer {
 public:
  // `photons` (the kd-tree) is needed for kPhotons without a cache, `lights` for lightSampling.
  PathTracer(const Scene& scene, const RayScene& rays, const PhotonMap* photons, const LightSampler* lights,
             const PathSettings& settings, const ImportanceCache* cache = nullptr);
  // Radiance arriving at `origin` from direction -`direction` [W/(m^2 sr)], one sample.
  Rgb Trace(Point3 origin, Vector3 direction, Rng& rng, PathScratch& scratch, PathStats& stats) const;

 private:
  // The distribution of directions at a diffuse hit: the importance map (kPhotons, where one is found) or the
  // cosine lobe, in the frame of the side the path arrived on.
  struct Guide {
    Frame frame;
    const ImportanceMap* map = nullptr;  // null: the cosine lobe
    float Pdf(Vector3 w) const;          // [1/sr]
  };
  struct Direction {
    Vector3 wi;
    Rgb weight;  // f cos / pdf
    float pdf;   // [1/sr]
  };
  Guide GuideAt(Point3 p, Normal3 side, PathScratch& scratch, PathStats& stats) const;
  Direction Sample(const Guide& guide, Rgb albedo, Point2 u) const;
  // Kd / pi times one sample of the lights' irradiance at a hit with a diffuse lobe, the area lights' weighted
  // against `guide` where there is one (a diffuse hit), else whole.
  Rgb NextEvent(const SurfaceHit& at, const Guide* guide, Rng& rng, PathScratch& scratch, PathStats& stats) const;

  const Scene& scene_;
  const RayScene& rays_;
  const PhotonMap* photons_;
  const LightSampler* lights_;
  PathSettings settings_;
  const ImportanceCache* cache_;
};

}  // namespace pb
