#include "baker/bake.h"

#include <fmt/format.h>

#include <cfloat>
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
#include "baker/photons/trace_and_estimate.h"
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

// The rounds' own settings, from the options.
RoundSettings RoundSettingsOf(const BakeOptions& o) {
  return {.scenePath = o.scenePath, .photons = o.photons, .maxPhotons = o.maxPhotons, .maxSeconds = o.maxSeconds,
          .maxRounds = o.maxRounds, .targetNoise = o.targetNoise, .targetError = o.targetError, .seed = o.seed,
          .maxBounces = o.maxBounces, .resumePath = o.resumePath, .savePhotonsPath = o.savePhotonsPath,
          .estimator = o.estimator, .referencePaths = o.referencePaths, .sh = o.sh,
          .sampledDirect = o.direct.mode == DirectLight::kSampled, .shadowRays = o.direct.samples,
          .directNoise = o.direct.noise, .fixedShadowRays = o.direct.fixedSamples, .gapPaths = o.gaps.paths,
          .gapNoise = o.gaps.noise, .fixedGapPaths = o.gaps.fixedPaths};
}

// --only's surfaces (every surface without it); an InputError when it names none.
std::vector<bool> EstimatedSurfaces(const BakeOptions& o, const PreparedScene& scene) {
  return o.only.empty() ? std::vector<bool>{} : SurfacesNamed(scene.scene, scene.surfaces, o.only, "--only");
}

// Stage 3's own settings, from the options; the rounds add their plan (baker/photons/trace_and_estimate.h).
FieldSettings FieldOf(const BakeOptions& o) {
  return {.estimator = o.estimator, .direct = o.direct,
          .referencePaths = o.referencePaths, .seed = o.seed, .gaps = o.gaps, .guidePhotons = o.guidePhotons,
          .pool = !o.estimator.bandwidth};
}

// Stages 1 to 3 (baker/photons/trace_and_estimate.h); --only is refused before any photon is traced when it names
// no surface.
Lit TraceAndEstimate(PhotonRounds& rounds, const PreparedScene& scene, const BakeOptions& o, OutputFiles& outputs,
                     const Distribution* distribution, StageClock& clock, const Log& log) {
  return TraceAndEstimate(rounds, scene, FieldOf(o), EstimatedSurfaces(o, scene), outputs, distribution, clock, log);
}

// What the estimated light warns about: with photons, lights that got none and bandwidths below the photons'
// spacing; then a bake that reads 0 everywhere, noise that shows, and an --exposure that shows nothing.
void WarnAboutTheLight(Journal& journal, const BakeOptions& o, const PreparedScene& scene, const PhotonRounds& rounds,
                       const Lit& lit, const Log& log) {
  if (o.referencePaths == 0) {
    journal.Warn(UnlitLightWarnings(scene, rounds.Store(), o.direct.mode == DirectLight::kSampled), log);
    journal.Warn(BandwidthWarnings(*lit.field, rounds.Bins(), o.estimator), log);
  }
  journal.Warn(DarkBakeWarnings(o.scenePath, lit.baked), log);
  if (o.referencePaths == 0) journal.Warn(BackLitWarnings(scene, rounds.Bins(), lit.baked), log);
  journal.Warn(VisibleNoiseWarnings({.scenePath = o.scenePath, .baked = lit.baked, .noise = lit.noise,
                                     .emitted = rounds.Store().stats.emitted, .referencePaths = o.referencePaths,
                                     .direct = o.direct, .rounds = o.Rounds()}), log);
  journal.Warn(ExposureWarnings(o.exposure, lit.baked), log);
}

// --maps: each surface's irradiance map (with --only, its surfaces'), staged in `outputs`, with the warnings of
// their time and of an earlier bake's maps in the folder.
// The mesh the maps are made over: the estimated one, or with --only every surface's, held in `all` (and the maps
// only theirs).
const SplitMesh& MapsBase(const BakeOptions& o, const PreparedScene& scene, const Lit& lit, std::optional<SplitMesh>& all) {
  if (o.only.empty()) return lit.baked.mesh;
  return all.emplace(SplitBySurface(scene.scene, scene.surfaces));
}
std::vector<bool> MappedSurfaces(const BakeOptions& o, const PreparedScene& scene) {
  return o.only.empty() ? std::vector<bool>{} : EstimatedSurfaces(o, scene);
}

MapsWritten WriteMaps(Journal& journal, const BakeOptions& o, const PreparedScene& scene, Lit& lit,
                      double secondsPerPoint, OutputFiles& outputs, const Distribution* distribution, StageClock& clock,
                      const Log& log) {
  if (o.mapsDirectory.empty()) return {};
  journal.Warn(MapTimeWarnings(o.texel, scene.regions, secondsPerPoint), log);
  const MapsWritten maps = clock.Time("maps", [&] {
    if (distribution != nullptr) lit.field->TakeRankZerosLateState(*distribution);
    std::optional<SplitMesh> all;
    return WriteIrradianceMaps(outputs, o.mapsDirectory, o.texel, *lit.field, MapsBase(o, scene, lit, all), log,
                               MappedSurfaces(o, scene), o.sh, distribution);
  });
  journal.Warn(StaleMapWarnings(o.mapsDirectory, maps.paths), log);
  return maps;
}

