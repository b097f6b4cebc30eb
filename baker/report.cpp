#include "baker/report.h"

#include <algorithm>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <nlohmann/json.hpp>

#include "baker/files/json_file.h"

namespace pb {
namespace {

nlohmann::json Json(Rgb c) { return {c.r, c.g, c.b}; }
nlohmann::json Json(const RgbSum& c) { return {c.r, c.g, c.b}; }
std::string Text(Rgb c) { return fmt::format("({:.4g}, {:.4g}, {:.4g})", c.r, c.g, c.b); }

nlohmann::json OptionsJson(const BakeOptions& o) {
  return {{"scene", o.scenePath},        {"output", o.outputPath}, {"estimator", EstimatorName(o.estimator.kind)},
          {"kernel", KernelName(o.estimator.kernel)}, {"k", o.estimator.neighbours},
          {"edge_correction", o.estimator.edgeCorrection}, {"local_linear", o.estimator.localLinear},
          {"find_covers", o.findCovers},
          {"h_m", o.estimator.bandwidth ? nlohmann::json(*o.estimator.bandwidth) : nlohmann::json("auto")},          {"photons", o.photons},   {"seed", o.seed},
          {"threads_requested", o.threads}, {"scale_m_per_unit", o.scale}, {"ascii", o.asciiPly},
          {"lights", o.lightsPath}, {"luminous_efficacy_lm_per_W", o.luminousEfficacy},
          {"max_bounces", o.maxBounces}, {"direct", DirectLightName(o.direct.mode)},
          {"direct_samples", o.direct.samples}, {"direct_noise", o.direct.noise},
          {"gap_paths", o.gaps.paths}, {"gap_small_area_h2", o.gaps.smallArea},
          {"gap_small_share", o.gaps.smallShare}, {"gap_edges", o.gaps.edges}, {"reference_paths", o.referencePaths}, {"guide_photons", o.guidePhotons},
          {"effects", o.effectsText}, {"refine", o.refine.adaptive}, {"tolerance", o.refine.tolerance},
          {"max_vertices", o.refine.maxVertices}, {"subdivide", o.refine.subdivide}, {"resume", o.resumePath},
          {"save_photons", o.savePhotonsPath},
          {"target_noise", o.targetNoise ? nlohmann::json(*o.targetNoise) : nlohmann::json()},
          {"target_error", o.targetError ? nlohmann::json(*o.targetError) : nlohmann::json()},
          {"max_photons", o.maxPhotons}, {"max_seconds", o.maxSeconds}, {"max_rounds", o.maxRounds}};
}

double StageSeconds(const BakeReport& r, const std::string& stage) {
  for (const auto& [name, seconds] : r.stageSeconds)
    if (name == stage) return seconds;
  return 0;
}

nlohmann::json ProgressiveJson(const ProgressiveReport& p) {
  nlohmann::json rounds = nlohmann::json::array();
  for (const RoundReport& r : p.rounds)
    rounds.push_back({{"requested", r.requested}, {"photons", r.photons}, {"shadow_rays", r.shadowRays},
                      {"direct_noise", r.directNoise}, {"noise", r.noise}, {"error", r.error}, {"seconds", r.seconds}});
  return {{"resumed_from", p.resumedFrom}, {"resumed_photons", p.resumedPhotons}, {"saved_to", p.savedTo},
          {"interrupted", p.interrupted}, {"estimate_stopped", p.estimateStopped},
          {"finished_at_fewest_samples_vertices", p.finishedVertices}, {"target_noise", p.target && !p.targetIsError ? nlohmann::json(*p.target) : nlohmann::json()},
          {"target_error", p.target && p.targetIsError ? nlohmann::json(*p.target) : nlohmann::json()},
          {"target_met", p.TargetMet()}, {"stopped_by", p.stoppedBy}, {"rounds", rounds},
          {"first_round_cut", p.firstRoundCut}, {"first_round_foretold_s", p.firstRoundForetold},
          {"small_surfaces_left_out", {{"surfaces", p.small.leftOut}, {"gathered", p.small.gathered},
                                       {"vertices_gathered", p.small.vertices}, {"seconds", p.small.seconds},
                                       {"interrupted", p.small.interrupted}}}};
}

// "  small     ...", or "" where the defaults' share left no small surface out.
std::string SmallSurfacesLine(const ProgressiveReport::SmallSurfaces& small) {
  if (small.leftOut == 0) return "";
  const bool all = small.gathered == small.leftOut;
  return fmt::format("  small     the time the rounds left gathered paths at the {} vertices of {} of the {} surfaces "
                     "smaller than their kernel that the share of the triangles left to the photons, the smallest "
                     "first ({:.1f} s){}\n", small.vertices, small.gathered, small.leftOut, small.seconds,
                     all                 ? ""
                     : small.interrupted ? "; Ctrl-C ended it"
                                         : "; the time budget ended it, so this machine's speed chose how many");
}

// The rounds of --target-noise or --target-error, how they ended, and the options that repeat the bake's bytes
// without rounds.
std::string RoundLines(const ProgressiveReport& p) {
  std::string s = fmt::format("  rounds    {} to target {} {:.4f}:", p.rounds.size(), p.targetIsError ? "error" : "noise", *p.target);
  for (const RoundReport& r : p.rounds)
    s += fmt::format(" {} photons{} -> {:.4f} ({:.1f} s) |", r.requested,
                     r.shadowRays ? ", " + ShadowRays(r) : "", p.Measured(r), r.seconds);
  s += p.TargetMet() ? " met\n"
       : p.stoppedBy.empty() ? " NOT met\n"
                             : fmt::format(" NOT met: stopped by {}\n", p.stoppedBy);
  if (p.firstRoundCut < 1)
    s += fmt::format("  fitted    the first round's estimate, foretold at {:.0f} s, would have passed the time budget: its "
                     "shadow rays and gathered paths were cut by {:.2f} (give --direct-samples and --gap-paths to "
                     "choose them)\n", p.firstRoundForetold, p.firstRoundCut);
  s += SmallSurfacesLine(p.small);
  if (p.stoppedBy.rfind("the time budget", 0) != 0) return s;
  if (p.small.gathered < p.small.leftOut)
    return s + fmt::format("  repeat    the time budget, so this machine's speed, chose the last round (--max-rounds {} "
                           "repeats the rounds on any machine) and how many small surfaces were gathered after them\n",
                           p.rounds.size());
  return s + fmt::format("  repeat    the time budget, so this machine's speed, chose the last round: --max-rounds {} "
                         "gives these bytes on any machine\n", p.rounds.size());
}

// The progressive lines of the summary: what was resumed and saved, the rounds, an interruption.
std::string ProgressiveLines(const ProgressiveReport& p, uint64_t emitted) {
  std::string s;
  if (!p.resumedFrom.empty())
    s += fmt::format("  resumed   {} photons from {}; {} traced now\n", p.resumedPhotons, p.resumedFrom,
                     emitted - p.resumedPhotons);
  if (p.target) s += RoundLines(p);
  if (p.finishedVertices > 0)
    s += fmt::format("  {}: {}; the outputs are valid\n", p.interrupted ? "INTERRUPTED" : "STOPPED", p.stoppedBy);
  else if (p.estimateStopped)
    s += fmt::format("  {}: {} stopped round {}; the vertices are round {}'s, of {} photons (the photons line counts "
                     "every one traced); the outputs are valid\n", p.interrupted ? "INTERRUPTED" : "STOPPED",
                     p.interrupted ? "Ctrl-C" : "the estimate's deadline", p.rounds.size() + 1, p.rounds.size(),
                     p.rounds.back().photons);
  else if (p.interrupted)
    s += "  INTERRUPTED: Ctrl-C stopped the tracing early; the outputs are valid, with fewer photons\n";
  if (!p.savedTo.empty()) s += fmt::format("  photons   saved to {} (add more with --resume)\n", p.savedTo);
  return s;
}

nlohmann::json TraceJson(const TraceStats& t, uint64_t storedHits) {
  return {{"emitted", t.emitted},
          {"hits_stored", t.hits},
          {"hits_binned_while_traced", t.hits - storedHits},
          {"absorbed", t.absorbed},
          {"escaped", t.escaped},
          {"forbidden", t.forbidden},
          {"truncated", t.truncated},
          {"events", {{"diffuse", t.diffuseBounces}, {"mirror", t.mirrorReflections},
                      {"fresnel_reflection", t.fresnelReflections}, {"refraction", t.refractions},
                      {"caustic_hits", t.causticHits}}},
          {"record_bytes", sizeof(PhotonHit)},
          {"store_bytes", storedHits * sizeof(PhotonHit)},
          {"power_emitted_W", Json(t.fluxEmitted)},
          {"power_absorbed_W", Json(t.fluxAbsorbed)},
          {"power_escaped_W", Json(t.fluxEscaped)},
          {"power_forbidden_W", Json(t.fluxForbidden)}};
}

// What --h auto chose (the default without --h): the range of the surfaces' h and its area-weighted median.
std::string AutomaticBandwidthLine(const std::vector<SurfaceReport>& surfaces) {
  std::vector<double> h, area;  // of the surfaces with photons
  for (const SurfaceReport& sr : surfaces)
    if (sr.frontHits > 0) h.push_back(sr.bandwidth), area.push_back(sr.area);
  if (h.empty()) return "";
  return fmt::format("  h         per surface from its photons (--h auto): {:.3g} to {:.3g} m, area-weighted median "
                     "{:.3g} m\n", *std::min_element(h.begin(), h.end()), *std::max_element(h.begin(), h.end()),
                     WeightedPercentile(h, area, 0.5));
}

// The chart counts, then one row per surface, up to kRows rows.
std::string SurfaceTable(const BakeReport& r) {
  constexpr size_t kRows = 40;
  const std::vector<SurfaceReport>& surfaces = r.surfaces;
  std::string s = fmt::format("  charts    {} planar, {} curved (LSCM), worst area distortion {:.3f}\n",
                              surfaces.size() - r.curvedCharts, r.curvedCharts, r.worstAreaDistortion);
  double covered = 0;
  size_t coveredSurfaces = 0;
  for (const SurfaceReport& sr : surfaces)
    if (sr.coveredArea > 0) covered += sr.coveredArea, ++coveredSurfaces;
  s += fmt::format("  covered   {:.4g} m^2 of {} surfaces lies under or inside other geometry: a domain of its own\n",
                   covered, coveredSurfaces);
  s += fmt::format("  {:>4}  {:<22} {:<14} {:>9} {:>11} {:>9} {:>12} {:>7} {:>6} {:>7}\n", "surf", "object", "material",
                   "area m^2", "front hits", "back hits", "mean H W/m^2", "h m", "chart", "error");
  for (size_t i = 0; i < surfaces.size() && i < kRows; ++i) {
    const SurfaceReport& sr = surfaces[i];
    s += fmt::format("  {:>4}  {:<22} {:<14} {:>9.4f} {:>11} {:>9} {:>12.4g} {:>7.4f} {:>6} {:>6.2f}%\n", i, sr.object,
                     sr.material, sr.area, sr.frontHits, sr.backHits, Luminance(sr.meanIrradiance), sr.bandwidth,
                     sr.planar ? "plane" : fmt::format("{:.2f}", sr.areaDistortion), 100 * sr.predicted.Total());
  }
  if (surfaces.size() > kRows) s += fmt::format("  ... {} more surfaces in --report\n", surfaces.size() - kRows);
  return s;
}

std::string RefineLine(const BakeReport& r) {
  const RefineReport& m = r.refine;
  return fmt::format("  refine    {} -> {} vertices ({} collapses, {} cuts; {} refused by the budget, {} by the "
                     "minimum edge), {:.3f} s\n"
                     "  error     displayed luminance: max {:.4f}, 99% of the area {:.4f}, mean {:.4f}; {:.2f}% of the "
                     "area above the tolerance {:.4g}\n",
                     m.verticesBefore, m.verticesAfter, m.collapses, m.splits, m.refusedByBudget,
                     m.refusedByEdgeLength, StageSeconds(r, "refine"), m.maxError, m.p99Error, m.meanError,
                     100 * m.areaAboveTolerance, r.options.refine.tolerance);
}

nlohmann::json RefineJson(const BakeReport& r) {
  const RefineReport& m = r.refine;
  return {{"vertices_before", m.verticesBefore}, {"vertices_after", m.verticesAfter}, {"faces_before", m.facesBefore},
          {"faces_after", m.facesAfter}, {"collapses", m.collapses}, {"splits", m.splits},
          {"refused_by_budget", m.refusedByBudget}, {"collapses_past_tolerance", m.collapsesPastTolerance}, {"refused_by_minimum_edge", m.refusedByEdgeLength},
          {"detached_faces", m.detachedFaces}, {"max_error", m.maxError}, {"mean_error", m.meanError},
          {"p99_error", m.p99Error}, {"area_fraction_above_tolerance", m.areaAboveTolerance},
          {"error_unit", "displayed luminance, fraction of the display range"},
          {"tolerance", r.options.refine.tolerance}, {"seconds", StageSeconds(r, "refine")}};
}

}  // namespace

double BakeReport::TotalSeconds() const {
  double total = 0;
  for (const auto& [name, seconds] : stageSeconds) total += seconds;
  return total;
}

namespace {

std::vector<LightReport> DescribeLights(const Scene& scene, const std::vector<Light>& lights,
                                        const std::vector<uint64_t>& photonsPerLight, const TransportPlan& plan) {
  std::vector<LightReport> out;
  for (size_t l = 0; l < lights.size(); ++l) {
    const std::string name = LightName(scene, lights[l]);
    out.push_back({lights[l].surface, name, LightKindName(lights[l].kind), lights[l].area, lights[l].Power(),
                   photonsPerLight[l], plan.lightNotes[l]});
  }
  return out;
}

// Each surface's written H averaged over its faces by area [W/m^2] (each face by the mean of its corners).
std::vector<Rgb> MeanIrradiance(const BakedMesh& baked, size_t surfaces) {
  std::vector<RgbSum> weighted(surfaces);
  std::vector<double> area(surfaces, 0.0);
  const SplitMesh& mesh = baked.mesh;
  for (const auto& [a, b, c] : mesh.faces) {
    const uint32_t s = mesh.surface[a];
    const double faceArea = 0.5 * Length(Cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]));
    weighted[s].Add(baked.irradiance[a] + baked.irradiance[b] + baked.irradiance[c], faceArea / 3);
    area[s] += faceArea;
  }
  std::vector<Rgb> mean(surfaces);
  for (size_t s = 0; s < surfaces; ++s)
    if (area[s] > 0) mean[s] = {float(weighted[s].r / area[s]), float(weighted[s].g / area[s]), float(weighted[s].b / area[s])};
  return mean;
}

