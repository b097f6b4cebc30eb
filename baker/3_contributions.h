// Stage 3: the terms whose sum is the irradiance field's H (baker/3_irradiance_field.h), each able to say its value
// at a surface point (mesh/split_mesh.h, SurfacePoint) in W/m^2 per unit surface area, and its noise
// (estimators/noisy_irradiance.h):
//   photons   the photons' density estimate on the point's own surface, with that surface's h [m];
//   direct    the direct light computed at the point by shadow rays (--direct sampled);
//   reference all of H by paths gathered at the point (--reference SPP).
// Each also says where its light comes from, its moments (estimators/incident_moments.h), for --sh.
#pragma once

#include <array>
#include <atomic>
#include <optional>
#include <string>
#include <memory>
#include <string_view>
#include <vector>

#include "baker/0_prepare_scene.h"
#include "baker/2_bin_photons.h"
#include "baker/3_direct_settings.h"
#include "baker/3_surface_point.h"
#include "baker/runtime/progress.h"
#include "estimators/density_estimator.h"
#include "estimators/incident_moments.h"
#include "estimators/irradiance_gather.h"
#include "estimators/light_sampler.h"
#include "estimators/noisy_irradiance.h"
#include "estimators/pooled_estimator.h"
#include "mesh/errors.h"
#include "mesh/split_mesh.h"

namespace pb {


// A density per unit (u,v) area of p's chart, as a density per unit surface area: times the chart's local area
// ratio at p (exactly 1 on planar charts). The one place this conversion is made.
inline Rgb PerSurfaceArea(Rgb perChartArea, const SurfacePoint& p) { return perChartArea * p.areaRatio; }

class IrradianceContribution {
 public:
  virtual ~IrradianceContribution() = default;
  virtual std::string_view Name() const = 0;
  virtual Rgb At(const SurfacePoint& p) const = 0;
  // The same irradiance as At(p), bit for bit, and its predicted noise.
  virtual NoisyIrradiance WithNoise(const SurfacePoint& p) const = 0;
  // Adds the moments of the light this term brings to p (estimators/incident_moments.h).
  virtual void AddMoments(const SurfacePoint& p, IncidentMoments& moments) const = 0;
  // The samples WithNoise has drawn at points so far, over every thread (shadow rays, or --reference's paths); 0
  // for a term drawn at no point (the photons').
  virtual uint64_t SamplesDrawn() const { return 0; }
};

// h per surface [m]: settings.bandwidth everywhere, or, where it is none, chosen per surface from its photons (with
// its progress on `log` when given).
std::vector<float> SurfaceBandwidths(const SurfaceRegions& regions, const SurfaceBins& bins,
                                     const EstimatorSettings& settings, const Log* log = nullptr);

// The photons' contribution: on each surface, the density estimate of the photons binned on its front side
// (stage 2), with that surface's h, edge-corrected over its region. Estimators are built in parallel (with their
// progress on `log` when given); they copy the photons and refer to the prepared scene's regions.
//
// Once BuildMoments is called, from bins that hold the photons' directions (--sh), their moments are estimated
// alike: by the same estimator, kernel, h and regions, of the photons weighted phi / c (F) and phi (1 + w_m) / c
// (F + D_m; each weight >= 0, so that no estimator sees a negative flux), c = max(cos, kGrazingCosine); D_m is their
// difference. D's covariance comes from the estimators' own noise of the photons weighted phi |a . w| / c along six
// axes (estimators/incident_moments.h).
//
// With `pool`, the sparse surfaces (SurfaceBins::Sparse, too few photons for an estimate of their own) are estimated
// instead from the photons pooled across them (bins.pooled; estimators/pooled_estimator.h), within the area-weighted
// median h of the other surfaces.
class PhotonIrradiance final : public IrradianceContribution {
 public:
  PhotonIrradiance(const PreparedScene& scene, const SurfaceBins& bins, const EstimatorSettings& settings,
                   std::vector<float> bandwidths, const Log* log = nullptr, bool pool = false);
  std::string_view Name() const override { return "photons"; }
  Rgb At(const SurfacePoint& p) const override {
    return Pooled(p.surface) ? pooled_->Estimate(p.position, p.normal).irradiance
                             : PerSurfaceArea(ChartDensity(p.surface, p.uv), p);
  }
  NoisyIrradiance WithNoise(const SurfacePoint& p) const override;
  // The estimators of the photons' moments, from `bins` with directions (those this contribution was built from),
  // in parallel, with their progress on `log` when given; before AddMoments.
  void BuildMoments(const PreparedScene& scene, const SurfaceBins& bins, const Log* log = nullptr);
  void AddMoments(const SurfacePoint& p, IncidentMoments& moments) const override;

