#include "baker/3_contributions.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <optional>

#include "baker/option_ranges.h"
#include "baker/photons/progressive.h"
#include "estimators/bandwidth.h"

namespace pb {

std::optional<DirectLight> ParseDirectLight(std::string_view name) {
  if (name == "photons") return DirectLight::kPhotons;
  if (name == "sampled") return DirectLight::kSampled;
  return std::nullopt;
}

std::string DirectLightName(DirectLight mode) { return mode == DirectLight::kSampled ? "sampled" : "photons"; }
std::string DirectLightNames() { return "photons, sampled"; }

void DirectSettings::Validate() const {
  RequireOption(samples >= 1 && samples <= 1'000'000, "--direct-samples", "must lie in [1, 1000000]");
  RequireOption(noise == 0 || (noise >= 1e-4 && noise <= 1), "--direct-noise", "must be 0 (off) or lie in [0.0001, 1]");
}

std::vector<float> SurfaceBandwidths(const SurfaceRegions& regions, const SurfaceBins& bins,
                                     const EstimatorSettings& settings, const Log* log) {
  if (settings.bandwidth) return std::vector<float>(regions.size(), *settings.bandwidth);
  std::vector<float> h(regions.size());
  std::optional<Progress> progress;
  if (log != nullptr) progress.emplace(*log, "choose bandwidths", regions.size());
  tbb::parallel_for(size_t(0), regions.size(), [&](size_t s) {
    h[s] = ChooseBandwidth(settings.kind, settings.kernel, PilotHistogram::Of(*regions[s], bins.Uv(s), bins.Flux(s), bins.fluxUnit));
    if (progress) progress->Advance(1);
  });
  return h;
}

namespace {

// Surface s's estimator of the photons at `uv` carrying `flux`, binned as `open` and `covered` say.
std::unique_ptr<DensityEstimator> SurfaceEstimator(const PreparedScene& scene, size_t s, const EstimatorSettings& own,
                                                   std::span<const Point2> uv, std::span<const Rgb> flux,
                                                   const KernelBinning& open, const KernelBinning& covered) {
  if (scene.covers[s].Empty()) return MakeDensityEstimator(own, *scene.regions[s], uv, flux, open);
  return MakeCoveredDensityEstimator(own, *scene.regions[s], *scene.coveredRegions[s], scene.covers[s], uv, flux, open,
                                     covered);
}

// The weighted fluxes of surface s's stored photons (MomentFluxes), each as an array.
std::array<std::vector<Rgb>, kMomentFluxes> StoredMomentFluxes(const SurfaceBins& bins, size_t s) {
  const std::span<const Rgb> flux = bins.Flux(s);
  const std::span<const Vector3> from = bins.From(s);
  const std::span<const float> cosine = bins.Cosine(s);
  std::array<std::vector<Rgb>, kMomentFluxes> moments;
  for (auto& m : moments) m.resize(flux.size());
  for (size_t j = 0; j < flux.size(); ++j) {
    const std::array<Rgb, kMomentFluxes> weighted = MomentFluxes(flux[j], from[j], cosine[j]);
    for (int m = 0; m < kMomentFluxes; ++m) moments[m][j] = weighted[m];
  }
  return moments;
}

// D's covariance at p (estimators/incident_moments.h): a^T M a along each of the six axes is the square of the
// noise that estimator `axes[k]` predicts for its own estimate.
Symmetric3 PhotonCovariance(std::span<const std::unique_ptr<DensityEstimator>> axes, const SurfacePoint& p) {
  std::array<double, 6> forms;
  for (size_t k = 0; k < 6; ++k) {
    const NoisyIrradiance e = axes[k]->EstimateWithNoise(p.uv);
    forms[k] = std::pow(e.relativeNoise * Luminance(PerSurfaceArea(e.irradiance, p)), 2);
  }
  return FromQuadraticForms(forms);
}

}  // namespace

namespace {
// Area samples per photon on the pooled surfaces: the area within the r that holds 200 photons is then known from
// about 25 samples, stratified (so far better than the photons' Poisson noise), twice PooledEstimator's floor of
// kMinAreaSamples' weight. A query costs the samples it finds: the sports car's bare estimate took 45 s at 4 per
// photon and 25 s at 1; at 1/8 its estimate under the CI guard is a quarter faster than at 1/4, and the staircase at
// 10^6 photons and 32 rays and paths reads the same (33.88% against 33.89%).
constexpr double kAreaSamplesPerPhoton = 0.125;

// The area-weighted median of the surfaces' h that are not pooled [m]: the scale on which the photons say the light
// changes, and so the farthest the pooled estimate reaches. The largest h when every surface is pooled.
float PooledReach(const SurfaceSet& surfaces, const std::vector<bool>& pooled, const std::vector<float>& bandwidths) {
  std::vector<double> h, area;
  for (size_t s = 0; s < bandwidths.size(); ++s)
    if (!pooled[s]) h.push_back(bandwidths[s]), area.push_back(surfaces.surfaces[s].area);
  if (h.empty()) return *std::max_element(bandwidths.begin(), bandwidths.end());
  return float(WeightedPercentile(h, area, 0.5));
}
}  // namespace

void PhotonIrradiance::PoolSparseSurfaces(const PreparedScene& scene, const SurfaceBins& bins) {
  pooledSurface_.assign(bins.SurfaceCount(), false);
  std::vector<uint32_t> triangles;
  double sparseArea = 0;
  for (size_t s = 0; s < bins.SurfaceCount(); ++s) {
    if (!bins.Sparse(s)) continue;
    pooledSurface_[s] = true;
    const Surface& surface = scene.surfaces.surfaces[s];
    triangles.insert(triangles.end(), surface.triangles.begin(), surface.triangles.end());
    sparseArea += surface.area;
  }
  if (bins.pooled.empty() || !(sparseArea > 0)) return pooledSurface_.clear();
  const double density = double(bins.pooled.size()) / sparseArea;  // photons per m^2
  PooledSettings settings;
  // Half the photons around a point face its way: `neighbours` of them lie within the disc of twice as many at the
  // mean density. That far at most, and no farther than the other surfaces' median h (a query costs the points within
  // its reach: the sports car's median h of 1.7 m, four times this, made the pooled queries 40 times the rest of the
  // estimate).
  const auto reach = float(std::sqrt(2 * settings.neighbours / (kPi * density)));
  settings.maxRadius = std::min(PooledReach(scene.surfaces, pooledSurface_, bandwidths_), reach);
  AreaSamples area = SampleArea(scene.scene, triangles, kAreaSamplesPerPhoton * density);
  std::vector<MapPhoton> photons = bins.pooled;
  for (size_t i = 0; i < photons.size(); ++i) photons[i].normal = area.normalOf.at(bins.pooledTriangles[i]);
  pooled_ = std::make_unique<PooledEstimator>(std::move(photons), std::move(area.samples), settings);
}

PhotonIrradiance::PhotonIrradiance(const PreparedScene& scene, const SurfaceBins& bins,
                                   const EstimatorSettings& settings, std::vector<float> bandwidths, const Log* log,
                                   bool pool)
    : settings_(settings), bandwidths_(std::move(bandwidths)), bias_(bins.SurfaceCount()),
      estimators_(bins.SurfaceCount()) {
  if (pool) PoolSparseSurfaces(scene, bins);
  std::optional<Progress> progress;
  if (log != nullptr) progress.emplace(*log, "build estimators", bins.SurfaceCount());
  tbb::parallel_for(size_t(0), bins.SurfaceCount(), [&](size_t s) {
    estimators_[s] = SurfaceEstimator(scene, s, Own(s), bins.Uv(s), bins.Flux(s), bins.BinningOf(s, 0), bins.BinningOf(s, 1));
    const PilotHistogram pilot = PilotHistogram::Of(*scene.regions[s], bins.Uv(s), bins.Flux(s), bins.fluxUnit);
    bias_[s] = PredictedBias(settings_.kind, settings_.kernel, pilot, bandwidths_[s]);
    if (progress) progress->Advance(1);
  });
}

EstimatorSettings PhotonIrradiance::Own(size_t s) const {
  EstimatorSettings own = settings_;
  own.bandwidth = bandwidths_[s];
  return own;
}

void PhotonIrradiance::BuildMoments(const PreparedScene& scene, const SurfaceBins& bins, const Log* log) {
  PB_CHECK(bins.directions, "the photons' moments need their directions (--sh)");
  moments_.resize(bins.SurfaceCount());
  std::optional<Progress> progress;
  if (log != nullptr) progress.emplace(*log, "build direction estimators", bins.SurfaceCount());
  tbb::parallel_for(size_t(0), bins.SurfaceCount(), [&](size_t s) {
    const std::array<std::vector<Rgb>, kMomentFluxes> fluxes = StoredMomentFluxes(bins, s);
    for (int m = 0; m < kMomentFluxes; ++m)
      moments_[s][m] = SurfaceEstimator(scene, s, Own(s), bins.Uv(s), fluxes[m], bins.MomentBinningOf(s, 0, m),
                                        bins.MomentBinningOf(s, 1, m));
    if (progress) progress->Advance(1);
  });
}

void PhotonIrradiance::AddMoments(const SurfacePoint& p, IncidentMoments& moments) const {
  PB_CHECK(!moments_.empty(), "the photons' moments are built first (BuildMoments)");
  const auto& m = moments_[p.surface];
  const Rgb scalar = m[0]->Estimate(p.uv);
  IncidentMoments own;
  own.scalar = PerSurfaceArea(scalar, p);
  for (int k = 0; k < 3; ++k) own.vector[k] = PerSurfaceArea(m[k + 1]->Estimate(p.uv) - scalar, p);
  own.covariance = PhotonCovariance(std::span(m).subspan(4), p);
  moments.Add(own);
}

NoisyIrradiance PhotonIrradiance::WithNoise(const SurfacePoint& p) const {
  if (Pooled(p.surface)) return pooled_->Estimate(p.position, p.normal);
  const NoisyIrradiance e = estimators_[p.surface]->EstimateWithNoise(p.uv);
  return {PerSurfaceArea(e.irradiance, p), e.relativeNoise};
}

double PhotonIrradiance::UniformNoise(uint32_t s, uint64_t hits, double area) const {
  return UniformRelativeNoise(Own(s), double(hits) / area);
}

NoisyIrradiance PointSampledIrradiance::WithNoise(const SurfacePoint& p) const {
  Rng rng = PointStream(seed_, p);
  const DirectSample e = Sample(RayStart(scene_, p).position, p.normal, count_, rng, nullptr);
  drawn_.fetch_add(e.samples, std::memory_order_relaxed);
  return {e.irradiance, e.relativeNoise};
}

void PointSampledIrradiance::AddMoments(const SurfacePoint& p, IncidentMoments& moments) const {
  Rng rng = PointStream(seed_, p);
  Sample(RayStart(scene_, p).position, p.normal, count_, rng, &moments);
}

DirectIrradiance::DirectIrradiance(const PreparedScene& scene, const DirectSettings& direct, uint64_t seed)
    : PointSampledIrradiance(scene, direct.samples, seed), sampler_(scene.scene, scene.lights, *scene.rays),
      noise_(direct.noise) {}

ReferenceIrradiance::ReferenceIrradiance(const PreparedScene& scene, uint32_t paths, uint64_t seed,
                                         const ImportanceCache* guide)
    : PointSampledIrradiance(scene, paths, seed), lights_(scene.scene, scene.lights, *scene.rays),
      gatherer_(scene.scene, *scene.rays, lights_, IrradianceGatherer::kMaxDepth, guide) {}

}  // namespace pb
