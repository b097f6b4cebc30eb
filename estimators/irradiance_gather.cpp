#include "estimators/irradiance_gather.h"

#include <algorithm>
#include <cmath>

#include "estimators/scatter.h"
#include "estimators/surface_hit.h"
#include "estimators/warps.h"

namespace pb {

IrradianceGatherer::IrradianceGatherer(const Scene& scene, const RayScene& rays, const LightSampler& lights,
                                       uint32_t maxDepth, const ImportanceCache* guide)
    : scene_(scene), rays_(rays), lights_(lights), maxDepth_(maxDepth), guide_(guide) {}

Rgb IrradianceGatherer::ScatteredRadiance(Point3 origin, Vector3 d, Rng& rng, const ScatteredLightField* field,
                                          uint64_t& rays) const {
  Rgb radiance, throughput{1, 1, 1};
  bool countEmission = false;  // only after a specular event: the light samples cover every other path to a light
  for (uint32_t depth = 0; depth < maxDepth_; ++depth) {
    const auto hit = rays_.Intersect(origin, d);
    ++rays;
    if (!hit) {  // the sky, seen through mirrors and glass (the light samples cover it after a diffuse bounce)
      if (countEmission) radiance = radiance + throughput * lights_.SkyRadiance(d);
      break;
    }
    const SurfaceHit y = SurfaceHit::Meet(scene_, *hit, d);
    if (countEmission && y.onFront) radiance = radiance + throughput * y.material->emission;
    const float uEvent = rng.Uniform();
    const Point2 uDirection = rng.Uniform2();
    const ScatterSample s =
        SampleScatter(*y.material, y.albedo, -d, y.front, TransportMode::kRadiance, uEvent, uDirection);
    if (s.Absorbed()) break;
    if (s.event == ScatterEvent::kDiffuse) {
      // Kd / pi E_d(y), over the probability of this lobe: s.weight is Kd / P(diffuse) for cosine sampling.
      const DirectSample direct = lights_.Irradiance(y.point, y.side, 1, rng);
      ++rays;
      const std::optional<Rgb> scattered = field ? field->ScatteredAt(*hit, y.onFront) : std::nullopt;
      radiance = radiance + throughput * s.weight * (direct.irradiance + scattered.value_or(Rgb{})) * float(kInvPi);
      if (scattered) break;  // the field holds the rest of this path's light
    }
    countEmission = s.Specular();
    throughput = throughput * s.weight;
    origin = y.NextOrigin(rays_, s.transmitted);
    d = s.wi;
  }
  return radiance;
}

std::pair<Vector3, float> IrradianceGatherer::FirstDirection(const ImportanceMap* map, Point2 u) {
  if (map == nullptr) return {SampleCosineHemisphere(u).direction, float(kPi)};
  const ImportanceSample s = map->Sample(u, ImportanceWarp::kMipmap);
  return {s.direction, s.direction.z / s.pdf};
}

DirectSample IrradianceGatherer::Gather(Point3 p, Normal3 n, uint32_t paths, Rng& rng, bool direct,
                                        const ScatteredLightField* field, IncidentMoments* moments) const {
  if (paths == 0) return {};
  const Frame frame = Frame::FromNormal(n);
  const Point3 origin = rays_.SpawnPoint(p, n);
  const ImportanceMap* map = guide_ ? guide_->At(p, n) : nullptr;
  SampleMean mean;
  IncidentMoments sum;  // of the paths, each at weight 1
  uint64_t rays = direct ? paths : 0;  // the light samples at p, and below the paths' own
  for (uint32_t k = 0; k < paths; ++k) {
    IncidentMoments path;
    IncidentMoments* const each = moments != nullptr ? &path : nullptr;
    const Rgb e = direct ? lights_.Irradiance(p, n, 1, rng, each).irradiance : Rgb{};
    const Point2 u = rng.Uniform2();
    const auto [local, factor] = FirstDirection(map, u);  // factor: cos / pdf
    const Vector3 w = frame.ToWorld(local);
    const Rgb scattered = ScatteredRadiance(origin, w, rng, field, rays) * factor;
    if (each == nullptr) {
      mean.Add(e + scattered);
      continue;
    }
    if (!scattered.IsBlack()) path.Add(scattered, w, Dot(w, n));
    mean.Add(e + scattered, path.LuminanceVector());  // the path's vector x v: its light sample's and its own
    sum.Add(path);  // (one light sample predicts no covariance: the paths' spread is their noise)
  }
  if (moments != nullptr) {
    moments->Add(sum, 1.0f / float(paths));
    moments->covariance.Add(mean.VectorCovariance(), 1);
  }
  raysCast_.fetch_add(rays, std::memory_order_relaxed);
  return mean.Result();
}

DirectSample IrradianceGatherer::AdaptiveScatteredIrradiance(Point3 p, Normal3 n, double target, uint32_t maxPaths,
                                                             Rng& rng, const ScatteredLightField& field,
                                                             IncidentMoments* moments) const {
  Rng pilotRng = PilotStream(rng);
  const DirectSample pilot = ScatteredIrradiance(p, n, kPilotPaths, pilotRng, field);
  const double ratio = pilot.relativeNoise / target;
  // A pilot that met no light has said nothing of the noise (light through a gap's mouth is a rare path).
  const double wanted = Luminance(pilot.irradiance) > 0 ? std::ceil(double(kPilotPaths) * ratio * ratio) : double(4 * kPilotPaths);
  const auto count = uint32_t(std::clamp(wanted, double(kPilotPaths), double(std::max(maxPaths, kPilotPaths))));
  DirectSample result = ScatteredIrradiance(p, n, count, rng, field, moments);
  result.samples = count + kPilotPaths;
  return result;
}

}  // namespace pb
