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
#include "baker/distribution.h"
#include "baker/files/atomic_file.h"
#include "baker/photons/photon_rounds.h"
#include "baker/photons/progressive.h"
#include "baker/runtime/interrupt.h"
#include "baker/runtime/stage_clock.h"
#include "baker/runtime/threads.h"
#include "baker/tone_map.h"
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

// Warns about each surface whose h is below half its mean photon spacing sqrt(A / hits), A the area that no other
// geometry covers (where H is 0 in truth): most of its vertices see no photon within h, so the photons' H there
// reads 0 between them. knn adapts its radius, and --h auto keeps 20 photons within h wherever a surface has
// photons enough to choose from (one with a handful, a table leg's end, is too small to matter): neither is
// warned about.
std::vector<std::string> BandwidthWarnings(const IrradianceField& field, const SurfaceBins& bins, const BakeOptions& o) {
  const PreparedScene& p = field.Prepared();
  std::vector<std::string> warnings;
  if (o.estimator.kind == EstimatorKind::kNearest || o.autoBandwidth) return warnings;
  for (uint32_t s = 0; s < p.surfaces.surfaces.size(); ++s) {
    const double area = p.surfaces.surfaces[s].area;
    const double open = area - (p.coveredRegions[s] ? p.coveredRegions[s]->Area() : 0.0);
    if (bins.FrontHits(s) == 0 || open <= 0.01 * area) continue;
    const double spacing = std::sqrt(open / double(bins.FrontHits(s)));
    if (field.Bandwidth(s) >= 0.5 * spacing) continue;
    warnings.push_back(fmt::format("{}: warning: surface {} ({}): h = {:.3g} m is below the photon spacing "
                                   "({:.3g} m): most vertices see no photon and the photons' H reads 0 there; raise --h or --photons",
                                   p.scene.path, s, p.scene.materials[p.surfaces.surfaces[s].material].name,
                                   field.Bandwidth(s), spacing));
  }
  return warnings;
}

// Warns about the lights that reach the scene but got no photon: their share n Phi_l / Phi is below one, so their
// light is missing from the bake (with --direct sampled, only their interreflected light). Up to kNamedUnlit
// lights are named one by one; more make one line: how many, the flux they carry, and the brightest of them.
constexpr size_t kNamedUnlit = 3;

// "the light of material 'NAME' (P W" and what follows in `rest`, then ")".
std::string UnlitLightName(const PreparedScene& scene, const Light& light, const std::string& rest = "") {
  const std::string which = light.IsArea() ? "the light of material" : fmt::format("the {} light", LightKindName(light.kind));
  return fmt::format("{} '{}' ({:.3g} W{})", which, LightName(scene.scene, light), light.Power().Mean(), rest);
}

std::vector<std::string> UnlitLightWarnings(const PreparedScene& scene, const PhotonStore& photons, bool sampled) {
  double total = 0, unlitFlux = 0, weakest = INFINITY;
  std::vector<size_t> unlit;
  for (size_t l = 0; l < scene.lights.size(); ++l) {
    if (!scene.plan.lightReaches[l]) continue;
    const double power = scene.lights[l].Power().Mean();
    total += power;
    if (photons.emitted[l] > 0 || !(power > 0)) continue;  // a light that emits nothing misses nothing
    unlit.push_back(l), unlitFlux += power, weakest = std::min(weakest, power);
  }
  const std::string missing = sampled ? "interreflected light is missing (the direct light is sampled)" : "light is missing";
  std::vector<std::string> warnings;
  if (unlit.size() <= kNamedUnlit) {
    for (size_t l : unlit)
      warnings.push_back(fmt::format("{}: warning: {} got no photon, so its {}; raise --photons to at least {:.0f}",
                                     scene.scene.path, UnlitLightName(scene, scene.lights[l], fmt::format(" of {:.3g} W", total)),
                                     missing, std::ceil(total / scene.lights[l].Power().Mean())));
    return warnings;
  }
  std::stable_sort(unlit.begin(), unlit.end(), [&](size_t a, size_t b) {
    return scene.lights[a].Power().Mean() > scene.lights[b].Power().Mean();
  });
  std::string brightest;
  for (size_t i = 0; i < kNamedUnlit; ++i)  // with its index: many lights share a material's name
    brightest += (i ? ", " : "") + UnlitLightName(scene, scene.lights[unlit[i]], fmt::format(", light {}", unlit[i]));
  warnings.push_back(fmt::format("{}: warning: {} of {} lights got no photon: {:.3g} W of {:.3g} W ({:.2g}% of the "
                                 "flux), so their {}; the brightest: {}; raise --photons to at least {:.0f} for every "
                                 "light to get one", scene.scene.path, unlit.size(), scene.lights.size(), unlitFlux,
                                 total, 100 * unlitFlux / total, missing, brightest, std::ceil(total / weakest)));
  return warnings;
}

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

