// Stage 3: the irradiance field, what the estimate hands on. It answers, for any point of any surface
// (mesh/split_mesh.h, SurfacePoint), the light there:
//   H  irradiance [W/m^2] per unit surface area, the sum of the field's contributions;
//   R  diffuse reflectance (Kd, times its texture at the point), dimensionless;
//   Le emitted radiance [W/(m^2 sr)];
//   L = Le + R H / pi [W/(m^2 sr)], the radiance a viewer sees;
//   the predicted relative noise of H's luminance (sigma / mean, dimensionless; the smoothing bias is not in it).
// Vertices, refinement, maps, noise warnings and --target-noise all ask the field; nothing else converts a photon
// density in a chart to irradiance per unit surface area (PerSurfaceArea, below).
//
// H is a sum of contributions, whose noises add in variance:
//   photons  the photons' density estimate on the point's own surface (kernel, histogram or k nearest;
//            estimators/density_estimator.h), with its own bandwidth h [m] per surface;
//   direct   with --direct sampled, the direct light computed at the point by shadow rays to the lights
//            (estimators/light_sampler.h); the photons then carry only the light scattered at least once;
//   reference with --reference SPP, all of H by SPP paths gathered at the point (estimators/irradiance_gather.h),
//            a path tracer's vertex bake; no photons are traced then.
// With --direct sampled, at a point in a narrow gap (or on a surface smaller than its kernel) the photons' term is
// replaced by the scattered light gathered there (baker/3_gap_gather.h).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "baker/0_prepare_scene.h"
#include "baker/2_bin_photons.h"
#include "baker/3_gap_gather.h"
#include "baker/baked_mesh.h"
#include "baker/options.h"
#include "baker/progress.h"
#include "baker/stage_clock.h"
#include "estimators/density_estimator.h"
#include "estimators/irradiance_gather.h"
#include "estimators/light_sampler.h"
#include "mesh/errors.h"
#include "mesh/split_mesh.h"

namespace pb {

// A density per unit (u,v) area of p's chart, as a density per unit surface area: times the chart's local area
// ratio at p (exactly 1 on planar charts). The one place this conversion is made.
inline Rgb PerSurfaceArea(Rgb perChartArea, const SurfacePoint& p) { return perChartArea * p.areaRatio; }

// One term of H at a surface point: its irradiance [W/m^2] and the relative noise of its luminance.
struct IrradianceSample {
  Rgb irradiance;
  double relativeNoise = 0;
};

// The random numbers of point p: a stream keyed by the seed, p's surface and its chart position (-0 as +0).
Rng PointStream(uint64_t seed, const SurfacePoint& p);
// Where rays for point p start. A vertex where a wall meets the floor lies on the wall's plane too: half the rays
// gathered there would leave through the wall, and shadow rays would graze it. The value at such a point is the
// limit from inside its surface, so a point on a planar surface's boundary starts just inside it.
SurfacePoint RayStart(const PreparedScene& scene, const SurfacePoint& p);

class IrradianceContribution {
 public:
  virtual ~IrradianceContribution() = default;
  virtual std::string_view Name() const = 0;
  virtual Rgb At(const SurfacePoint& p) const = 0;
  // The same irradiance as At(p), bit for bit, and its predicted noise.
  virtual IrradianceSample WithNoise(const SurfacePoint& p) const = 0;
};

// h per surface [m]: settings.bandwidth everywhere, or, when `automatic`, chosen per surface from its photons.
std::vector<float> SurfaceBandwidths(const SurfaceRegions& regions, const SurfaceBins& bins,
                                     const EstimatorSettings& settings, bool automatic);

// The photons' contribution: on each surface, the density estimate of the photons binned on its front side
// (stage 2), with that surface's h, edge-corrected over its region. Estimators are built in parallel; they copy
// the photons and refer to the prepared scene's regions.
class PhotonIrradiance final : public IrradianceContribution {
 public:
  PhotonIrradiance(const PreparedScene& scene, const SurfaceBins& bins, const EstimatorSettings& settings,
                   std::vector<float> bandwidths);
  std::string_view Name() const override { return "photons"; }
  Rgb At(const SurfacePoint& p) const override { return PerSurfaceArea(ChartDensity(p.surface, p.uv), p); }
  IrradianceSample WithNoise(const SurfacePoint& p) const override;

  // The estimate on surface s at chart position uv, per unit chart area [W/m^2 of (u,v)].
  Rgb ChartDensity(uint32_t s, Point2 uv) const {
    PB_DCHECK_LT(s, estimators_.size());
    return estimators_[s]->Estimate(uv);
  }
  float Bandwidth(uint32_t s) const { return bandwidths_[s]; }
  const std::vector<float>& Bandwidths() const { return bandwidths_; }
  // The relative noise of an estimate on surface s if its `hits` photons, of equal flux, were spread evenly
  // over its `area` [m^2] (estimators/density_estimator.h, UniformRelativeNoise).
  double UniformNoise(uint32_t s, uint64_t hits, double area) const;

 private:
  EstimatorSettings settings_;
  std::vector<float> bandwidths_;
  std::vector<std::unique_ptr<DensityEstimator>> estimators_;
};

// A term of H computed at each point by Monte Carlo, with `count` samples. The random numbers of point p come from
// a stream keyed by the seed and p's surface and chart position, so the same point reads the same value on any
// thread, in any order. Rays start at RayStart(p): at a vertex on its surface's edge, just inside it.
class PointSampledIrradiance : public IrradianceContribution {
 public:
  Rgb At(const SurfacePoint& p) const final { return WithNoise(p).irradiance; }
  IrradianceSample WithNoise(const SurfacePoint& p) const final;

