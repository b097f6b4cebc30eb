#include "baker/render/path_tracer.h"

#include <chrono>

#include "estimators/scatter.h"
#include "estimators/warps.h"
#include "mesh/errors.h"

namespace pb {
namespace {
constexpr uint64_t kTimedEvery = 16;

// The power heuristic (Veach and Guibas 1995) of a sample drawn with pdf a, where another technique has pdf b.
float PowerHeuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 && std::isfinite(a2 + b2) ? a2 / (a2 + b2) : (a > b ? 1.0f : 0.0f);
}
}  // namespace

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

float PathTracer::Guide::Pdf(Vector3 w) const {
  const Vector3 local = frame.ToLocal(w);
  return map ? map->Pdf(local) : CosineHemispherePdf(local.z);
}

PathTracer::Guide PathTracer::GuideAt(Point3 p, Normal3 side, PathScratch& scratch, PathStats& stats) const {
  Guide guide{Frame::FromNormal(side)};
  if (settings_.sampling != DirectionSampling::kPhotons) return guide;
  // Every kTimedEvery-th map is timed, and counts for kTimedEvery: two clock reads a map cost 5% of it.
  const bool timed = stats.importanceMaps % kTimedEvery == 0;
  const auto start = timed ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
  if (cache_) {
    guide.map = cache_->At(p, side);
  } else {
    BuildImportanceMap(scratch.map, *photons_, p, side, settings_.Map(), scratch.indices, scratch.distance2);
    guide.map = &scratch.map;
  }
  ++stats.importanceMaps;
  if (guide.map == nullptr) ++stats.cosineFallbacks;  // no cached map faces this hit's way
  if (timed)
    stats.importanceSeconds +=
        kTimedEvery * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return guide;
}

PathTracer::Direction PathTracer::Sample(const Guide& guide, Rgb albedo, Point2 u) const {
  if (guide.map == nullptr) {  // the cosine lobe: f cos / pdf = Kd
    const DirectionSample d = SampleCosineHemisphere(u);
    return {guide.frame.ToWorld(d.direction), albedo, d.pdf};
  }
  const ImportanceSample s = guide.map->Sample(u, settings_.warp);
  return {guide.frame.ToWorld(s.direction), albedo * (kInvPi * s.direction.z / s.pdf), s.pdf};
}

Rgb PathTracer::NextEvent(const SurfaceHit& at, const Guide* guide, Rng& rng, PathScratch& scratch,
                          PathStats& stats) const {
  ++stats.rays;
  const LightSampler::AreaSample area = lights_->SampleAreaLights(at.point, at.side, rng, scratch.light);
  Rgb irradiance = lights_->OtherIrradiance(at.point, at.side, rng);
  if (!area.irradiance.IsBlack())
    irradiance += area.irradiance * (guide ? PowerHeuristic(area.pdf, guide->Pdf(area.from)) : 1.0f);
  return at.albedo * irradiance * float(kInvPi);
}

Rgb PathTracer::Trace(Point3 origin, Vector3 direction, Rng& rng, PathScratch& scratch, PathStats& stats) const {
  ++stats.paths;
  Rgb radiance, throughput{1, 1, 1};
  bool countEmission = true;  // from the camera, after a specular event, or without light sampling
  const bool sampled = settings_.lightSampling;
  // After a diffuse hit with light sampling: where the path left, and the pdf of its direction there (> 0), for
  // the weight of the emission it meets next; pdf 0 otherwise.
  struct Left {
    Point3 point;
    Normal3 side;
    float pdf = 0;
  } left;
  for (uint32_t depth = 0; depth < settings_.maxDepth; ++depth) {
    ++stats.rays;
    const auto hit = rays_.Intersect(origin, direction);
    if (!hit) {
      if (sampled && countEmission) radiance += throughput * lights_->SkyRadiance(direction);
      break;
    }
    const SurfaceHit at = SurfaceHit::Meet(scene_, *hit, direction);
    const Material& material = *at.material;
    if (at.onFront && material.IsEmissive()) {
      if (countEmission) {
        radiance += throughput * material.emission;
      } else if (left.pdf > 0) {  // found by the direction as well as by the shadow ray at the last hit
        const float light = lights_->AreaLightPdf(left.point, left.side, hit->triangle, at.point, scratch.light);
        radiance += throughput * material.emission * PowerHeuristic(left.pdf, light);
      }
    }
    left.pdf = 0;
    const bool lobed = (material.kind == MaterialClass::kDiffuse || material.kind == MaterialClass::kMirror) &&
                       !at.albedo.IsBlack();
    const float uEvent = rng.Uniform();
    const Point2 uDirection = rng.Uniform2();
    bool transmitted = false;
    if (material.kind == MaterialClass::kDiffuse) {
      const Guide guide = GuideAt(at.point, at.side, scratch, stats);
      if (sampled && lobed) radiance += throughput * NextEvent(at, &guide, rng, scratch, stats);
      const float survival = at.albedo.Max();
      if (uEvent >= survival) break;
      const Direction d = Sample(guide, at.albedo, uDirection);
      throughput = throughput * d.weight / survival;
      direction = d.wi;
      countEmission = !sampled;
      if (sampled) left = {at.point, at.side, d.pdf};
    } else {
      if (sampled && lobed) radiance += throughput * NextEvent(at, nullptr, rng, scratch, stats);
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
