#include "baker/bake.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "baker/0_plan_transport.h"
#include "baker/1_trace_photons.h"
#include "baker/2_bin_photons.h"
#include "baker/3_estimate_irradiance.h"
#include "baker/4_refine_mesh.h"
#include "baker/5_write_maps.h"
#include "baker/5_write_ply.h"
#include "baker/atomic_file.h"
#include "baker/interrupt.h"
#include "baker/progressive.h"
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
  if (!(o.refine.tolerance > 0 && o.refine.tolerance < 1)) throw InputError("--tolerance", 0, "must lie in (0, 1)");
  if (o.refine.subdivide < 0 || o.refine.subdivide > 8) throw InputError("--subdivide", 0, "must lie in [0, 8]");
  if (o.refine.maxVertices < 3) throw InputError("--max-vertices", 0, "must be at least 3");
  if (o.targetNoise && !(*o.targetNoise > 0 && *o.targetNoise < 1)) throw InputError("--target-noise", 0, "must lie in (0, 1)");
  if (o.targetNoise && o.maxPhotons < o.photons)
    throw InputError("--max-photons", 0, "must be at least --photons, the first round of --target-noise");
  // knn's noise is 1/sqrt(k - 2) whatever the photon count: more photons only shrink its disc.
  if (const double knnNoise = 1.0 / std::sqrt(std::max(1.0, o.estimator.neighbours - 2.0));
      o.targetNoise && o.estimator.kind == EstimatorKind::kNearest && *o.targetNoise < knnNoise)
    throw InputError("--target-noise", 0, fmt::format("knn's noise is 1/sqrt(k - 2) = {:.3f} for --k {}, whatever the "
                                                      "photon count: raise --k to {} or more, or use the kernel estimator",
                                                      knnNoise, o.estimator.neighbours,
                                                      uint32_t(std::ceil(2 + 1 / (*o.targetNoise * *o.targetNoise)))));
}

void ValidateOutputs(const BakeOptions& o) {
  RequireWritableLocation(o.outputPath);
  if (!o.reportPath.empty()) RequireWritableLocation(o.reportPath);
  if (!o.mapsDirectory.empty()) RequireWritableLocation(o.mapsDirectory + "/surface_0.exr");
  if (!o.savePhotonsPath.empty()) RequireWritableLocation(o.savePhotonsPath);
}

void RequireLight(const Scene& scene, const std::vector<AreaLight>& lights) {
  if (lights.empty())
    throw InputError(scene.path, 0, "scene has no light: no face uses a material with Ke > 0");
}

void ReportWarnings(BakeReport& report, std::vector<std::string> warnings, const Log& log) {
  constexpr size_t kShown = 10;
  for (size_t i = 0; i < warnings.size() && i < kShown; ++i) log.Warning(warnings[i]);
  if (warnings.size() > kShown) log.Warning(fmt::format("... and {} more warnings", warnings.size() - kShown));
  report.warnings.insert(report.warnings.end(), warnings.begin(), warnings.end());
}

// Warns about each surface whose h is below half its mean photon spacing sqrt(A / hits): most of its vertices see
// no photon within h, so H there reads 0 between photons. knn adapts its radius and is never warned about.
std::vector<std::string> BandwidthWarnings(const Scene& scene, const SurfaceSet& surfaces, const SurfaceBins& bins,
                                           const std::vector<float>& bandwidths, EstimatorKind kind) {
  std::vector<std::string> warnings;
  if (kind == EstimatorKind::kNearest) return warnings;
  for (size_t s = 0; s < surfaces.surfaces.size(); ++s) {
    if (bins.FrontHits(s) == 0) continue;
    const double spacing = std::sqrt(surfaces.surfaces[s].area / double(bins.FrontHits(s)));
    if (bandwidths[s] >= 0.5 * spacing) continue;
    warnings.push_back(fmt::format("{}: warning: surface {} ({}): h = {:.3g} m is below the photon spacing "
                                   "({:.3g} m): most vertices see no photon and read H = 0; raise --h or --photons",
                                   scene.path, s, scene.materials[surfaces.surfaces[s].material].name, bandwidths[s],
                                   spacing));
  }
  return warnings;
}

// Stages 1 to 3: the photons, binned per surface, each surface's h and estimator, and the light at every vertex.
struct Estimated {
  PhotonHits photons;
  SurfaceBins bins;
  std::vector<float> bandwidths;
  SurfaceEstimators estimators;
  BakedMesh baked;
  std::vector<double> irradianceNoise;  // sigma_H / H per vertex, with --target-noise
};

// Stages 2 and 3 from the photons in `e`.
void EstimateLight(Estimated& e, const Scene& scene, const SurfaceSet& surfaces, const SurfaceRegions& regions,
                   const BakeOptions& o, StageClock& clock, const Log& log) {
  e.bins = clock.Time("bin", [&] { return BinPhotons(surfaces, e.photons); });
  e.bandwidths = clock.Time("bandwidth", [&] { return SurfaceBandwidths(regions, e.bins, o.estimator, o.autoBandwidth); });
  e.estimators = clock.Time("estimators", [&] { return BuildEstimators(regions, e.bins, o.estimator, e.bandwidths); });
  e.baked = clock.Time("estimate", [&] {
    return EstimateIrradiance(scene, surfaces, e.estimators, SplitBySurface(scene, surfaces), log,
                              o.targetNoise ? &e.irradianceNoise : nullptr);
  });
}

