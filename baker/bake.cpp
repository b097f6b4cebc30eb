#include "baker/bake.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "baker/0_plan_transport.h"
#include "baker/1_trace_photons.h"
#include "baker/2_bin_photons.h"
#include "baker/3_estimate_irradiance.h"
#include "baker/5_write_ply.h"
#include "baker/atomic_file.h"
#include "baker/stage_clock.h"
#include "baker/threads.h"
#include "mesh/errors.h"
#include "mesh/obj_loader.h"
#include "mesh/ray_scene.h"
#include "mesh/split_mesh.h"

namespace pb {
namespace {

void ValidateOptions(const BakeOptions& o) {
  if (!(o.estimator.bandwidth > 0) || !std::isfinite(o.estimator.bandwidth))
    throw InputError("--h", 0, "must be a finite length > 0 m");
  if (o.estimator.neighbours < 2) throw InputError("--k", 0, "must be at least 2");
  if (o.photons == 0) throw InputError("--photons", 0, "must be at least 1");
  if (!(o.scale > 0) || !std::isfinite(o.scale)) throw InputError("--scale", 0, "must be a finite number > 0");
  if (o.exposure && !(*o.exposure > 0)) throw InputError("--exposure", 0, "must be > 0");
  RequireWritableLocation(o.outputPath);
  if (!o.reportPath.empty()) RequireWritableLocation(o.reportPath);
}

void RequireLight(const Scene& scene, const std::vector<AreaLight>& lights) {
  if (lights.empty())
    throw InputError(scene.path, 0, "scene has no light: no face uses a material with Ke > 0");
}

void ReportWarnings(BakeReport& report, std::vector<std::string> warnings, const Log& log) {
  constexpr size_t kShown = 10;
  for (size_t i = 0; i < warnings.size() && i < kShown; ++i) log.Warning(warnings[i]);
  if (warnings.size() > kShown) log.Warning(fmt::format("... and {} more warnings", warnings.size() - kShown));
  report.warnings = std::move(warnings);
}

}  // namespace

BakeReport Bake(const BakeOptions& o, const Log& log) {
  ValidateOptions(o);
  const EffectOverrides overrides = ParseEffectOverrides(o.effectsText);
  const ThreadScope threads(o.threads);
  BakeReport report{o, threads.Count()};
  StageClock clock(report.stageSeconds);

  LoadedScene loaded = clock.Time("load", [&] { return LoadObj(o.scenePath, {o.scale}); });
  const Scene& scene = loaded.scene;
  ReportWarnings(report, std::move(loaded.warnings), log);
  const SurfaceSet surfaces = clock.Time("surfaces", [&] { return BuildSurfaces(scene); });
  const std::vector<AreaLight> lights = CollectLights(scene, surfaces);
  RequireLight(scene, lights);
  report.plan = clock.Time("plan", [&] { return PlanTransport(scene, surfaces, lights, overrides); });
  std::optional<RayScene> rays;
  clock.Time("bvh", [&] { rays.emplace(scene); });

  const PhotonHits photons =
      clock.Time("trace", [&] { return TracePhotons(scene, lights, *rays, report.plan, {o.photons, o.seed, o.maxBounces}, log); });
  const SurfaceBins bins = clock.Time("bin", [&] { return BinPhotons(surfaces, photons); });
  const SurfaceRegions regions = clock.Time("regions", [&] { return BuildRegions(surfaces); });
  const std::vector<float> bandwidths =
      clock.Time("bandwidth", [&] { return SurfaceBandwidths(regions, bins, o.estimator, o.autoBandwidth); });
  const BakedMesh baked = clock.Time("estimate", [&] {
    return EstimateIrradiance(scene, surfaces, regions, SplitBySurface(scene, surfaces), bins, o.estimator, bandwidths, log);
  });
  report.exposure = clock.Time("write", [&] { return WritePly(o.outputPath, baked, {o.asciiPly, o.exposure}); });

  report.triangles = scene.triangles.size();
  report.degenerateTrianglesSkipped = scene.degenerateTrianglesSkipped;
  report.vertices = baked.mesh.VertexCount();
  report.faces = baked.mesh.faces.size();
  report.lights = DescribeLights(scene, lights, photons.stats.photonsPerLight, report.plan);
  report.surfaces = DescribeSurfaces(scene, surfaces, bins);
  report.curvedCharts = surfaces.CurvedCount();
  report.worstAreaDistortion = surfaces.WorstAreaDistortion();
  for (size_t s = 0; s < report.surfaces.size(); ++s) report.surfaces[s].bandwidth = bandwidths[s];
  report.trace = photons.stats;
  if (!o.reportPath.empty()) WriteReportJson(o.reportPath, report);
  return report;
}

}  // namespace pb
