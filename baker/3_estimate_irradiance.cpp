#include "baker/3_estimate_irradiance.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <memory>

#include "estimators/kernel_estimator.h"

namespace pb {

BakedMesh EstimateIrradiance(const Scene& scene, const SurfaceSet& surfaces, SplitMesh mesh, const SurfaceBins& bins,
                             Kernel kernel, float bandwidth, const Log& log) {
  std::vector<std::unique_ptr<KernelEstimator>> estimators(bins.SurfaceCount());
  tbb::parallel_for(size_t(0), estimators.size(), [&](size_t s) {
    estimators[s] = std::make_unique<KernelEstimator>(bins.Uv(s), bins.Power(s), bandwidth, kernel);
  });

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
      baked.irradiance[v] = estimators[s]->Estimate(mesh.uv[v]);
      baked.albedo[v] = material.albedo;
      baked.emitted[v] = material.emission;
    }
    progress.Advance(r.size());
  });
  baked.mesh = std::move(mesh);
  return baked;
}

}  // namespace pb