// Noise that shows as blotches: above 2% of the displayed light, about 5 of 255 grey levels.
constexpr double kVisibleNoise = 0.02;

// Rounded up to two significant digits: 3,456,789 -> 3,500,000.
uint64_t TwoDigits(double x) {
  const double unit = std::pow(10.0, std::max(0.0, std::floor(std::log10(std::max(x, 1.0))) - 1));
  return uint64_t(std::ceil(x / unit) * unit);
}

// Warns when the user's --exposure shows every lit vertex black, or every one white (each channel it has at 255):
// within its range it can still be far from this scene's light (the automatic exposure says how far).
std::vector<std::string> ExposureWarnings(const BakeOptions& o, const BakedMesh& baked) {
  if (!o.exposure) return {};
  bool black = true, white = true, lit = false;
  for (size_t v = 0; v < baked.mesh.VertexCount(); ++v) {
    const Rgb radiance = baked.Radiance(v);
    if (!(radiance.Max() > 0)) continue;
    const std::array<uint8_t, 3> shown = ToneMap(radiance, *o.exposure);
    lit = true;
    black = black && shown == std::array<uint8_t, 3>{0, 0, 0};
    const float channels[3] = {radiance.r, radiance.g, radiance.b};
    for (int c = 0; c < 3; ++c) white = white && (shown[c] == 255 || !(channels[c] > 0));
  }
  if (!lit || !(black || white)) return {};
  return {fmt::format("--exposure {}: warning: the display colours show every lit vertex {}; the automatic exposure "
                      "would be {:.4g}", *o.exposure, black ? "black" : "white", DisplayExposure(baked, std::nullopt))};
}

// Warns when every vertex reads no light: the lights shine only on back sides or along the surfaces (a sun from
// below the ground, a point light in the plane of the only surface), so the outputs are black.
std::vector<std::string> DarkBakeWarnings(const BakeOptions& o, const BakedMesh& baked) {
  if (std::any_of(baked.irradiance.begin(), baked.irradiance.end(), [](Rgb h) { return h.Max() > 0; })) return {};
  return {fmt::format("{}: warning: every vertex reads 0 W/m^2: no light reached the front side of any surface (a "
                      "light behind or in the plane of the surfaces, a sun from below); the outputs are black",
                      o.scenePath)};
}

// Warns about the surfaces lit only from behind: photons reached their back sides (at least kBackLitHits) but no
// vertex of their front reads any light, so they are black. Their fronts usually face into the object they close
// (faces wound the wrong way round in the modelling tool): on the staircase, 4 surfaces and 0.7 m^2 read 0 this way
// without a word. The largest kNamedUnlit are named, the rest counted.
constexpr uint64_t kBackLitHits = 20;
std::vector<std::string> BackLitWarnings(const PreparedScene& scene, const SurfaceBins& bins, const BakedMesh& baked) {
  std::vector<bool> lit(bins.SurfaceCount(), false);
  for (size_t v = 0; v < baked.mesh.VertexCount(); ++v)
    if (baked.irradiance[v].Max() > 0) lit[baked.mesh.surface[v]] = true;
  std::vector<uint32_t> dark;
  double area = 0;
  uint64_t hits = 0;
  for (uint32_t s = 0; s < bins.SurfaceCount(); ++s) {
    if (lit[s] || bins.BackHits(s) < kBackLitHits || bins.FrontHits(s) > 0) continue;
    dark.push_back(s), area += scene.surfaces.surfaces[s].area, hits += bins.BackHits(s);
  }
  if (dark.empty()) return {};
  std::stable_sort(dark.begin(), dark.end(), [&](uint32_t a, uint32_t b) {
    return scene.surfaces.surfaces[a].area > scene.surfaces.surfaces[b].area;
  });
  std::string named;
  for (size_t i = 0; i < std::min(dark.size(), kNamedUnlit); ++i) {
    const Surface& surface = scene.surfaces.surfaces[dark[i]];
    named += fmt::format("{}surface {} ('{}', {:.3g} m^2, {} back hits)", i ? ", " : "", dark[i],
                         scene.scene.materials[surface.material].name, surface.area, bins.BackHits(dark[i]));
  }
  return {fmt::format("{}: warning: {} surface{} of {:.3g} m^2 in all lit only from behind: {} photons reached the "
                      "back and none the front, so the front reads black; its faces may be wound the wrong way round "
                      "(the front is the side from which the corners run counter-clockwise); the largest: {}",
                      scene.scene.path, dark.size(), dark.size() == 1 ? "" : "s", area, hits, named)};
}