std::vector<SurfaceReport> DescribeSurfaces(const Scene& scene, const SurfaceSet& surfaces, const SurfaceBins& bins,
                                            const IrradianceField& field, const BakedMesh& baked) {
  std::vector<SurfaceReport> out;
  const std::vector<Rgb> mean = MeanIrradiance(baked, surfaces.surfaces.size());
  const std::vector<BakeError> predicted = PredictedErrorPerSurface(baked, surfaces.surfaces.size());
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
    const Surface& surface = surfaces.surfaces[s];
    const std::string& object = scene.objectNames[scene.triangles[surface.triangles.front()].object];
    out.push_back({object, scene.materials[surface.material].name, surface.area, bins.FrontHits(s), bins.BackHits(s),
                   mean[s], bins.FrontFlux(s) / float(surface.area), surface.planar, surface.areaDistortion,
                   field.Bandwidth(s), field.Prepared().covers[s].Area(), predicted[s]});
  }
  return out;
}

BakeReport::NarrowGaps DescribeNarrowGaps(const std::vector<GapWeight>& weights) {
  BakeReport::NarrowGaps g;
  double weighted = 0;
  for (const GapWeight& w : weights) {
    if (w.vertices == 0) continue;
    g.vertices += w.vertices, ++g.surfaces, weighted += w.alpha * w.vertices;
  }
  if (g.vertices > 0) g.meanWeight = weighted / double(g.vertices);
  return g;
}

