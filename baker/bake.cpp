#include "baker/bake.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>

#include "baker/0_prepare_scene.h"
#include "baker/2_bin_photons.h"
#include "baker/3_irradiance_field.h"
#include "baker/4_refine_mesh.h"
#include "baker/5_write_gltf.h"
#include "baker/5_write_maps.h"
#include "baker/5_write_ply.h"
#include "baker/5_write_preview.h"
#include "baker/diagnostics.h"
#include "baker/distribution.h"
#include "baker/files/atomic_file.h"
#include "baker/photons/photon_rounds.h"
#include "baker/photons/progressive.h"
#include "baker/runtime/interrupt.h"
#include "baker/runtime/stage_clock.h"
#include "baker/runtime/threads.h"
#include "mesh/errors.h"
#include "mesh/scene_file.h"
#include "mesh/split_mesh.h"

namespace pb {
namespace {

// The files a bake writes besides its maps (whose names, surface_N.exr, no input can have), by option.
std::vector<std::pair<std::string, std::string>> OutputFilesOf(const BakeOptions& o) {
  return {{"-o", o.outputPath}, {"--report", o.reportPath}, {"--save-photons", o.savePhotonsPath},
          {"--preview", o.previewPath}};
}

// Every output, each --maps file named, once the scene's surfaces are known (-o DIR/surface_0.exr --maps DIR
// would have written one over the other).
std::vector<std::pair<std::string, std::string>> OutputsWithMaps(const BakeOptions& o, size_t surfaces) {
  std::vector<std::pair<std::string, std::string>> files = OutputFilesOf(o);
  if (!o.mapsDirectory.empty())
    for (std::string& path : MapPaths(o.mapsDirectory, surfaces)) files.emplace_back("--maps", std::move(path));
  return files;
}

// The --preview camera, read before any work: --camera, or the scene's sidecar.
std::optional<Camera> PreviewCamera(const BakeOptions& o) {
  if (o.previewPath.empty()) return std::nullopt;
  const std::string path = o.cameraPath.empty() ? CameraSidecarPath(o.scenePath) : o.cameraPath;
  try {
    return LoadCamera(path);
  } catch (const InputError& e) {
    if (!o.cameraPath.empty() || e.line() > 0) throw;
    throw InputError(e.file(), 0, e.message() + "; --preview needs a camera: give --camera FILE or write " + path);
  }
}

// The temporaries that killed runs left beside this run's outputs (baker/files/atomic_file.h), removed, as warnings.
std::vector<std::string> RemoveKilledRunsTemporaries(const BakeOptions& o) {
  std::vector<std::string> notes;
  const auto remove = [&](const std::string& directory, const std::function<bool(const std::string&)>& isOutput) {
    for (const auto& [path, pid] : RemoveStaleTemporaries(directory, isOutput))
      notes.push_back(fmt::format("{}: warning: removed this temporary file, left by a run (pid {}) that was killed "
                                  "before it finished", path, pid));
  };
  for (const auto& [option, path] : OutputFilesOf(o)) {
    if (path.empty()) continue;
    const std::filesystem::path p(path);
    remove(p.has_parent_path() ? p.parent_path().string() : ".",
           [name = p.filename().string()](const std::string& n) { return n == name; });
  }
  if (!o.mapsDirectory.empty())
    remove(o.mapsDirectory, IsMapName);
  return notes;
}

// Each output can be written, none names another or an input (--save-photons may name the --resume file). The
// scene's material libraries and textures are checked once it is loaded (BakeMesh). The --maps folder is created
// when it is missing (and removed again if the run fails while it is still empty).
void ValidateOutputs(const BakeOptions& o, OutputFiles& outputs) {
  RequireWritableLocation(o.outputPath);
  if (!o.reportPath.empty()) RequireWritableLocation(o.reportPath);
  if (!o.savePhotonsPath.empty()) RequireWritableLocation(o.savePhotonsPath);
  if (!o.previewPath.empty()) RequireWritableLocation(o.previewPath);
  RequireDistinctFiles(OutputFilesOf(o), {{"the scene", o.scenePath}, {"--camera", o.cameraPath}});
  RequireDistinctFiles({{"-o", o.outputPath}, {"--report", o.reportPath}}, {{"--resume", o.resumePath}});
  if (o.mapsDirectory.empty()) return;
  outputs.MakeDirectory(o.mapsDirectory);
  RequireWritableLocation(o.mapsDirectory + "/surface_0.exr");
}

// What the driver records as the stages run: seconds per stage and the warnings shown.
struct Journal {
  std::vector<std::pair<std::string, double>> stageSeconds;
  std::vector<std::string> warnings;