// Warns when the bake's noise is visible, naming what would bring it under kVisibleNoise (RemedyForNoise): more
// photons, and more shadow rays (or --reference paths) where the points' own noise is most of it, and the rounds
// that find them. None when the user chose a --target-noise or --target-error.
std::vector<std::string> VisibleNoiseWarnings(const BakeOptions& o, const Lit& lit, const PhotonRounds& rounds) {
  if (lit.noise <= kVisibleNoise || o.Rounds()) return {};
  const bool reference = o.referencePaths > 0;
  const uint32_t samples = reference ? o.referencePaths : o.direct.mode == DirectLight::kSampled ? o.direct.samples : 0;
  const uint64_t emitted = rounds.Store().stats.emitted;
  const NoiseRemedy r = RemedyForNoise(lit.baked, kVisibleNoise, emitted, samples);
  std::vector<std::string> remedies;
  if (!reference && r.photons > emitted)
    remedies.push_back(fmt::format("--photons {}", TwoDigits(1.05 * double(r.photons))));
  // With --direct-noise the points' own noise falls by sqrt(factor) when their target does; and at most half the
  // visible noise, as the pilot's noisy estimate leaves the 95th percentile above the target (1.3x it measured).
  const bool adaptive = !reference && o.direct.mode == DirectLight::kSampled && o.direct.noise > 0;
  if (r.pointSamples > samples && adaptive)
    remedies.push_back(fmt::format("--direct-noise {:.2g}", std::min(o.direct.noise / std::sqrt(1.05 * r.pointSamples / samples),
                                                                  kVisibleNoise / 2)));
  else if (r.pointSamples > samples)
    remedies.push_back(fmt::format("{} {}", reference ? "--reference" : "--direct-samples",
                                   TwoDigits(1.05 * r.pointSamples)));
  // No count of photons or shadow rays brings it under: what is left is the paths gathered in narrow gaps, which
  // neither lowers (RemedyForNoise leaves their noise as it is).
  const std::string remedy =
      remedies.empty()
          ? fmt::format("no count of photons or shadow rays alone brings it under {:.0f}%: the paths gathered in "
                        "narrow gaps hold it (raise --gap-paths)", 100 * kVisibleNoise)
          : fmt::format("about {} would bring it under {:.0f}%{}",
                        remedies.size() == 1 ? remedies[0] : remedies[0] + " and " + remedies[1], 100 * kVisibleNoise,
                        reference
                            ? ""
                            : fmt::format(" (or --target-noise {} finds the photons itself)", kVisibleNoise));
  return {fmt::format("{}: warning: the bake's noise is {:.1f}% (the 95th percentile of the displayed light's "
                      "predicted relative error), enough to show as blotches; {}", o.scenePath, 100 * lit.noise, remedy)};
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
    journal.Warn(BandwidthWarnings(*lit.field, rounds.Bins(), o), log);
  }
  journal.Warn(DarkBakeWarnings(o, lit.baked), log);
  if (o.referencePaths == 0) journal.Warn(BackLitWarnings(scene, rounds.Bins(), lit.baked), log);
  journal.Warn(VisibleNoiseWarnings(o, lit, rounds), log);
  journal.Warn(ExposureWarnings(o, lit.baked), log);
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