BakeReport::Pooled DescribePooled(const PreparedScene& p, const PhotonIrradiance& photons, const BakedMesh& mesh) {
  BakeReport::Pooled pooled;
  for (uint32_t s = 0; s < p.surfaces.surfaces.size(); ++s)
    if (photons.Pooled(s)) ++pooled.surfaces, pooled.area += p.surfaces.surfaces[s].area;
  if (pooled.surfaces == 0) return pooled;
  pooled.photons = photons.PooledPhotons();
  pooled.reach = photons.PooledRadius();
  double all = 0, theirs = 0;
  for (size_t v = 0; v < mesh.mesh.VertexCount(); ++v) {
    const double h = Luminance(mesh.irradiance[v]);
    all += h;
    if (!photons.Pooled(mesh.mesh.surface[v])) continue;
    // The photons' part: what the shadow rays and the gathered paths did not bring (all of it when not known).
    const double sampled = v < mesh.sampledShare.size() ? mesh.sampledShare[v] : 0.0;
    ++pooled.vertices, theirs += h * (1 - sampled);
  }
  pooled.lightShare = all > 0 ? theirs / all : 0.0;
  return pooled;
}

}  // namespace

BakeReport DescribeBake(const BakeResults& r) {
  const PreparedScene& p = r.scene;
  BakeReport report{r.options, r.threads};
  report.triangles = p.scene.triangles.size();
  report.degenerateTrianglesSkipped = p.scene.degenerateTrianglesSkipped;
  report.duplicateTrianglesSkipped = p.scene.duplicateTrianglesSkipped;
  report.vertices = r.mesh.mesh.VertexCount();
  report.faces = r.mesh.mesh.faces.size();
  report.curvedCharts = p.surfaces.CurvedCount();
  report.worstAreaDistortion = p.surfaces.WorstAreaDistortion();
  report.lights = DescribeLights(p.scene, p.lights, r.photons.emitted, p.plan);
  report.surfaces = DescribeSurfaces(p.scene, p.surfaces, r.bins, r.field, r.mesh);
  report.trace = r.photons.stats;
  report.storedHits = r.photons.StoredHits();
  report.stageSeconds = r.stageSeconds;
  report.plan = p.plan;
  report.warnings = r.warnings;
  report.exposure = r.exposure;
  report.maps = r.maps;
  report.refine = r.refine;
  report.progressive = r.progressive;
  report.noise = r.noise;
  report.error = r.error;
  report.noiseParts = r.noiseParts;
  report.narrowGaps = DescribeNarrowGaps(r.field.GapWeights());
  report.pooled = DescribePooled(p, r.field.Photons(), r.mesh);
  report.directionNoise = BakeDirectionNoise(r.mesh);
  return report;
}