  void Warn(const std::vector<std::string>& lines, const Log& log) {
    log.Warnings(lines);
    Record(lines);
  }
  void Record(const std::vector<std::string>& lines) { warnings.insert(warnings.end(), lines.begin(), lines.end()); }
};

// Stage 3 from a round's photons: the irradiance field they give, and the light at every vertex with its noise.
struct Lit {
  std::optional<IrradianceField> field;
  BakedMesh baked;
  double noise = 0;  // the bake's predicted noise (BakeNoise)
  BakeError error;   // and its predicted error of H (PredictedError)
  NoiseParts noiseParts;  // the noise of each source alone (BakeNoiseParts)
};

// --only's surfaces (every surface without it).
std::vector<bool> EstimatedSurfaces(const BakeOptions& o, const PreparedScene& scene) {
  return o.only.empty() ? std::vector<bool>{} : SurfacesNamed(scene.scene, scene.surfaces, o.only, "--only");
}

FieldSettings FieldSettingsOf(const BakeOptions& o, const PhotonRounds& rounds) {
  return {o.estimator,      o.autoBandwidth, rounds.HeldBandwidths(), rounds.Direct(), o.referencePaths,
          o.seed,           rounds.Gaps(),   o.guidePhotons, /*pool=*/o.autoBandwidth};
}

// Rank 0 takes every process's vertices (baker/distribution.h).
void GatherVertices(BakedMesh& baked, const Distribution& d) {
  const auto gather = [&](auto& values) {
    d.GatherChunks(std::as_writable_bytes(std::span(values)), sizeof(values[0]), kVertexChunk);
  };
  gather(baked.irradiance), gather(baked.albedo), gather(baked.emitted);
  gather(baked.irradianceNoise), gather(baked.photonVarianceShare), gather(baked.sampledShare);
  gather(baked.irradianceBias), gather(baked.gatheredVarianceShare), gather(baked.gapPairs);
}

// The first round's estimate of every vertex foretold from a pilot over one vertex in kPilotStride, spread over
// the whole mesh [s]: what its field costs on this scene, at this round's settings, on this machine.
constexpr size_t kPilotStride = 64;
double ForetoldEstimateSeconds(const IrradianceField& field, const SplitMesh& base, StageClock& clock) {
  const double before = clock.Seconds("estimate");
  const size_t piloted = (base.VertexCount() + kPilotStride - 1) / kPilotStride;
  clock.Time("estimate", [&] {
    tbb::parallel_for(size_t(0), piloted, [&](size_t k) { field.LightWithNoise(base.Point(k * kPilotStride)); });
  });
  return piloted > 0 ? (clock.Seconds("estimate") - before) * double(base.VertexCount()) / double(piloted) : 0.0;
}

// Copies into `into` the vertices of every chunk (kVertexChunk vertices) that `taken` leaves 0, from `from`.
void TakeUntakenChunks(BakedMesh& into, const BakedMesh& from, const std::vector<char>& taken) {
  const auto take = [&](auto& to, const auto& source) {
    for (size_t c = 0; c < taken.size(); ++c) {
      if (taken[c] != 0) continue;
      const size_t begin = c * kVertexChunk, end = std::min(to.size(), begin + kVertexChunk);
      std::copy(source.begin() + ptrdiff_t(begin), source.begin() + ptrdiff_t(end), to.begin() + ptrdiff_t(begin));
    }
  };
  take(into.irradiance, from.irradiance), take(into.albedo, from.albedo), take(into.emitted, from.emitted);
  take(into.irradianceNoise, from.irradianceNoise), take(into.photonVarianceShare, from.photonVarianceShare);
  take(into.sampledShare, from.sampledShare), take(into.irradianceBias, from.irradianceBias);
  take(into.gatheredVarianceShare, from.gatheredVarianceShare), take(into.gapPairs, from.gapPairs);
}

// The first round's chunks that a stopped estimate did not take (`taken` 0), estimated into `baked` at no more than
// PhotonRounds::kFinishSamples shadow rays and gathered paths a point, from the round's photon estimators with
// those terms built anew; lit's field becomes that field, and the rounds report it.
void FinishAtTheFewestSamples(BakedMesh& baked, Lit& lit, const PreparedScene& scene, const SplitMesh& base,
                              const BakeOptions& o, PhotonRounds& rounds, const std::vector<char>& taken,
                              bool interrupted, StageClock& clock, const Log& log) {
  uint64_t done = 0;
  for (size_t c = 0; c < taken.size(); ++c)
    if (taken[c] != 0) done += std::min<uint64_t>(kVertexChunk, base.VertexCount() - c * kVertexChunk);
  FieldSettings fewest = FieldSettingsOf(o, rounds);
  if (fewest.direct.mode == DirectLight::kSampled)
    fewest.direct.samples = std::min(fewest.direct.samples, PhotonRounds::kFinishSamples), fewest.direct.noise = 0;
  fewest.gaps.paths = std::min(fewest.gaps.paths, PhotonRounds::kFinishSamples);
  rounds.FinishFirstEstimate(done, base.VertexCount(), interrupted, fewest.direct.samples, fewest.gaps.paths);
  lit.field.emplace(WithSampledTerms(*std::move(lit.field), scene, fewest, clock));
  const BakedMesh rest = clock.Time("estimate", [&] {
    return EstimateIrradiance(*lit.field, base, log, /*withNoise=*/true, [&](size_t c) { return taken[c] == 0; });
  });
  TakeUntakenChunks(baked, rest, taken);
}

// The round's estimate at the vertices of `base`, each with its noise; with a distribution, this process's chunks
// of them. On one process it takes no more chunks once Ctrl-C comes or the rounds' deadline passes
// (PhotonRounds::EstimateDeadline): a later round then ends there (nullopt; lit keeps the round before's vertices,
// with the new round's field), and the first round estimates the chunks left at the fewest samples, with a field
// built for them (PhotonRounds::FinishFirstEstimate), so that the bake ends within its budget with valid outputs.
std::optional<BakedMesh> EstimateUntilStopped(Lit& lit, const PreparedScene& scene, const SplitMesh& base,
                                              const BakeOptions& o, PhotonRounds& rounds, const Distribution* d,
                                              StageClock& clock, const Log& log) {
  const bool mayStop = d == nullptr && base.VertexCount() > 0;
  const double deadline = rounds.EstimateDeadline();
  std::vector<char> taken((base.VertexCount() + kVertexChunk - 1) / kVertexChunk, 0);
  std::atomic<bool> stopped{false};
  const auto owns = [&](size_t chunk) {
    if (mayStop && (stopped || InterruptRequested() || clock.Elapsed() > deadline)) {
      stopped = true;
      return false;
    }
    if (d != nullptr) return d->ClaimChunk(chunk);
    taken[chunk] = 1;
    return true;
  };
  BakedMesh baked = clock.Time("estimate", [&] {
    if (d != nullptr) d->OpenChunks(taken.size());
    BakedMesh estimated = EstimateIrradiance(*lit.field, base, log, /*withNoise=*/true, owns);
    if (d != nullptr) d->CloseChunks();
    return estimated;
  });
  if (!stopped) return baked;
  const bool interrupted = InterruptRequested();
  if (lit.baked.mesh.VertexCount() > 0) {
    rounds.EstimateInterrupted(interrupted);
    return std::nullopt;
  }
  FinishAtTheFewestSamples(baked, lit, scene, base, o, rounds, taken, interrupted, clock, log);
  return baked;
}

// Stage 3 from the round's photons at the vertices of `base`, with each vertex's noise and the bake's; with a
// distribution, each process estimates its share of the vertices for rank 0. False where a later round's estimate
// stopped (EstimateUntilStopped): lit then keeps the round before's vertices.
bool EstimateLight(Lit& lit, const PreparedScene& scene, const SplitMesh& base, const BakeOptions& o,
                   PhotonRounds& rounds, const Distribution* d, StageClock& clock, const Log& log) {
  lit.field.emplace(BuildIrradianceField(scene, rounds.Bins(), FieldSettingsOf(o, rounds), clock, &log));
  const bool first = rounds.Report().rounds.empty() && d == nullptr && o.Rounds();
  if (first && rounds.FitFirstEstimate(ForetoldEstimateSeconds(*lit.field, base, clock)))
    lit.field.emplace(WithSampledTerms(*std::move(lit.field), scene, FieldSettingsOf(o, rounds), clock));
  std::optional<BakedMesh> baked = EstimateUntilStopped(lit, scene, base, o, rounds, d, clock, log);
  if (!baked) return false;
  lit.baked = std::move(*baked);
  if (d != nullptr) clock.Time("estimate", [&] { GatherVertices(lit.baked, *d); });
  if (d == nullptr || d->Root()) clock.Time("estimate", [&] { WeighGatheredPaths(*lit.field, lit.baked); });
  if (d == nullptr || d->Root())
    clock.Time("noise", [&] {
      lit.noise = BakeNoise(lit.baked), lit.error = PredictedError(lit.baked), lit.noiseParts = BakeNoiseParts(lit.baked);
    });
  return true;
}

// The time the estimate took per vertex, over every round [s]: what a texel or a refined vertex costs.
double SecondsPerPoint(const Lit& lit, const PhotonRounds& rounds, const StageClock& clock) {
  const double points = double(lit.baked.mesh.VertexCount()) * double(std::max<size_t>(rounds.Report().rounds.size(), 1));
  return points > 0 ? clock.Seconds("estimate") / points : 0.0;
}

// Stages 1 to 3 once with --photons, or in rounds until --target-noise (baker/photons/photon_rounds.h); then
// --save-photons. Ctrl-C ends the rounds: in the first round's tracing, the bake goes on with the photons it has;
// in the first round's estimate, the vertices left read the fewest samples; in a later round, that round's estimate
// stops (at once, when the Ctrl-C came while it traced) and the bake keeps the vertices of the round before. The
// rounds' deadline stops an estimate alike.
Lit TraceAndEstimate(PhotonRounds& rounds, const PreparedScene& scene, const BakeOptions& o, OutputFiles& outputs,
                     const Distribution* distribution, StageClock& clock, const Log& log) {
  const InterruptScope interrupt;
  // The vertices estimated in every round: every surface's, or --only's (refused here, before any photon is
  // traced, when it names nothing).
  const SplitMesh base = SplitBySurface(scene.scene, scene.surfaces, EstimatedSurfaces(o, scene));
  Lit lit;
  do {
    rounds.TraceRound();
    if (!EstimateLight(lit, scene, base, o, rounds, distribution, clock, log)) break;
  } while (rounds.Continue(lit.baked, lit.noise, lit.error, lit.field->Photons().Bandwidths()));
  rounds.Save(outputs);
  return lit;
}

// What the estimated light warns about: with photons, lights that got none and bandwidths below the photons'
// spacing; then a bake that reads 0 everywhere, noise that shows, and an --exposure that shows nothing.
void WarnAboutTheLight(Journal& journal, const BakeOptions& o, const PreparedScene& scene, const PhotonRounds& rounds,
                       const Lit& lit, const Log& log) {
  if (o.referencePaths == 0) {
    journal.Warn(UnlitLightWarnings(scene, rounds.Store(), o.direct.mode == DirectLight::kSampled), log);
    journal.Warn(BandwidthWarnings(*lit.field, rounds.Bins(), o.estimator.kind, o.autoBandwidth), log);
  }
  journal.Warn(DarkBakeWarnings(o.scenePath, lit.baked), log);
  if (o.referencePaths == 0) journal.Warn(BackLitWarnings(scene, rounds.Bins(), lit.baked), log);
  journal.Warn(VisibleNoiseWarnings({.scenePath = o.scenePath, .baked = lit.baked, .noise = lit.noise,
                                     .emitted = rounds.Store().stats.emitted, .referencePaths = o.referencePaths,
                                     .direct = o.direct, .rounds = o.Rounds()}), log);
  journal.Warn(ExposureWarnings(o.exposure, lit.baked), log);
}

// The scene as the options describe it. Covered parts are found on a lattice of spacing h / 2, at most 1/175 of
// the scene's diagonal (10 mm on the box, whose 1.74 m includes the light behind the camera), so that a block's
// corner is kept past the vertices of a mesh finer than h, and the lattice scales with the scene
// (docs/conventions.md, "Covered parts"). With --h auto, whose h is known only from the photons, 1/290 of the diagonal: 25 mm on the
// office, as its default h gave, and the same lattice for a scene in any unit.
constexpr double kMaxCoverSpacingPerDiagonal = 1.0 / 175, kAutoCoverSpacingPerDiagonal = 1.0 / 290;
SceneSettings SceneOf(const BakeOptions& o) {
  const CoverSettings covers = !o.findCovers ? CoverSettings{.spacing = 0}
                               : o.autoBandwidth
                                   ? CoverSettings{.spacing = FLT_MAX, .maxSpacingPerDiagonal = kAutoCoverSpacingPerDiagonal}
                                   : CoverSettings{.spacing = o.estimator.bandwidth / 2, .maxSpacingPerDiagonal = kMaxCoverSpacingPerDiagonal};
  return {o.scenePath, o.scale, ParseEffectOverrides(o.effectsText), covers, o.lightsPath, o.luminousEfficacy};
}

}  // namespace

BakeResult BakeMesh(const BakeOptions& o, const Log& log, OutputFiles& outputs, const Distribution* distribution) {
  o.Validate();
  const ThreadScope threads(o.threads);
  Journal journal;
  StageClock clock(journal.stageSeconds);

  const PreparedScene scene = PrepareScene(SceneOf(o), clock, &log);
  RequireDistinctFiles(OutputsWithMaps(o, scene.surfaces.surfaces.size()), scene.scene.InputFiles());
  scene.warningsShown ? journal.Record(scene.warnings) : journal.Warn(scene.warnings, log);
  if (!o.mapsDirectory.empty()) CheckMapTexels(o.texel, scene.regions, threads.Count());
  if (o.refine.subdivide > 0) CheckSubdivisionMemory(scene.scene.triangles.size(), o.refine.subdivide);
  PhotonRounds rounds(scene, o, distribution, clock, log);
  Lit lit = TraceAndEstimate(rounds, scene, o, outputs, distribution, clock, log);
  const IrradianceField& field = *lit.field;
  WarnAboutTheLight(journal, o, scene, rounds, lit, log);
  const float exposure = DisplayExposure(lit.baked, o.exposure);

  if (o.sh) clock.Time("directions", [&] { lit.field->PrepareMoments(rounds.Bins(), &log); });
  MapsWritten maps;
  const double secondsPerPoint = SecondsPerPoint(lit, rounds, clock);  // what a texel or a refined vertex costs
  journal.Warn(SubdivisionTimeWarnings(scene.scene.triangles.size(), o.refine.subdivide, secondsPerPoint), log);
  if (!o.mapsDirectory.empty()) {
    journal.Warn(MapTimeWarnings(o.texel, scene.regions, secondsPerPoint), log);
    maps = clock.Time("maps", [&] {
      if (o.only.empty()) return WriteIrradianceMaps(outputs, o.mapsDirectory, o.texel, field, lit.baked.mesh, log, {}, o.sh);
      return WriteIrradianceMaps(outputs, o.mapsDirectory, o.texel, field, SplitBySurface(scene.scene, scene.surfaces),
                                 log, EstimatedSurfaces(o, scene), o.sh);
    });
    journal.Warn(StaleMapWarnings(o.mapsDirectory, maps.paths), log);
  }
  RefineReport refine;
  if (o.refine.adaptive) journal.Warn(NoiseWarnings(field, rounds.Bins(), exposure, o.refine.tolerance), log);
  if (o.refine.Enabled()) {
    RefinedMesh refined = clock.Time("refine", [&] { return RefineMesh({field, lit.baked.mesh, exposure}, o.refine, log); });
    if (refined.report.interrupted) {
      journal.Warn({fmt::format("{}: warning: Ctrl-C stopped refinement; the mesh is written as estimated, unrefined",
                                o.scenePath)}, log);
    } else {
      lit.baked = std::move(refined.mesh);
      refine = std::move(refined.report);
      journal.Warn(refine.warnings, log);
    }
  }
  if (o.sh)
    clock.Time("directions", [&] { EstimateDirections(field, lit.baked, log); });

  BakeReport report = DescribeBake({o, threads.Count(), scene, rounds.Store(), rounds.Bins(), field, lit.baked,
                                    exposure, refine, maps, rounds.Report(), lit.noise, lit.error, lit.noiseParts, journal.stageSeconds, journal.warnings});
  return {std::move(report), std::move(lit.baked), NamesOf(scene.scene, scene.surfaces)};
}

BakeResult BakeMesh(const BakeOptions& o, const Log& log) {
  const InterruptScope interrupt(InterruptScope::Start::kFromInnerScope);  // from tracing to the commit
  OutputFiles outputs;
  BakeResult result = BakeMesh(o, log, outputs);
  outputs.Commit();
  return result;
}

BakeReport Bake(const BakeOptions& o, const Log& log, const Distribution* distribution) {
  o.Validate();
  // From tracing to the commit, the first Ctrl-C asks every stage to finish with what it has; before, it ends the
  // run at once. The scope outlives `outputs`, so that a second Ctrl-C finds their temporaries held.
  const InterruptScope interrupt(InterruptScope::Start::kFromInnerScope);
  OutputFiles outputs;
  ValidateOutputs(o, outputs);
  for (const std::string& note : RemoveKilledRunsTemporaries(o)) log.Warning(note);
  const std::optional<Camera> camera = PreviewCamera(o);
  BakeResult result = BakeMesh(o, log, outputs, distribution);
  BakeReport& report = result.report;
  StageClock clock(report.stageSeconds);
  if (camera)
    clock.Time("preview", [&] {
      WritePreview(outputs, o.previewPath, result.mesh, {*camera, o.previewWidth, o.previewHeight, report.exposure}, log);
    });
  clock.Time("write", [&] {
    if (HasGltfExtension(o.outputPath))
      WriteGltf(outputs, o.outputPath, result.mesh, result.names, report.exposure);
    else
      WritePly(outputs, o.outputPath, result.mesh, {o.asciiPly, report.exposure});
    if (!o.reportPath.empty()) WriteReportJson(outputs, o.reportPath, report);
    outputs.Commit();
  });
  return report;
}

void TraceShareOfBake(const BakeOptions& o, const Log& log, const Distribution& distribution) {
  o.Validate();
  const ThreadScope threads(o.threads);
  std::vector<std::pair<std::string, double>> seconds;
  StageClock clock(seconds);
  const PreparedScene scene = PrepareScene(SceneOf(o), clock, &log);
  PhotonRounds rounds(scene, o, &distribution, clock, log);
  OutputFiles none;  // a process other than rank 0 writes nothing
  TraceAndEstimate(rounds, scene, o, none, &distribution, clock, log);
}

}  // namespace pb
