// Stage 3: irradiance H [W/m^2] at every vertex of the split mesh, estimated from the photons of the vertex's
// own surface (estimators/density_estimator.h: kernel, histogram or k nearest, edge-corrected over the
// surface's region in its chart, times the chart's local area ratio on curved surfaces). Each surface has its
// own bandwidth h [m]: the user's, or one chosen from its photons (estimators/bandwidth.h). Also fills each
// vertex's reflectance R and emitted radiance Le from its surface's material.
#pragma once

#include <memory>
#include <vector>

#include "baker/2_bin_photons.h"
#include "baker/baked_mesh.h"
#include "baker/progress.h"
#include "estimators/density_estimator.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

// Each surface's region in its chart, by surface index.
using SurfaceRegions = std::vector<std::unique_ptr<SurfaceRegion>>;
SurfaceRegions BuildRegions(const SurfaceSet& surfaces);

// h per surface [m]: settings.bandwidth everywhere, or, when `automatic`, chosen per surface from its photons.
std::vector<float> SurfaceBandwidths(const SurfaceRegions& regions, const SurfaceBins& bins,
                                     const EstimatorSettings& settings, bool automatic);

// One estimator per surface (its own photons, its own h), built in parallel. They refer to `regions`.
using SurfaceEstimators = std::vector<std::unique_ptr<DensityEstimator>>;
SurfaceEstimators BuildEstimators(const SurfaceRegions& regions, const SurfaceBins& bins,
                                  const EstimatorSettings& settings, const std::vector<float>& bandwidths);

// The light at one point of surface s: H from the surface's estimator at chart position uv, times the chart's
// area ratio there; R from the material (and its texture at texcoord); Le from the material.
struct PointLight {
  Rgb irradiance, albedo, emitted;
  Rgb Radiance() const { return OutgoingRadiance(emitted, albedo, irradiance); }
};
PointLight LightAt(const Scene& scene, const SurfaceSet& surfaces, const SurfaceEstimators& estimators, uint32_t s,
                   Point2 uv, Point2 texcoord, float areaRatio);
// The same with H given: R from `material` (and its texture at texcoord), Le from `material`.
PointLight LightWith(const Scene& scene, const Material& material, Rgb irradiance, Point2 texcoord);

// Every vertex of `mesh`, by LightAt. With `irradianceNoise`, also each vertex's predicted sigma_H / H
// (DensityEstimator::RelativeNoise), from the same query; H is the same bit for bit either way.
BakedMesh EstimateIrradiance(const Scene& scene, const SurfaceSet& surfaces, const SurfaceEstimators& estimators,
                             SplitMesh mesh, const Log& log, std::vector<double>* irradianceNoise = nullptr);

}  // namespace pb