namespace {

// "  gaps      ...", or "" where no vertex's gathered light was weighed.
std::string NarrowGapsLine(const BakeReport::NarrowGaps& g) {
  if (g.vertices == 0) return "";
  return fmt::format("  gaps      {} vertices gathered in narrow gaps or on surfaces smaller than their kernel, on {} "
                     "surface{}, their gathered light weighed against the photons': mean weight {:.3f} (1: the gathered "
                     "light alone)\n", g.vertices, g.surfaces,
                     g.surfaces == 1 ? "" : "s", g.meanWeight);
}

// "  pooled    ...", or "" where no surface is pooled.
std::string PooledLine(const BakeReport::Pooled& p) {
  if (p.surfaces == 0) return "";
  return fmt::format("  pooled    {} surface{} ({:.4g} m^2) with fewer than {} photons each, read from the {} photons "
                     "pooled across them, near each point and turned its way: on their {} vertices the pooled photons "
                     "bring {:.3g}% of the bake's light, each the light averaged over up to {:.3g} m about it, a "
                     "smoothing the predicted bias does not count\n", p.surfaces, p.surfaces == 1 ? "" : "s", p.area, kPooledBelowHits, p.photons,
                     p.vertices, 100 * p.lightShare, p.reach);
}

// "; alone: photons 2.10%, shadow rays 8.40%, gathered paths 60.30%", the sources that contribute; "" with one.
std::string NoisePartsText(const BakeReport& r) {
  const NoiseParts& p = r.noiseParts;
  std::vector<std::string> parts;
  if (p.photons > 0) parts.push_back(fmt::format("photons {:.2f}%", 100 * p.photons));
  if (p.points > 0) parts.push_back(fmt::format("{} {:.2f}%", r.options.referencePaths > 0 ? "paths" : "shadow rays", 100 * p.points));
  if (p.gathered > 0) parts.push_back(fmt::format("gathered paths {:.2f}%", 100 * p.gathered));
  return parts.size() > 1 ? fmt::format("; alone: {}", fmt::join(parts, ", ")) : "";
}

// Where the error sits, when the bake's figure hides it: up to three surfaces of at least kWhereShare of the scene's
// area whose own predicted error (relative to their own mean H) passes twice the bake's, largest first; "" when none
// does. A dim room behind a door (1% of the lit room's light) reads tens of percent on its own where the lit room
// sets the bake's 1.4%. Surfaces below kWhereDark of the scene's mean H (by area) show black at the bake's exposure
// whatever their error, and are left out: the staircase's 15 m^2 of unlit paint read 199% of 0.0002 W/m^2.
std::string WhereLine(const BakeReport& r) {
  constexpr double kWhereShare = 0.01, kWhereDark = 1e-3;
  constexpr size_t kWhereRows = 3;
  double area = 0, light = 0;
  for (const SurfaceReport& sr : r.surfaces) area += sr.area, light += sr.area * Luminance(sr.meanIrradiance);
  const double dark = area > 0 ? kWhereDark * light / area : 0;
  std::vector<size_t> worse;
  for (size_t i = 0; i < r.surfaces.size(); ++i) {
    const SurfaceReport& sr = r.surfaces[i];
    if (sr.area >= kWhereShare * area && Luminance(sr.meanIrradiance) >= dark && sr.predicted.Total() > 2 * r.error.Total())
      worse.push_back(i);
  }
  if (worse.empty()) return "";
  std::stable_sort(worse.begin(), worse.end(), [&](size_t a, size_t b) {
    return r.surfaces[a].predicted.Total() > r.surfaces[b].predicted.Total();
  });
  std::vector<std::string> named;
  for (size_t k = 0; k < worse.size() && k < kWhereRows; ++k) {
    const SurfaceReport& sr = r.surfaces[worse[k]];
    named.push_back(fmt::format("surface {} ({} {}, {:.3g} m^2, mean H {:.3g} W/m^2) {:.1f}%", worse[k], sr.object,
                                sr.material, sr.area, Luminance(sr.meanIrradiance), 100 * sr.predicted.Total()));
  }
  return fmt::format("  where     {} of the surfaces of 1% of the area or more read over twice the bake's error on their "
                     "own (relative to their own mean H): {}\n", worse.size(), fmt::join(named, "; "));
}

}  // namespace

