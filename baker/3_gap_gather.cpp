#include "baker/3_gap_gather.h"

#include <algorithm>
#include <cmath>

#include "baker/option_ranges.h"
#include "baker/3_contributions.h"
#include "baker/3_surface_point.h"
#include "estimators/warps.h"

namespace pb {

void GapSettings::Validate() const {
  RequireOption(paths <= 1'000'000, "--gap-paths", "must lie in [0, 1000000] paths per point");
  RequireOption(noise == 0 || (noise >= 1e-4 && noise <= 1), "--gap-noise", "must be 0 (off) or lie in [0.0001, 1]");
  RequireOption(smallArea >= 0 && smallArea <= 1000, "--gap-small-area", "must lie in [0, 1000] h^2");
}

namespace {
// Salt the probes' and the paths' streams apart from each other and from the direct light's at the same point.
constexpr uint64_t kProbeStream = 0x9a9e'0b5e'77e5'0001ull, kPathStream = 0x9a9e'0b5e'77e5'0002ull;
constexpr float kParallelCosine = 0.5f;                       // within 60 degrees of parallel

// The surfaces of area below smallArea h^2, the smallest first (by area, then index).
std::vector<uint32_t> SmallestFirst(const SurfaceSet& surfaces, const PhotonIrradiance& photons, float smallArea) {
  std::vector<uint32_t> small;
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
    const double h = photons.Bandwidth(s);
    if (surfaces.surfaces[s].area < smallArea * h * h) small.push_back(s);
  }
  std::stable_sort(small.begin(), small.end(),
                   [&](uint32_t a, uint32_t b) { return surfaces.surfaces[a].area < surfaces.surfaces[b].area; });
  return small;
}

// How many of `small` (SmallestFirst) hold at most `share` of the triangles, taken in order.
size_t WithinShare(const SurfaceSet& surfaces, const std::vector<uint32_t>& small, float share) {
  std::vector<uint32_t> triangles(surfaces.surfaces.size(), 0);
  for (uint32_t s : surfaces.surfaceOfTriangle) ++triangles[s];
  const double budget = share * double(surfaces.surfaceOfTriangle.size());
  double taken = 0;
  for (size_t k = 0; k < small.size(); ++k)
    if ((taken += triangles[small[k]]) > budget) return k;
  return small.size();
}

}  // namespace

GapGather::GapGather(const PreparedScene& scene, const PhotonIrradiance& photons, const LightSampler& lights,
                     const GapSettings& settings, uint64_t seed, const ImportanceCache* guide)
    : scene_(scene), photons_(photons), settings_(settings), seed_(seed),
      gatherer_(scene.scene, *scene.rays, lights, IrradianceGatherer::kMaxDepth, guide), ends_(scene, photons),
      small_(scene.surfaces.surfaces.size(), 0) {
  std::vector<uint32_t> small = SmallestFirst(scene.surfaces, photons, settings.smallArea);
  const size_t within = WithinShare(scene.surfaces, small, settings.smallShare);
  for (size_t k = 0; k < within; ++k) small_[small[k]] = kUnread;
  leftOut_.assign(small.begin() + ptrdiff_t(within), small.end());
}

void GapGather::GatherAtPoints(uint32_t s, bool gathered) {
  if (small_[s] != kUnread) small_[s] = gathered ? kGatheredAtPoints : 0;
}

GapGather::Kind GapGather::KindOf(const SurfacePoint& p, const SurfacePoint& start) const {
  if (small_[p.surface] != 0) return Kind::kSmallSurface;
  if (settings_.edges && OnBoundary(p, start)) return Kind::kEdge;
  const float reach = settings_.reach * photons_.Bandwidth(p.surface);
  const RayScene& rays = *scene_.rays;
  const Frame frame = Frame::FromNormal(p.normal);
  const Point3 origin = rays.SpawnPoint(start.position, p.normal);
  Rng rng = PointStream(seed_ ^ kProbeStream, p);
  // The decision, parallel >= needed, is known as soon as enough probes have met a surface or too few are left to.
  const auto needed = uint32_t(std::ceil(settings_.facing * float(settings_.probes)));
  // Where nothing lies in front within reach (most points of a room, an LED's face), every probe would miss.
  if (needed > 0 && !rays.MayMeetInFront(origin, p.normal, reach)) return Kind::kNone;
  uint32_t parallel = 0;
  for (uint32_t k = 0; k < settings_.probes && parallel < needed && parallel + (settings_.probes - k) >= needed; ++k) {
    const Vector3 w = frame.ToWorld(SampleCosineHemisphere(rng.Uniform2()).direction);
    const auto hit = rays.Intersect(origin, w, reach);
    if (hit && std::abs(Dot(scene_.scene.FrontNormal(hit->triangle), p.normal)) >= kParallelCosine) ++parallel;
  }
  return parallel >= needed ? Kind::kNarrowGap : Kind::kNone;
}

NoisyIrradiance GapGather::Gathered(const SurfacePoint& p, const SurfacePoint& start, IncidentMoments* moments) const {
  Rng rng = PointStream(seed_ ^ kPathStream, p);
  const DirectSample e =
      settings_.noise > 0
          ? gatherer_.AdaptiveScatteredIrradiance(start.position, p.normal, settings_.noise, settings_.paths, rng, *this,
                                                  moments)
          : gatherer_.ScatteredIrradiance(start.position, p.normal, settings_.paths, rng, *this, moments);
  return {e.irradiance, e.relativeNoise};
}

std::optional<Rgb> GapGather::ScatteredAt(const RayHit& hit, bool onFront) const {
  const uint32_t s = scene_.surfaces.surfaceOfTriangle[hit.triangle];
  if (!onFront || hit.t < photons_.Bandwidth(s)) return std::nullopt;
  if (photons_.Pooled(s)) {  // read where the pooled photons' reach lies well within the path's last step
    if (hit.t < photons_.PooledRadius()) return std::nullopt;
    return ends_.Pooled(hit.triangle, hit.b1, hit.b2);
  }
  if (small_[s] == kUnread) return std::nullopt;
  // Per unit surface area: times the chart's area ratio on this triangle (1 on planar charts).
  const auto& c = scene_.surfaces.cornerUv[hit.triangle];
  const double area = scene_.scene.Area(hit.triangle);
  const float ratio = scene_.surfaces.surfaces[s].planar || !(area > 0)
                          ? 1.0f
                          : float(std::fabs(SignedArea(c[0], c[1], c[2])) / area);
  return ends_.ChartDensity(s, scene_.surfaces.UvAt(hit.triangle, hit.b1, hit.b2)) * ratio;
}

}  // namespace pb
