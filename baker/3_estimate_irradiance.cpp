#include "baker/3_estimate_irradiance.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "estimators/bandwidth.h"

namespace pb {
namespace {

std::vector<Triangle2> ChartTriangles(const SurfaceSet& surfaces, const Surface& surface) {
  std::vector<Triangle2> triangles;
  triangles.reserve(surface.triangles.size());
  for (uint32_t t : surface.triangles) triangles.push_back(surfaces.cornerUv[t]);
  return triangles;
}

}  // namespace

SurfaceEstimators BuildEstimators(const SurfaceRegions& regions, const SurfaceBins& bins,
                                  const EstimatorSettings& settings, const std::vector<float>& bandwidths) {
  SurfaceEstimators estimators(bins.SurfaceCount());
  tbb::parallel_for(size_t(0), bins.SurfaceCount(), [&](size_t s) {
    EstimatorSettings own = settings;
    own.bandwidth = bandwidths[s];
    estimators[s] = MakeDensityEstimator(own, *regions[s], bins.Uv(s), bins.Power(s));
  });
  return estimators;
}

SurfaceRegions BuildRegions(const SurfaceSet& surfaces) {
  SurfaceRegions regions(surfaces.surfaces.size());
  tbb::parallel_for(size_t(0), regions.size(), [&](size_t s) {
    regions[s] = std::make_unique<SurfaceRegion>(ChartTriangles(surfaces, surfaces.surfaces[s]));
  });
  return regions;
}

std::vector<float> SurfaceBandwidths(const SurfaceRegions& regions, const SurfaceBins& bins,
                                     const EstimatorSettings& settings, bool automatic) {
  std::vector<float> h(regions.size(), settings.bandwidth);
  if (!automatic) return h;
  tbb::parallel_for(size_t(0), regions.size(), [&](size_t s) {
    h[s] = ChooseBandwidth(settings.kind, settings.kernel, *regions[s], bins.Uv(s), bins.Power(s));
  });
  return h;
}

PointLight LightAt(const Scene& scene, const SurfaceSet& surfaces, const SurfaceEstimators& estimators, uint32_t s,
                   Point2 uv, Point2 texcoord, float areaRatio) {
  return LightWith(scene, scene.materials[surfaces.surfaces[s].material], estimators[s]->Estimate(uv) * areaRatio,
                   texcoord);
}

PointLight LightWith(const Scene& scene, const Material& material, Rgb irradiance, Point2 texcoord) {
  return {irradiance, scene.AlbedoAtTexcoord(material, texcoord), material.emission};
}

BakedMesh EstimateIrradiance(const Scene& scene, const SurfaceSet& surfaces, const SurfaceEstimators& estimators,
                             SplitMesh mesh, const Log& log, std::vector<double>* irradianceNoise) {
  BakedMesh baked;
  const size_t n = mesh.VertexCount();
  baked.irradiance.resize(n);
  baked.albedo.resize(n);
  baked.emitted.resize(n);
  if (irradianceNoise) irradianceNoise->assign(n, 0.0);
  Progress progress(log, "estimate irradiance", n);
  // LightAt, or the same with the noise of H from the same query.
  const auto lightAt = [&](size_t v) {
    const uint32_t s = mesh.surface[v];
    if (!irradianceNoise) return LightAt(scene, surfaces, estimators, s, mesh.uv[v], mesh.texcoord[v], mesh.uvAreaRatio[v]);
    const DensityEstimator::WithNoise e = estimators[s]->EstimateWithNoise(mesh.uv[v]);
    (*irradianceNoise)[v] = e.relativeNoise;
    return LightWith(scene, scene.materials[surfaces.surfaces[s].material], e.irradiance * mesh.uvAreaRatio[v],
                     mesh.texcoord[v]);
  };
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t v = r.begin(); v != r.end(); ++v) {
      const PointLight light = lightAt(v);
      baked.irradiance[v] = light.irradiance;
      baked.albedo[v] = light.albedo;
      baked.emitted[v] = light.emitted;
    }
    progress.Advance(r.size());
  });
  baked.mesh = std::move(mesh);
  return baked;
}

}  // namespace pb
