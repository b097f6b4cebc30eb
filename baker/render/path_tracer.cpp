#include "baker/render/path_tracer.h"

#include <chrono>

#include "estimators/scatter.h"
#include "estimators/surface_hit.h"
#include "mesh/errors.h"

namespace pb {
std::string SamplingName(DirectionSampling s) { return s == DirectionSampling::kBrdf ? "brdf" : "photons"; }
std::string WarpName(ImportanceWarp w) { return w == ImportanceWarp::kMipmap ? "mipmap" : "inversion"; }
std::string DomainName(MapDomain d) { return d == MapDomain::kCosineHemisphere ? "cosine" : "solid-angle"; }

void PathStats::Add(const PathStats& o) {
  paths += o.paths;
  rays += o.rays;
  importanceMaps += o.importanceMaps;
  cosineFallbacks += o.cosineFallbacks;
  importanceSeconds += o.importanceSeconds;
}

PathTracer::PathTracer(const Scene& scene, const RayScene& rays, const PhotonMap* photons, const LightSampler* lights,
                       const PathSettings& settings, const ImportanceCache* cache)
    : scene_(scene), rays_(rays), photons_(photons), lights_(lights), settings_(settings), cache_(cache) {
  PB_CHECK(settings.sampling == DirectionSampling::kBrdf || photons != nullptr || cache != nullptr,
           "photon sampling needs a photon map or a cache of maps");
  PB_CHECK(!settings.lightSampling || lights != nullptr, "light sampling needs the lights");
}

PathTracer::Direction PathTracer::SampleByPhotons(Point3 p, Normal3 side, Rgb albedo, Point2 u, PathScratch& scratch,
                                                  PathStats& stats) const {
  const auto start = std::chrono::steady_clock::now();
  const Frame frame = Frame::FromNormal(side);
  const ImportanceMap* map = cache_ ? cache_->At(p, side) : nullptr;
  if (map == nullptr && cache_ == nullptr) {
    BuildImportanceMap(scratch.map, *photons_, p, side, settings_.Map(), scratch.indices, scratch.distance2);
    map = &scratch.map;
  }
  Direction d;
  if (map == nullptr) {  // no site faces this hit's way: the cosine lobe, f cos / pdf = Kd
    d = {frame.ToWorld(SampleCosineHemisphere(u).direction), albedo};
    ++stats.cosineFallbacks;
  } else {  // f cos / pdf, with f = Kd / pi
    const ImportanceSample s = map->Sample(u, settings_.warp);
    d = {frame.ToWorld(s.direction), albedo * (kInvPi * s.direction.z / s.pdf)};
  }
  ++stats.importanceMaps;
  stats.importanceSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return d;
}

Rgb PathTracer::Trace(Point3 origin, Vector3 direction, Rng& rng, PathScratch& scratch, PathStats& stats) const {
  ++stats.paths;
  Rgb radiance, throughput{1, 1, 1};
  bool countEmission = true;  // from the camera, after a specular event, or without light sampling
  const bool sampled = settings_.lightSampling;
  // Kd / pi E_d at a hit with a diffuse lobe, before the event is chosen (so that Russian roulette does not
  // discard it): the shadow ray's part of the path.
  const auto nextEvent = [&](const SurfaceHit& at) {
    const MaterialClass kind = at.material->kind;
    if ((kind != MaterialClass::kDiffuse && kind != MaterialClass::kMirror) || at.albedo.IsBlack()) return;
    ++stats.rays;
    radiance += throughput * at.albedo * lights_->Irradiance(at.point, at.side, 1, rng).irradiance * float(kInvPi);
  };
  for (uint32_t depth = 0; depth < settings_.maxDepth; ++depth) {
    ++stats.rays;
    const auto hit = rays_.Intersect(origin, direction);
    if (!hit) {
      if (sampled && countEmission) radiance += throughput * lights_->SkyRadiance(direction);
      break;
    }
    const SurfaceHit at = SurfaceHit::Meet(scene_, *hit, direction);
    const Material& material = *at.material;
    if (at.onFront && material.IsEmissive() && countEmission) radiance += throughput * material.emission;
    if (sampled) nextEvent(at);
    const float uEvent = rng.Uniform();
    const Point2 uDirection = rng.Uniform2();
    bool transmitted = false;
    if (settings_.sampling == DirectionSampling::kPhotons && material.kind == MaterialClass::kDiffuse) {
      const float survival = at.albedo.Max();
      if (uEvent >= survival) break;
      const Direction d = SampleByPhotons(at.point, at.side, at.albedo, uDirection, scratch, stats);
      throughput = throughput * d.weight / survival;
      direction = d.wi;
      countEmission = !sampled;
    } else {
      const ScatterSample s =
          SampleScatter(material, at.albedo, -direction, at.front, TransportMode::kRadiance, uEvent, uDirection);
      if (s.Absorbed()) break;
      throughput = throughput * s.weight;
      direction = s.wi;
      transmitted = s.transmitted;
      countEmission = !sampled || s.Specular();
    }
    origin = at.NextOrigin(rays_, transmitted);
  }
  return radiance;
}

}  // namespace pb