 protected:
  PointSampledIrradiance(const PreparedScene& scene, uint32_t count, uint64_t seed)
      : scene_(scene), count_(count), seed_(seed) {}
  // E at `position` on the side of `normal`, from `count` samples drawn from `rng`.
  virtual DirectSample Sample(Point3 position, Normal3 normal, uint32_t count, Rng& rng) const = 0;
  const PreparedScene& scene_;

 private:
  uint32_t count_;
  uint64_t seed_;
};

// The direct light at a point, sampled there with `direct.samples` shadow rays, or with as many as its noise
// target `direct.noise` needs, up to that many (estimators/light_sampler.h).
class DirectIrradiance final : public PointSampledIrradiance {
 public:
  DirectIrradiance(const PreparedScene& scene, const DirectSettings& direct, uint64_t seed);
  std::string_view Name() const override { return "direct"; }
  const LightSampler& Sampler() const { return sampler_; }

 private:
  DirectSample Sample(Point3 position, Normal3 normal, uint32_t count, Rng& rng) const override {
    return noise_ > 0 ? sampler_.AdaptiveIrradiance(position, normal, noise_, count, rng)
                      : sampler_.Irradiance(position, normal, count, rng);
  }
  LightSampler sampler_;
  double noise_;
};

// All of H at a point by `paths` paths gathered there (estimators/irradiance_gather.h).
class ReferenceIrradiance final : public PointSampledIrradiance {
 public:
  ReferenceIrradiance(const PreparedScene& scene, uint32_t paths, uint64_t seed);
  std::string_view Name() const override { return "reference"; }

 private:
  DirectSample Sample(Point3 position, Normal3 normal, uint32_t count, Rng& rng) const override {
    return gatherer_.Irradiance(position, normal, count, rng);
  }
  LightSampler lights_;
  IrradianceGatherer gatherer_;
};

// The light at a point: H, R, Le and the relative noise of H (0 unless asked for).
struct SurfaceLight {
  Rgb irradiance, albedo, emitted;
  double relativeNoise = 0;
  double photonVarianceShare = 1;  // of relativeNoise^2: the photons'; the rest is the points' samples
  Rgb Radiance() const { return OutgoingRadiance(emitted, albedo, irradiance); }
};

class IrradianceField {
 public:
  // `scene` must outlive the field.
  IrradianceField(const PreparedScene& scene, std::unique_ptr<PhotonIrradiance> photons);
  // Adds a term of H after the photons'.
  void Add(std::unique_ptr<IrradianceContribution> contribution);
  // At points in narrow gaps, gathers the light the photons would have estimated (baker/3_gap_gather.h).
  void GatherGaps(std::unique_ptr<GapGather> gaps);

  Rgb Irradiance(const SurfacePoint& p) const;
  SurfaceLight Light(const SurfacePoint& p) const;
  // The same light, bit for bit, with the noise of H.
  SurfaceLight LightWithNoise(const SurfacePoint& p) const;
  // R and Le at p with H given (refinement's cached irradiance grid).
  SurfaceLight LightWith(const SurfacePoint& p, Rgb irradiance) const;

  const PhotonIrradiance& Photons() const { return *photons_; }
  // The scale below which H has no detail, on surface s [m]: its photon bandwidth.
  float Bandwidth(uint32_t s) const { return photons_->Bandwidth(s); }
  const PreparedScene& Prepared() const { return *scene_; }

 private:
  // The gathered term that replaces the photons' at p, if p lies in a gap.
  std::optional<IrradianceSample> GapTerm(const SurfacePoint& p) const;

  const PreparedScene* scene_;
  const PhotonIrradiance* photons_;
  std::vector<std::unique_ptr<IrradianceContribution>> contributions_;  // photons first
  std::unique_ptr<GapGather> gaps_;                                     // or null
};

// What the field is made of: the photons' estimator, and the terms computed at the points.
struct FieldSettings {
  EstimatorSettings estimator;
  bool automaticBandwidth = false;  // --h auto
  // h per surface [m], when given: instead of the above (the rounds of --target-noise hold the first round's
  // --h auto, so that their noise falls as 1 / sqrt(photons); baker/progressive.h).
  std::vector<float> heldBandwidths;
  // --direct sampled adds DirectIrradiance. Photons, by default, as TraceSettings stores the first hits by default
  // (storeDirect): the two must agree, or the direct light is counted twice or not at all. Bake() sets both from
  // --direct, whose default is sampled.
  DirectSettings direct{DirectLight::kPhotons};
  uint32_t referencePaths = 0;      // --reference SPP: ReferenceIrradiance instead of direct light (0: none)
  uint64_t seed = 1;                // of the point streams
  GapSettings gaps;                 // with --direct sampled: the gathering in narrow gaps (paths 0: none)
};

// The field of the photons in `bins`: bandwidths ("bandwidth") and estimators ("estimators") timed on `clock`,
// with the terms computed at the points that `settings` asks for.
IrradianceField BuildIrradianceField(const PreparedScene& scene, const SurfaceBins& bins, const FieldSettings& settings,
                                     StageClock& clock);

// Vertices are estimated in chunks of this many, in parallel.
inline constexpr size_t kVertexChunk = 1024;

// H, R and Le at every vertex of `mesh`; with `withNoise`, also each vertex's relative noise
// (BakedMesh::irradianceNoise), from the same queries: H is the same bit for bit either way. With `owns`, only the
// chunks c of vertices [c kVertexChunk, (c + 1) kVertexChunk) for which owns(c) is true (a distributed bake shares
// them out, baker/distribution.h); the others read 0.
BakedMesh EstimateIrradiance(const IrradianceField& field, SplitMesh mesh, const Log& log, bool withNoise = false,
                             const std::function<bool(size_t)>& owns = {});

}  // namespace pb