  // The estimate on surface s at chart position uv, per unit chart area [W/m^2 of (u,v)].
  Rgb ChartDensity(uint32_t s, Point2 uv) const {
    PB_DCHECK_LT(s, estimators_.size());
    return estimators_[s]->Estimate(uv);
  }
  float Bandwidth(uint32_t s) const { return bandwidths_[s]; }
  // Whether ChartDensity is a kernel's estimate, smooth on the scale of h (not a histogram's or the nearest
  // neighbours').
  bool KernelEstimates() const { return settings_.kind == EstimatorKind::kKernel; }
  // Whether surface s is estimated from the pooled photons; and their estimate at a point of it [W/m^2].
  bool Pooled(uint32_t s) const { return pooled_ && s < pooledSurface_.size() && pooledSurface_[s]; }
  NoisyIrradiance PooledAt(Point3 position, Normal3 normal) const { return pooled_->Estimate(position, normal); }
  // The pooled estimate's reach [m] (PooledSettings::maxRadius): a path's hit nearer than this to its last vertex
  // would read light averaged over the path's own start.
  float PooledRadius() const { return pooled_->Settings().maxRadius; }
  size_t PooledPhotons() const { return pooled_ ? pooled_->Photons() : 0; }
  // The smoothing bias predicted for surface s's estimate of H's luminance: its RMS over the surface [W/m^2 of
  // (u,v)] (estimators/bandwidth.h, PredictedBias).
  double Bias(uint32_t s) const { return bias_[s]; }
  const std::vector<float>& Bandwidths() const { return bandwidths_; }
  // The relative noise of an estimate on surface s if its `hits` photons, of equal flux, were spread evenly
  // over its `area` [m^2] (estimators/density_estimator.h, UniformRelativeNoise).
  double UniformNoise(uint32_t s, uint64_t hits, double area) const;

 private:
  EstimatorSettings Own(size_t s) const;  // the settings with surface s's h
  // Builds pooled_ over the sparse surfaces of `bins` (none when no photon reached them).
  void PoolSparseSurfaces(const PreparedScene& scene, const SurfaceBins& bins);

  EstimatorSettings settings_;
  std::vector<float> bandwidths_;
  std::vector<double> bias_;
  std::vector<std::unique_ptr<DensityEstimator>> estimators_;
  std::unique_ptr<PooledEstimator> pooled_;  // with `pool` and sparse surfaces lit; else null
  std::vector<bool> pooledSurface_;          // per surface, when pooled_
  // Once built: per surface, the estimators of F, F + D_x, F + D_y, F + D_z and the six axes'; else empty.
  std::vector<std::array<std::unique_ptr<DensityEstimator>, kMomentFluxes>> moments_;
};

// A term of H computed at each point by Monte Carlo, with `count` samples. The random numbers of point p come from
// a stream keyed by the seed and p's surface and chart position, so the same point reads the same value on any
// thread, in any order. Rays start at RayStart(p): at a vertex on its surface's edge, just inside it.
class PointSampledIrradiance : public IrradianceContribution {
 public:
  Rgb At(const SurfacePoint& p) const final { return WithNoise(p).irradiance; }
  NoisyIrradiance WithNoise(const SurfacePoint& p) const final;
  // From the same samples as WithNoise's.
  void AddMoments(const SurfacePoint& p, IncidentMoments& moments) const final;
  uint64_t SamplesDrawn() const final { return drawn_.load(std::memory_order_relaxed); }

 protected:
  PointSampledIrradiance(const PreparedScene& scene, uint32_t count, uint64_t seed)
      : scene_(scene), count_(count), seed_(seed) {}
  // E at `position` on the side of `normal`, from `count` samples drawn from `rng`; their moments added to
  // `moments` when given.
  virtual DirectSample Sample(Point3 position, Normal3 normal, uint32_t count, Rng& rng,
                              IncidentMoments* moments) const = 0;
  const PreparedScene& scene_;

 private:
  uint32_t count_;
  uint64_t seed_;
  mutable std::atomic<uint64_t> drawn_{0};
};

// The direct light at a point, sampled there with `direct.samples` shadow rays, or with as many as its noise
// target `direct.noise` needs, up to that many (estimators/light_sampler.h).
class DirectIrradiance final : public PointSampledIrradiance {
 public:
  DirectIrradiance(const PreparedScene& scene, const DirectSettings& direct, uint64_t seed);
  std::string_view Name() const override { return "direct"; }
  const LightSampler& Sampler() const { return sampler_; }

 private:
  DirectSample Sample(Point3 position, Normal3 normal, uint32_t count, Rng& rng,
                      IncidentMoments* moments) const override {
    return noise_ > 0 ? sampler_.AdaptiveIrradiance(position, normal, noise_, count, rng, moments)
                      : sampler_.Irradiance(position, normal, count, rng, moments);
  }
  LightSampler sampler_;
  double noise_;
};

// All of H at a point by `paths` paths gathered there (estimators/irradiance_gather.h), their first directions
// drawn from `guide`'s maps when given (it must outlive this).
class ReferenceIrradiance final : public PointSampledIrradiance {
 public:
  ReferenceIrradiance(const PreparedScene& scene, uint32_t paths, uint64_t seed, const ImportanceCache* guide = nullptr);
  std::string_view Name() const override { return "reference"; }

 private:
  DirectSample Sample(Point3 position, Normal3 normal, uint32_t count, Rng& rng,
                      IncidentMoments* moments) const override {
    return gatherer_.Irradiance(position, normal, count, rng, moments);
  }
  LightSampler lights_;
  IrradianceGatherer gatherer_;
};

}  // namespace pb