// Stages 1 to 3 once with --photons, or in rounds until --target-noise (baker/progressive.h); then --save-photons.
Estimated TraceAndEstimate(const PhotonSource& source, const SurfaceSet& surfaces, const SurfaceRegions& regions,
                           const BakeOptions& o, BakeReport& report, StageClock& clock, const Log& log) {
  const InterruptScope interrupt;
  ProgressiveReport& progress = report.progressive;
  Estimated e{clock.Time("trace", [&] { return OpenPhotonStore(o, source, progress); })};
  for (uint64_t photons = std::max(o.photons, progress.resumedPhotons);;) {
    clock.Time("trace", [&] { GrowPhotonStore(e.photons, photons, o, source, progress, log); });
    EstimateLight(e, source.scene, surfaces, regions, o, clock, log);
    if (!o.targetNoise) break;
    const double noise = clock.Time("noise", [&] { return BakeNoise(e.baked, e.irradianceNoise); });
    progress.rounds.push_back({photons, e.photons.stats.emitted, noise});
    log.Info(fmt::format("round {}: {} photons, noise {:.4f} (target {:.4f})", progress.rounds.size(),
                         e.photons.stats.emitted, noise, *o.targetNoise));
    if (noise <= *o.targetNoise || photons >= o.maxPhotons || progress.interrupted) break;
    if (InterruptRequested()) {  // Ctrl-C came after this round's tracing: no further round
      progress.interrupted = true;
      log.Warning("interrupted: no further rounds; the bake goes on with the photons it has");
      break;
    }
    photons = NextRoundPhotons(photons, noise, *o.targetNoise, o.maxPhotons);
  }
  clock.Time("save photons", [&] { SavePhotonStore(e.photons, o, source, progress); });
  return e;
}

}  // namespace

BakeResult BakeMesh(const BakeOptions& o, const Log& log) {
  ValidateOptions(o);
  const EffectOverrides overrides = ParseEffectOverrides(o.effectsText);
  const ThreadScope threads(o.threads);
  BakeReport report{o, threads.Count()};
  StageClock clock(report.stageSeconds);

  LoadedScene loaded = clock.Time("load", [&] { return LoadObj(o.scenePath, {o.scale}); });
  const Scene& scene = loaded.scene;
  if (scene.Recentred())
    loaded.warnings.push_back(fmt::format("{}: note: the scene lies far from the origin; it is traced about "
                                          "({:.6g}, {:.6g}, {:.6g}) m for float precision, and written back in world "
                                          "coordinates", scene.path, scene.origin[0], scene.origin[1], scene.origin[2]));
  ReportWarnings(report, std::move(loaded.warnings), log);
  const SurfaceSet surfaces = clock.Time("surfaces", [&] { return BuildSurfaces(scene); });
  const std::vector<AreaLight> lights = CollectLights(scene, surfaces);
  RequireLight(scene, lights);
  report.plan = clock.Time("plan", [&] { return PlanTransport(scene, surfaces, lights, overrides); });
  std::optional<RayScene> rays;
  clock.Time("bvh", [&] { rays.emplace(scene); });

  const SurfaceRegions regions = clock.Time("regions", [&] { return BuildRegions(surfaces); });
  Estimated estimated = TraceAndEstimate({scene, lights, *rays, report.plan}, surfaces, regions, o, report, clock, log);
  const PhotonHits& photons = estimated.photons;
  const SurfaceBins& bins = estimated.bins;
  const std::vector<float>& bandwidths = estimated.bandwidths;
  const SurfaceEstimators& estimators = estimated.estimators;
  BakedMesh& baked = estimated.baked;
  ReportWarnings(report, BandwidthWarnings(scene, surfaces, bins, bandwidths, o.estimator.kind), log);
  report.exposure = DisplayExposure(baked, o.exposure);
  if (o.refine.adaptive)
    ReportWarnings(report, NoiseWarnings(scene, surfaces, bins, bandwidths, o.estimator, report.exposure,
                                         o.refine.tolerance), log);
  if (o.refine.Enabled())
    baked = clock.Time("refine", [&] {
      return RefineMesh({scene, surfaces, estimators, bandwidths, baked.mesh, report.exposure}, o.refine, report.refine, log);
    });
  ReportWarnings(report, report.refine.warnings, log);
  if (!o.mapsDirectory.empty())
    report.maps = clock.Time("maps", [&] {
      return WriteIrradianceMaps(o.mapsDirectory, o.texel, scene, surfaces, regions, estimators, log);
    });

  report.triangles = scene.triangles.size();
  report.degenerateTrianglesSkipped = scene.degenerateTrianglesSkipped;
  report.duplicateTrianglesSkipped = scene.duplicateTrianglesSkipped;
  report.vertices = baked.mesh.VertexCount();
  report.faces = baked.mesh.faces.size();
  report.lights = DescribeLights(scene, lights, photons.emitted, report.plan);
  report.surfaces = DescribeSurfaces(scene, surfaces, bins);
  report.curvedCharts = surfaces.CurvedCount();
  report.worstAreaDistortion = surfaces.WorstAreaDistortion();
  for (size_t s = 0; s < report.surfaces.size(); ++s) report.surfaces[s].bandwidth = bandwidths[s];
  report.trace = photons.stats;
  return {std::move(report), std::move(estimated.baked)};
}

BakeReport Bake(const BakeOptions& o, const Log& log) {
  ValidateOutputs(o);
  BakeResult result = BakeMesh(o, log);
  BakeReport& report = result.report;
  StageClock clock(report.stageSeconds);
  clock.Time("write", [&] { return WritePly(o.outputPath, result.mesh, {o.asciiPly, report.exposure}); });
  if (!o.reportPath.empty()) WriteReportJson(o.reportPath, report);
  return report;
}

}  // namespace pb
