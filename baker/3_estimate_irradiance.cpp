#include "baker/3_estimate_irradiance.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <memory>

namespace pb {
namespace {

std::vector<Triangle2> ChartTriangles(const SurfaceSet& surfaces, const Surface& surface) {
  std::vector<Triangle2> triangles;
  triangles.reserve(surface.triangles.size());
  for (uint32_t t : surface.triangles) triangles.push_back(surfaces.cornerUv[t]);
  return triangles;
}

// One region and one estimator per surface, built in parallel (each from its own photons only).
struct SurfaceEstimators {
  std::vector<std::unique_ptr<SurfaceRegion>> regions;
  std::vector<std::unique_ptr<DensityEstimator>> estimators;
};

SurfaceEstimators BuildEstimators(const SurfaceSet& surfaces, const SurfaceBins& bins, const EstimatorSettings& settings) {
  SurfaceEstimators built;
  built.regions.resize(bins.SurfaceCount());
  built.estimators.resize(bins.SurfaceCount());
  tbb::parallel_for(size_t(0), bins.SurfaceCount(), [&](size_t s) {
    built.regions[s] = std::make_unique<SurfaceRegion>(ChartTriangles(surfaces, surfaces.surfaces[s]));
    built.estimators[s] = MakeDensityEstimator(settings, *built.regions[s], bins.Uv(s), bins.Power(s));
  });
  return built;
}

}  // namespace

BakedMesh EstimateIrradiance(const Scene& scene, const SurfaceSet& surfaces, SplitMesh mesh, const SurfaceBins& bins,
                             const EstimatorSettings& settings, const Log& log) {
  const SurfaceEstimators built = BuildEstimators(surfaces, bins, settings);
  BakedMesh baked;
  const size_t n = mesh.VertexCount();
  baked.irradiance.resize(n);
  baked.albedo.resize(n);
  baked.emitted.resize(n);
  Progress progress(log, "estimate irradiance", n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t v = r.begin(); v != r.end(); ++v) {
      const uint32_t s = mesh.surface[v];
      const Material& material = scene.materials[surfaces.surfaces[s].material];
      baked.irradiance[v] = built.estimators[s]->Estimate(mesh.uv[v]) * mesh.uvAreaRatio[v];
      baked.albedo[v] = material.albedo;
      baked.emitted[v] = material.emission;
    }
    progress.Advance(r.size());
  });
  baked.mesh = std::move(mesh);
  return baked;
}

}  // namespace pb