void PrintSummary(const BakeReport& r, const Log& log) {
  if (log.Quiet()) return;
  const TraceStats& t = r.trace;
  std::string s = fmt::format("\nphotonbake summary: {} -> {}\n", r.options.scenePath, r.options.outputPath);
  s += fmt::format("  scene     {} triangles ({} zero-area and {} duplicates skipped), {} surfaces, {} lights\n",
                   r.triangles, r.degenerateTrianglesSkipped, r.duplicateTrianglesSkipped, r.surfaces.size(),
                   r.lights.size());
  constexpr size_t kLightRows = 40;
  for (size_t i = 0; i < r.lights.size() && i < kLightRows; ++i) {
    const LightReport& l = r.lights[i];
    s += fmt::format("  light     {:<20} {}  Phi {} W  {} photons{}\n", l.material,
                     l.kind == "area" ? fmt::format("area {:.4g} m^2", l.area) : l.kind, Text(l.power), l.photons,
                     l.note.empty() ? "" : "  (" + l.note + ")");
  }
  if (r.lights.size() > kLightRows) s += fmt::format("  ... {} more lights in --report\n", r.lights.size() - kLightRows);
  s += fmt::format("  photons   {} emitted, {} hits stored, {} absorbed, {} escaped, {} forbidden, {} truncated\n",
                   t.emitted, t.hits, t.absorbed, t.escaped, t.forbidden, t.truncated);
  s += fmt::format("  events    {} diffuse, {} mirror, {} Fresnel reflections, {} refractions; {} caustic hits\n",
                   t.diffuseBounces, t.mirrorReflections, t.fresnelReflections, t.refractions, t.causticHits);
  s += fmt::format("  store     {} B per hit, {:.1f} MiB{}\n", sizeof(PhotonHit), r.storedHits * sizeof(PhotonHit) / 1048576.0,
                   r.storedHits < t.hits ? fmt::format("; {} hits binned while traced, not stored", t.hits - r.storedHits) : "");
  const double out = t.fluxAbsorbed.Mean() + t.fluxEscaped.Mean() + t.fluxForbidden.Mean();
  const double balance = t.fluxEmitted.Mean() > 0 ? out / t.fluxEmitted.Mean() - 1.0 : 0.0;
  s += fmt::format("  flux      emitted {:.5g} W = absorbed {:.5g} W + escaped {:.5g} W + forbidden {:.5g} W"
                   "  (balance {:+.3f}%)\n", t.fluxEmitted.Mean(), t.fluxAbsorbed.Mean(), t.fluxEscaped.Mean(),
                   t.fluxForbidden.Mean(), 100.0 * balance);
  s += ProgressiveLines(r.progressive, t.emitted);
  if (!r.options.estimator.bandwidth) s += AutomaticBandwidthLine(r.surfaces);
  s += fmt::format("  noise     {:.2f}% predicted (95th percentile over the vertices, by luminance x area, of the "
                   "displayed light's relative standard error; smoothing bias not included){}\n", 100 * r.noise,
                   NoisePartsText(r));
  s += NarrowGapsLine(r.narrowGaps);
  s += PooledLine(r.pooled);
  s += fmt::format("  error     {:.2f}% predicted (the RMS of H's error over the vertices, relative to their mean H): "
                   "noise {:.2f}%, smoothing bias {:.2f}%{}\n", 100 * r.error.Total(), 100 * r.error.noise,
                   100 * r.error.bias, r.pooled.lightShare > 1e-3 ? " (the pooled surfaces' not counted)" : "");
  s += WhereLine(r);
  if (r.options.sh)
    s += fmt::format("  directions  {:.2f} degrees predicted (95th percentile, as the noise, of the standard error of "
                     "the direction of each vertex's L1)\n", r.directionNoise * 180 / kPi);
  s += SurfaceTable(r);
  s += "  seconds  ";
  for (const auto& [name, seconds] : r.stageSeconds) s += fmt::format(" {} {:.3f} |", name, seconds);
  s += fmt::format(" total {:.3f} ({} threads)\n", r.TotalSeconds(), r.threads);
  for (Effect e : kAllEffects) s += fmt::format("  effect    {}: {}\n", EffectName(e), r.plan.Describe(e));
  s += fmt::format("  output    {}: {} vertices, {} triangles, display exposure {:.4g}\n", r.options.outputPath,
                   r.vertices, r.faces, r.exposure);
  if (r.refine.ran) s += RefineLine(r);
  if (!r.maps.paths.empty())
    s += fmt::format("  maps      {} irradiance maps (EXR, W/m^2), {} texels of {} m, in {}\n", r.maps.paths.size(),
                     r.maps.texels, r.options.texel, r.options.mapsDirectory);
  log.Info(s);
}

