#include "baker/render/path_tracer.h"

#include <chrono>

#include "estimators/scatter.h"
#include "estimators/surface_hit.h"
#include "mesh/errors.h"

namespace pb {
namespace {

// A neighbour whose surface normal is more than about 25 degrees from the hit's describes light arriving at a
// different surface (the floor beside a wall, the other side of a thin panel); it would steer samples toward
// directions that do not light this point.
constexpr float kSameSurfaceCosine = 0.9f;

}  // namespace

std::string SamplingName(DirectionSampling s) { return s == DirectionSampling::kBrdf ? "brdf" : "photons"; }
std::string WarpName(ImportanceWarp w) { return w == ImportanceWarp::kMipmap ? "mipmap" : "inversion"; }

void PathStats::Add(const PathStats& o) {
  paths += o.paths;
  rays += o.rays;
  importanceMaps += o.importanceMaps;
  importanceSeconds += o.importanceSeconds;
}

PathTracer::PathTracer(const Scene& scene, const RayScene& rays, const PhotonMap* photons, const PathSettings& settings)
    : scene_(scene), rays_(rays), photons_(photons), settings_(settings) {
  PB_CHECK(settings.sampling == DirectionSampling::kBrdf || photons != nullptr, "photon sampling needs a photon map");
}

PathTracer::Direction PathTracer::SampleByPhotons(Point3 p, Normal3 side, Rgb albedo, Point2 u, PathScratch& scratch,
                                                  PathStats& stats) const {
  const auto start = std::chrono::steady_clock::now();
  const Frame frame = Frame::FromNormal(side);
  const float brdf = Luminance(albedo) * kInvPi;  // Lambertian: the same for every pair of directions
  ImportanceMap& map = scratch.map;
  map.Clear();
  const size_t found = photons_->Nearest(p, settings_.neighbours, scratch.indices, scratch.distance2);
  for (size_t i = 0; i < found; ++i) {
    const MapPhoton& photon = (*photons_)[scratch.indices[i]];
    if (Dot(photon.normal, side) < kSameSurfaceCosine) continue;  // light that reached another surface
    map.Add(frame.ToLocal(photon.wi), Luminance(photon.flux) * brdf);  // ignored unless in the hemisphere
  }
  map.Finish(settings_.floorFraction);
  const ImportanceSample s = map.Sample(u, settings_.warp);
  ++stats.importanceMaps;
  stats.importanceSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // f cos / pdf, with f = Kd / pi.
  return {frame.ToWorld(s.direction), albedo * (kInvPi * s.direction.z / s.pdf)};
}

Rgb PathTracer::Trace(Point3 origin, Vector3 direction, Rng& rng, PathScratch& scratch, PathStats& stats) const {
  ++stats.paths;
  Rgb radiance, throughput{1, 1, 1};
  for (uint32_t depth = 0; depth < settings_.maxDepth; ++depth) {
    ++stats.rays;
    const auto hit = rays_.Intersect(origin, direction);
    if (!hit) break;
    const SurfaceHit at = SurfaceHit::Meet(scene_, *hit, direction);
    const Material& material = *at.material;
    if (at.onFront && material.IsEmissive()) radiance += throughput * material.emission;
    const float uEvent = rng.Uniform();
    const Point2 uDirection = rng.Uniform2();
    bool transmitted = false;
    if (settings_.sampling == DirectionSampling::kPhotons && material.kind == MaterialClass::kDiffuse) {
      const float survival = at.albedo.Max();
      if (uEvent >= survival) break;
      const Direction d = SampleByPhotons(at.point, at.side, at.albedo, uDirection, scratch, stats);
      throughput = throughput * d.weight / survival;
      direction = d.wi;
    } else {
      const ScatterSample s =
          SampleScatter(material, at.albedo, -direction, at.front, TransportMode::kRadiance, uEvent, uDirection);
      if (s.Absorbed()) break;
      throughput = throughput * s.weight;
      direction = s.wi;
      transmitted = s.transmitted;
    }
    origin = at.NextOrigin(rays_, transmitted);
  }
  return radiance;
}

}  // namespace pb
