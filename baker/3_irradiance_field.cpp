#include "baker/3_irradiance_field.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <bit>
#include <cmath>

#include "baker/3_gap_gather.h"
#include "estimators/bandwidth.h"

namespace pb {

std::vector<float> SurfaceBandwidths(const SurfaceRegions& regions, const SurfaceBins& bins,
                                     const EstimatorSettings& settings, bool automatic) {
  std::vector<float> h(regions.size(), settings.bandwidth);
  if (!automatic) return h;
  tbb::parallel_for(size_t(0), regions.size(), [&](size_t s) {
    h[s] = ChooseBandwidth(settings.kind, settings.kernel, *regions[s], bins.Uv(s), bins.Flux(s));
  });
  return h;
}

PhotonIrradiance::PhotonIrradiance(const PreparedScene& scene, const SurfaceBins& bins,
                                   const EstimatorSettings& settings, std::vector<float> bandwidths)
    : settings_(settings), bandwidths_(std::move(bandwidths)), estimators_(bins.SurfaceCount()) {
  tbb::parallel_for(size_t(0), bins.SurfaceCount(), [&](size_t s) {
    EstimatorSettings own = settings;
    own.bandwidth = bandwidths_[s];
    estimators_[s] = scene.covers[s].Empty()
                         ? MakeDensityEstimator(own, *scene.regions[s], bins.Uv(s), bins.Flux(s), bins.BinningOf(s, 0))
                         : MakeCoveredDensityEstimator(own, *scene.regions[s], *scene.coveredRegions[s], scene.covers[s],
                                                       bins.Uv(s), bins.Flux(s), bins.BinningOf(s, 0), bins.BinningOf(s, 1));
  });
}

IrradianceSample PhotonIrradiance::WithNoise(const SurfacePoint& p) const {
  const DensityEstimator::WithNoise e = estimators_[p.surface]->EstimateWithNoise(p.uv);
  return {PerSurfaceArea(e.irradiance, p), e.relativeNoise};
}

double PhotonIrradiance::UniformNoise(uint32_t s, uint64_t hits, double area) const {
  EstimatorSettings own = settings_;
  own.bandwidth = bandwidths_[s];
  return UniformRelativeNoise(own, double(hits) / area);
}

Rng PointStream(uint64_t seed, const SurfacePoint& p) {
  const auto bits = [](float f) { return uint64_t(std::bit_cast<uint32_t>(f == 0.0f ? 0.0f : f)); };
  return Rng(seed, SplitMix64((uint64_t(p.surface) << 32) ^ bits(p.uv.u)) ^ bits(p.uv.v));
}

// On a planar surface a point within 10 steps of its region's boundary steps once inward, along the region's
// kernel centroid about it (SurfaceRegion::Moments). A step is kStepPerSpawnOffset of the rays' spawn offset, which
// is relative to the scene's size (mesh/ray_scene.h): 0.2 mm on the box, and the same share of a scene 1 mm or 1 km
// across (an absolute 0.2 mm had moved the points of a 4 mm floor 5% of the way in, and read its edges 39% high).
namespace {
constexpr double kStepPerSpawnOffset = 20, kProbeSteps = 10;
}  // namespace

SurfacePoint RayStart(const PreparedScene& scene, const SurfacePoint& p) {
  const Surface& surface = scene.surfaces.surfaces[p.surface];
  if (!surface.planar) return p;
  const double step = kStepPerSpawnOffset * scene.rays->SpawnOffset();
  const KernelMomentsAt m = scene.regions[p.surface]->Moments(p.uv, Kernel::kUniform, kProbeSteps * step);
  const double length = std::hypot(m.first[0], m.first[1]);
  if (!(length > 0)) return p;
  const float du = float(step * m.first[0] / length), dv = float(step * m.first[1] / length);
  SurfacePoint start = p;
  start.position = p.position + surface.chart.frame.s * du + surface.chart.frame.t * dv;
  start.uv = {p.uv.u + du, p.uv.v + dv};
  return start;
}

IrradianceSample PointSampledIrradiance::WithNoise(const SurfacePoint& p) const {
  Rng rng = PointStream(seed_, p);
  const DirectSample e = Sample(RayStart(scene_, p).position, p.normal, count_, rng);
  return {e.irradiance, e.relativeNoise};
}

DirectIrradiance::DirectIrradiance(const PreparedScene& scene, const DirectSettings& direct, uint64_t seed)
    : PointSampledIrradiance(scene, direct.samples, seed), sampler_(scene.scene, scene.lights, *scene.rays),
      noise_(direct.noise) {}

ReferenceIrradiance::ReferenceIrradiance(const PreparedScene& scene, uint32_t paths, uint64_t seed)
    : PointSampledIrradiance(scene, paths, seed), lights_(scene.scene, scene.lights, *scene.rays),
      gatherer_(scene.scene, *scene.rays, lights_) {}

IrradianceField::IrradianceField(const PreparedScene& scene, std::unique_ptr<PhotonIrradiance> photons)
    : scene_(&scene), photons_(photons.get()) {
  contributions_.push_back(std::move(photons));
}

void IrradianceField::Add(std::unique_ptr<IrradianceContribution> contribution) {
  contributions_.push_back(std::move(contribution));
}

void IrradianceField::GatherGaps(std::unique_ptr<GapGather> gaps) { gaps_ = std::move(gaps); }

std::optional<IrradianceSample> IrradianceField::GapTerm(const SurfacePoint& p) const {
  if (!gaps_) return std::nullopt;
  const SurfacePoint start = RayStart(*scene_, p);
  if (!gaps_->InGap(p, start)) return std::nullopt;
  return gaps_->Gathered(p, start);
}

Rgb IrradianceField::Irradiance(const SurfacePoint& p) const {
  const std::optional<IrradianceSample> gap = GapTerm(p);
  Rgb sum = gap ? gap->irradiance : contributions_.front()->At(p);
  for (size_t i = 1; i < contributions_.size(); ++i) sum = sum + contributions_[i]->At(p);
  return sum;
}

SurfaceLight IrradianceField::LightWith(const SurfacePoint& p, Rgb irradiance) const {
  const Material& material = scene_->scene.materials[scene_->surfaces.surfaces[p.surface].material];
  return {irradiance, scene_->scene.AlbedoAtTexcoord(material, p.texcoord), material.emission};
}

SurfaceLight IrradianceField::Light(const SurfacePoint& p) const { return LightWith(p, Irradiance(p)); }

SurfaceLight IrradianceField::LightWithNoise(const SurfacePoint& p) const {
  // Independent contributions: their variances add, sigma_i = relative noise_i x luminance_i.
  const std::optional<IrradianceSample> gap = GapTerm(p);
  IrradianceSample total = gap ? *gap : contributions_.front()->WithNoise(p);
  double share = gap ? 0 : 1;
  if (contributions_.size() > 1) {
    const double first = std::pow(total.relativeNoise * Luminance(total.irradiance), 2), photons = gap ? 0 : first;
    double variance = first;
    for (size_t i = 1; i < contributions_.size(); ++i) {
      const IrradianceSample c = contributions_[i]->WithNoise(p);
      total.irradiance = total.irradiance + c.irradiance;
      variance += std::pow(c.relativeNoise * Luminance(c.irradiance), 2);
    }
    const double mean = Luminance(total.irradiance);
    total.relativeNoise = mean > 0 ? std::sqrt(variance) / mean : 0.0;
    share = variance > 0 ? photons / variance : 1.0;
  }
  SurfaceLight light = LightWith(p, total.irradiance);
  light.relativeNoise = total.relativeNoise;
  light.photonVarianceShare = share;
  return light;
}

IrradianceField BuildIrradianceField(const PreparedScene& scene, const SurfaceBins& bins, const FieldSettings& settings,
                                     StageClock& clock) {
  const EstimatorSettings& estimator = settings.estimator;
  std::vector<float> bandwidths = clock.Time("bandwidth", [&] {
    return settings.heldBandwidths.empty()
               ? SurfaceBandwidths(scene.regions, bins, estimator, settings.automaticBandwidth)
               : settings.heldBandwidths;
  });
  IrradianceField field = clock.Time("estimators", [&] {
    return IrradianceField(scene, std::make_unique<PhotonIrradiance>(scene, bins, estimator, std::move(bandwidths)));
  });
  if (settings.referencePaths > 0)
    field.Add(std::make_unique<ReferenceIrradiance>(scene, settings.referencePaths, settings.seed));
  else if (settings.direct.mode == DirectLight::kSampled) {
    auto direct = clock.Time("lights", [&] { return std::make_unique<DirectIrradiance>(scene, settings.direct, settings.seed); });
    const LightSampler& lights = direct->Sampler();  // owned by the field from here on
    field.Add(std::move(direct));
    if (settings.gaps.paths > 0)
      field.GatherGaps(std::make_unique<GapGather>(scene, field.Photons(), lights, settings.gaps, settings.seed));
  }
  return field;
}

BakedMesh EstimateIrradiance(const IrradianceField& field, SplitMesh mesh, const Log& log, bool withNoise,
                             const std::function<bool(size_t)>& owns) {
  BakedMesh baked;
  const size_t n = mesh.VertexCount();
  baked.irradiance.resize(n);
  baked.albedo.resize(n);
  baked.emitted.resize(n);
  if (withNoise) baked.irradianceNoise.assign(n, 0.0), baked.photonVarianceShare.assign(n, 1.0);
  Progress progress(log, "estimate irradiance", n);
  const size_t chunks = (n + kVertexChunk - 1) / kVertexChunk;
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    const size_t begin = c * kVertexChunk, end = std::min(n, begin + kVertexChunk);
    if (owns && !owns(c)) return progress.Advance(end - begin);
    for (size_t v = begin; v != end; ++v) {
      const SurfacePoint p = mesh.Point(v);
      const SurfaceLight light = withNoise ? field.LightWithNoise(p) : field.Light(p);
      baked.irradiance[v] = light.irradiance;
      baked.albedo[v] = light.albedo;
      baked.emitted[v] = light.emitted;
      if (withNoise) baked.irradianceNoise[v] = light.relativeNoise, baked.photonVarianceShare[v] = light.photonVarianceShare;
    }
    progress.Advance(end - begin);
  });
  baked.mesh = std::move(mesh);
  return baked;
}

}  // namespace pb
