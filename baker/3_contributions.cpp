#include "baker/3_contributions.h"

#include <tbb/parallel_for.h>

#include <optional>

#include "estimators/bandwidth.h"

namespace pb {

std::vector<float> SurfaceBandwidths(const SurfaceRegions& regions, const SurfaceBins& bins,
                                     const EstimatorSettings& settings, bool automatic, const Log* log) {
  std::vector<float> h(regions.size(), settings.bandwidth);
  if (!automatic) return h;
  std::optional<Progress> progress;
  if (log != nullptr) progress.emplace(*log, "choose bandwidths", regions.size());
  tbb::parallel_for(size_t(0), regions.size(), [&](size_t s) {
    h[s] = ChooseBandwidth(settings.kind, settings.kernel, *regions[s], bins.Uv(s), bins.Flux(s));
    if (progress) progress->Advance(1);
  });
  return h;
}

PhotonIrradiance::PhotonIrradiance(const PreparedScene& scene, const SurfaceBins& bins,
                                   const EstimatorSettings& settings, std::vector<float> bandwidths, const Log* log)
    : settings_(settings), bandwidths_(std::move(bandwidths)), estimators_(bins.SurfaceCount()) {
  std::optional<Progress> progress;
  if (log != nullptr) progress.emplace(*log, "build estimators", bins.SurfaceCount());
  tbb::parallel_for(size_t(0), bins.SurfaceCount(), [&](size_t s) {
    EstimatorSettings own = settings;
    own.bandwidth = bandwidths_[s];
    estimators_[s] = scene.covers[s].Empty()
                         ? MakeDensityEstimator(own, *scene.regions[s], bins.Uv(s), bins.Flux(s), bins.BinningOf(s, 0))
                         : MakeCoveredDensityEstimator(own, *scene.regions[s], *scene.coveredRegions[s], scene.covers[s],
                                                       bins.Uv(s), bins.Flux(s), bins.BinningOf(s, 0), bins.BinningOf(s, 1));
    if (progress) progress->Advance(1);
  });
}

NoisyIrradiance PhotonIrradiance::WithNoise(const SurfacePoint& p) const {
  const NoisyIrradiance e = estimators_[p.surface]->EstimateWithNoise(p.uv);
  return {PerSurfaceArea(e.irradiance, p), e.relativeNoise};
}

double PhotonIrradiance::UniformNoise(uint32_t s, uint64_t hits, double area) const {
  EstimatorSettings own = settings_;
  own.bandwidth = bandwidths_[s];
  return UniformRelativeNoise(own, double(hits) / area);
}

NoisyIrradiance PointSampledIrradiance::WithNoise(const SurfacePoint& p) const {
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

}  // namespace pb