// --refine / --subdivide: lit's vertices replaced by the refined mesh's, unless a Ctrl-C stopped refinement (the
// mesh is then written as estimated, with a warning); with the warnings of its noise and its budget.
RefineReport RefineTheMesh(Journal& journal, const BakeOptions& o, Lit& lit, const SurfaceBins& bins, float exposure,
                           StageClock& clock, const Log& log) {
  const IrradianceField& field = *lit.field;
  if (o.refine.adaptive) journal.Warn(NoiseWarnings(field, bins, exposure, o.refine.tolerance), log);
  if (!o.refine.Enabled()) return {};
  RefinedMesh refined =
      clock.Time("refine", [&] { return RefineMesh({field, lit.baked.mesh, exposure}, o.refine, log); });
  if (refined.report.interrupted) {
    journal.Warn({fmt::format("{}: warning: Ctrl-C stopped refinement; the mesh is written as estimated, unrefined",
                              o.scenePath)}, log);
    return {};
  }
  lit.baked = std::move(refined.mesh);
  journal.Warn(refined.report.warnings, log);
  return std::move(refined.report);
}

// The scene as the options describe it. Covered parts are found on a lattice of spacing h / 2, at most 1/175 of
// the scene's diagonal (10 mm on the box, whose 1.74 m includes the light behind the camera), so that a block's
// corner is kept past the vertices of a mesh finer than h, and the lattice scales with the scene
// (docs/conventions.md, "Covered parts"). With --h auto, whose h is known only from the photons, 1/290 of the diagonal: 25 mm on the
// office, as its default h gave, and the same lattice for a scene in any unit.
constexpr double kMaxCoverSpacingPerDiagonal = 1.0 / 175, kAutoCoverSpacingPerDiagonal = 1.0 / 290;
SceneSettings SceneOf(const BakeOptions& o) {
  const CoverSettings covers = !o.findCovers ? CoverSettings{.spacing = 0}
                               : !o.estimator.bandwidth
                                   ? CoverSettings{.spacing = FLT_MAX, .maxSpacingPerDiagonal = kAutoCoverSpacingPerDiagonal}
                                   : CoverSettings{.spacing = *o.estimator.bandwidth / 2, .maxSpacingPerDiagonal = kMaxCoverSpacingPerDiagonal};
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
  PhotonRounds rounds(scene, RoundSettingsOf(o), distribution, clock, log);
  Lit lit = TraceAndEstimate(rounds, scene, o, outputs, distribution, clock, log);
  const IrradianceField& field = *lit.field;
  WarnAboutTheLight(journal, o, scene, rounds, lit, log);
  const float exposure = DisplayExposure(lit.baked, o.exposure);

  if (o.sh) clock.Time("directions", [&] { lit.field->PrepareMoments(rounds.Bins(), &log); });
  const double secondsPerPoint = SecondsPerPoint(lit, rounds, clock);  // what a texel or a refined vertex costs
  journal.Warn(SubdivisionTimeWarnings(scene.scene.triangles.size(), o.refine.subdivide, secondsPerPoint), log);
  const MapsWritten maps = WriteMaps(journal, o, scene, lit, secondsPerPoint, outputs, distribution, clock, log);
  const RefineReport refine = RefineTheMesh(journal, o, lit, rounds.Bins(), exposure, clock, log);
  if (o.referencePaths == 0) journal.Warn(MissedLightWarnings(scene, rounds.Bins(), lit.baked), log);  // as written
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

void BakeAndSummarise(const BakeOptions& o, const Log& log, const Distribution* distribution) {
  PrintSummary(Bake(o, log, distribution), log);
}

void TraceShareOfBake(const BakeOptions& o, const Log& log, const Distribution& distribution) {
  o.Validate();
  const ThreadScope threads(o.threads);
  std::vector<std::pair<std::string, double>> seconds;
  StageClock clock(seconds);
  const PreparedScene scene = PrepareScene(SceneOf(o), clock, &log);
  PhotonRounds rounds(scene, RoundSettingsOf(o), &distribution, clock, log);
  OutputFiles none;  // a process other than rank 0 writes nothing
  Lit lit = TraceAndEstimate(rounds, scene, o, none, &distribution, clock, log);
  if (o.mapsDirectory.empty()) return;  // rank 0 alone refines and writes the rest
  if (o.sh) lit.field->PrepareMoments(rounds.Bins());
  lit.field->TakeRankZerosLateState(distribution);
  std::optional<SplitMesh> all;
  ShareIrradianceMaps(o.texel, *lit.field, MapsBase(o, scene, lit, all), MappedSurfaces(o, scene), o.sh, distribution);
}

}  // namespace pb