namespace {

// The indices of the `listed` entries of `items` that `larger` ranks first (ties by index), in index order; all
// of them when `all` or when there are no more.
template <typename T, typename Larger>
std::vector<size_t> Listed(const std::vector<T>& items, bool all, Larger larger) {
  std::vector<size_t> order(items.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  if (all || items.size() <= kListed) return order;
  std::partial_sort(order.begin(), order.begin() + kListed, order.end(), [&](size_t a, size_t b) {
    return larger(items[a], items[b]) || (!larger(items[b], items[a]) && a < b);
  });
  order.resize(kListed);
  std::sort(order.begin(), order.end());
  return order;
}

nlohmann::json SurfacesSummary(const std::vector<SurfaceReport>& surfaces, size_t listed) {
  double area = 0;
  uint64_t front = 0, back = 0;
  for (const SurfaceReport& s : surfaces) area += s.area, front += s.frontHits, back += s.backHits;
  return {{"count", surfaces.size()}, {"listed", listed}, {"area_m2", area}, {"front_hits", front}, {"back_hits", back}};
}

nlohmann::json LightsSummary(const std::vector<LightReport>& lights, size_t listed) {
  RgbSum power, dark;
  uint64_t photons = 0, without = 0;
  for (const LightReport& l : lights) {
    power.Add(l.power), photons += l.photons;
    if (l.photons == 0) dark.Add(l.power), ++without;
  }
  return {{"count", lights.size()}, {"listed", listed}, {"power_W", Json(power.ToRgb())}, {"photons", photons},
          {"without_photons", without}, {"without_photons_power_W", Json(dark.ToRgb())}};
}

}  // namespace

void WriteReportJson(OutputFiles& outputs, const std::string& path, const BakeReport& r) {
  nlohmann::json j;
  j["options"] = OptionsJson(r.options);
  j["threads"] = r.threads;
  j["scene"] = {{"triangles", r.triangles},
                {"zero_area_triangles_skipped", r.degenerateTrianglesSkipped},
                {"duplicate_triangles_skipped", r.duplicateTrianglesSkipped},
                {"surfaces", r.surfaces.size()},
                {"curved_charts", r.curvedCharts},
                {"worst_area_distortion", r.worstAreaDistortion}};
  const std::vector<size_t> lights =
      Listed(r.lights, r.options.reportAll, [](const LightReport& a, const LightReport& b) { return a.power.Mean() > b.power.Mean(); });
  j["lights"] = nlohmann::json::array();
  for (size_t i : lights) {
    const LightReport& l = r.lights[i];
    j["lights"].push_back({{"light", i}, {"kind", l.kind}, {"surface", l.surface == kNoSurface ? nlohmann::json() : nlohmann::json(l.surface)},
                           {"material", l.material}, {"area_m2", l.area},
                           {"power_W", Json(l.power)}, {"photons", l.photons}, {"note", l.note}});
  }
  j["lights_summary"] = LightsSummary(r.lights, lights.size());
  j["photons"] = TraceJson(r.trace, r.storedHits);
  j["progressive"] = ProgressiveJson(r.progressive);
  j["noise"] = r.noise;
  j["predicted_error"] = {{"total", r.error.Total()}, {"noise", r.error.noise}, {"bias", r.error.bias}};
  j["noise_parts"] = {{"photons", r.noiseParts.photons}, {"points", r.noiseParts.points}, {"gathered", r.noiseParts.gathered}};
  j["narrow_gaps"] = {{"vertices", r.narrowGaps.vertices}, {"surfaces", r.narrowGaps.surfaces},
                      {"mean_weight", r.narrowGaps.meanWeight}};
  j["pooled"] = {{"surfaces", r.pooled.surfaces}, {"area_m2", r.pooled.area}, {"photons", r.pooled.photons},
                 {"vertices", r.pooled.vertices}, {"light_share", r.pooled.lightShare}, {"reach_m", r.pooled.reach}};
  if (r.options.sh) j["direction_noise_deg"] = r.directionNoise * 180 / kPi;
  const std::vector<size_t> surfaces =
      Listed(r.surfaces, r.options.reportAll, [](const SurfaceReport& a, const SurfaceReport& b) { return a.area > b.area; });
  j["surfaces"] = nlohmann::json::array();
  j["surfaces_summary"] = SurfacesSummary(r.surfaces, surfaces.size());
  for (size_t i : surfaces) {
    const SurfaceReport& s = r.surfaces[i];
    j["surfaces"].push_back({{"surface", i}, {"object", s.object}, {"material", s.material}, {"area_m2", s.area}, {"front_hits", s.frontHits},
                             {"back_hits", s.backHits}, {"mean_irradiance_W_m2", Json(s.meanIrradiance)},
                             {"photon_irradiance_W_m2", Json(s.photonIrradiance)},
                             {"chart", s.planar ? "planar" : "conformal"}, {"area_distortion", s.areaDistortion},
                             {"h_m", s.bandwidth}, {"covered_area_m2", s.coveredArea},
                             {"predicted_error", {{"total", s.predicted.Total()}, {"noise", s.predicted.noise},
                                                  {"smoothing_bias", s.predicted.bias}}}});
  }
  for (const auto& [name, seconds] : r.stageSeconds) j["seconds"][name] = seconds;
  j["seconds"]["total"] = r.TotalSeconds();
  for (Effect e : kAllEffects) {
    const EffectDecision& d = r.plan.effects[size_t(e)];
    j["effects"][EffectName(e)] = {{"simulated", d.simulated}, {"overridden", d.overridden}, {"reason", d.reason}};
  }
  j["effects"]["significant_diffuse_bounces"] = r.plan.significantBounces;
  j["output"] = {{"path", r.options.outputPath}, {"vertices", r.vertices}, {"faces", r.faces},
                 {"display_exposure", r.exposure}};
  if (r.refine.ran) j["refine"] = RefineJson(r);
  j["maps"] = {{"paths", r.maps.paths}, {"texels", r.maps.texels}, {"texel_m", r.options.texel}};
  j["warnings"] = r.warnings;
  WriteJsonFile(outputs, path, j);
}

}  // namespace pb
