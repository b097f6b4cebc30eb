// Options of one bake, as the user gives them. Units: lengths in metres, counts dimensionless.
// Each field states its range and a typical value; tools/bake.cpp shows the same text in --help, and Validate()
// checks every range before any work is done (STYLE.md habit 14: validation beside the parameter's owner).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "baker/1_trace_photons.h"
#include "baker/3_contributions.h"
#include "baker/3_gap_gather.h"
#include "baker/4_refine_mesh.h"
#include "estimators/density_estimator.h"

namespace pb {

// --quality: a name for a target and the first round's photons (--photons): the predicted error of H
// (--target-error) for draft, high and production, the defaults' noise target (--target-noise) for medium. h is
// chosen per surface from the photons (--h auto) and the shadow rays and gathered paths by the rounds, so a preset
// suits a scene of any size; options given explicitly win (docs/bake.md, "Quality presets", has what each reaches
// on the box and the office).
//   draft       error 8%, first round   160,000 photons, 32 shadow rays and 32 gathered paths a point
//   medium      noise 3%, first round 1,000,000 photons (the defaults)
//   high        error 3%, first round 2,000,000 photons
//   production  error 2%, first round 2,000,000 photons, and the edges gathered (--gap-edges, 1,024 paths to start)
struct QualityPreset {
  float target;       // --target-noise, or with `error` --target-error (baker/photons/progressive.h)
  uint64_t photons;   // the first round's, over all lights
  bool error = false;  // the target is the predicted error of H, not the noise's 95th percentile
  bool gatherEdges = false;  // --gap-edges (baker/3_gap_gather.h)
  // The first round's --direct-samples and --gap-paths per point; 0: the defaults' (DirectSettings, GapSettings).
  uint32_t shadowRays = 0, gapPaths = 0;
};
// "draft", "medium", "high" or "production"; nullopt for any other name.
std::optional<QualityPreset> ParseQuality(std::string_view name);
std::string QualityNames();  // comma-separated, for --help and error messages

struct BakeOptions {
  std::string scenePath;   // OBJ file; its MTL files are found relative to it.
  std::string lightsPath;         // --lights: a lights file; empty: SCENE.lights.json where it exists
  double luminousEfficacy = 683;  // --luminous-efficacy [lm/W]: glTF's candela and lux to watts; [1, 683]
  std::string outputPath;  // PLY file, written atomically (temporary file, then rename).
  std::string reportPath;  // JSON report; empty for none.
  bool reportAll = false;  // --report-all: every surface and light in the JSON, not only the largest (report.h)
  // Estimator, kernel, h [m] (kernel support radius or bucket side; range (0, inf), typical 0.02-0.1 for a
  // room), k (knn) and edge correction. estimators/density_estimator.h.
  EstimatorSettings estimator;
  bool autoBandwidth = false;
  // --effects: which transport to simulate; "auto" lets the scene decide (baker/0_plan_transport.h).
  std::string effectsText = "auto";  // --h auto: h chosen per surface from its photons (estimators/bandwidth.h)
  uint64_t photons = 1'000'000;   // photons emitted over all lights; range [1, 2^40], typical 1e6-1e7.
  uint64_t seed = 1;              // any value; the same seed gives the same bytes for any thread count.
  unsigned threads = 0;           // worker threads; 0 = all cores.
  float scale = 1.0f;             // metres per scene unit; (0, inf), typical 1 or 0.001 (millimetres).
  bool asciiPly = false;          // ASCII instead of binary little-endian PLY.
  std::optional<float> exposure;  // display exposure multiplier on radiance; unset = automatic.
  // --max-bounces: scattering events a photon may undergo after its first hit; 0 = direct light only; range
  // [0, 10000]; the default, 10000, is unlimited in practice (Russian roulette ends paths; baker/1_trace_photons.h).
  uint32_t maxBounces = kDefaultMaxBounces;
  DirectSettings direct;          // --direct, --direct-samples
  GapSettings gaps;               // --gap-paths (baker/3_gap_gather.h)
  // --reference: instead of tracing photons, gather this many paths at every point (a path tracer's vertex bake,
  // unbiased: estimators/irradiance_gather.h); 0 = off; range [0, 1e7], typical 1024-16384.
  uint32_t referencePaths = 0;
  // --guide-photons: photons for importance maps that guide the first direction of --reference's and the gap
  // gather's paths (estimators/irradiance_gather.h); 0 = off; range [0, 1e9], typical 250000.
  uint64_t guidePhotons = 0;
  bool quiet = false;             // no progress or summary on stderr.
  // --no-cover: do not find the parts of surfaces that other geometry covers (estimators/surface_cover.h); they
  // are found on a lattice of spacing h / 2 (the default h's with --h auto).
  bool findCovers = true;
  // --only: comma-separated globs of object or material names (mesh/split_mesh.h, SurfacesNamed); only their
  // surfaces are estimated and written, the light still traced through the whole scene. Empty: every surface.
  std::string only;
  std::string mapsDirectory;      // --maps: one irradiance map (EXR) per surface here; empty for none.
  // --sh: each vertex also carries where its light comes from, the L1 spherical harmonics of its incident radiance
  // per colour (estimators/incident_moments.h); the photons are then stored with their directions.
  bool sh = false;
  // --preview: a PNG of the baked mesh as a viewer shows it (baker/5_write_preview.h); empty for none. Seen from
  // --camera, or the scene's sidecar SCENE.camera.json; --preview-size pixels, each in [1, 8192].
  std::string previewPath;
  std::string cameraPath;
  int previewWidth = 640, previewHeight = 480;
  float texel = 0.02f;            // --texel: map texel side [m]; range (0, inf), typical 0.005-0.05.
  RefineSettings refine;          // --refine, --tolerance, --max-vertices, --subdivide (baker/4_refine_mesh.h)
  // Progressive bakes (baker/photons/progressive.h).
  std::string resumePath;         // --resume: continue the photon store in this file (same scene, seed, options).
  std::string savePhotonsPath;    // --save-photons: write the photon store here; may equal resumePath.
  std::optional<float> targetNoise;  // --target-noise: trace in rounds until the noise is at most this; (0, 1).
  // --target-error: trace in rounds until the predicted error of H (noise and smoothing bias, in the accuracy
  // tool's measure; baker/photons/progressive.h, PredictedError) is at most this; (0, 1). Not with --target-noise.
  std::optional<float> targetError;
  bool Rounds() const { return targetNoise || targetError; }  // traced in rounds to a target
  uint64_t maxPhotons = 100'000'000;  // --max-photons: --target-noise's budget over all lights.
  // --max-seconds: --target-noise's time budget [s]: no round starts that is expected to end after this much of the
  // bake's wall time; range [1, 1e7]. The one setting whose outcome depends on the machine (the summary gives the
  // options that repeat the bake's bytes).
  double maxSeconds = 60;
  uint32_t maxRounds = 0;  // --max-rounds: --target-noise's rounds at most; 0: no limit. Repeats a bake on any machine.

  // InputError naming the option when any value lies outside its range (or --effects does not parse).
  void Validate() const;
};

// The noise the defaults aim at: the 95th percentile of the displayed light's predicted relative error at 3%
// (baker/photons/progressive.h; docs/bake.md, "Defaults that suit the scene").
constexpr float kDefaultTargetNoise = 0.03f;
// The defaults gather on surfaces smaller than 6 h^2 (--gap-small-area), the smallest first, while they hold at
// most a tenth of the triangles (GapSettings::smallShare; docs/bake.md, "Narrow gaps").
constexpr float kDefaultSmallArea = 6, kDefaultSmallShare = 0.1f;

// Which of the options that the defaults choose were given on the command line (or, for photons, by --quality).
struct GivenOptions {
  bool bandwidth = false;   // --h
  bool photons = false;     // --photons
  bool shadowRays = false;  // --direct-samples or --direct-noise
  bool gapPaths = false;    // --gap-paths
  bool smallArea = false;   // --gap-small-area
};
// The first round's photons for --target-error `target`, from a first round of `photons` that suits target `at`:
// photons (at / target)^2, within [250,000, 32,000,000]. h is chosen from the first round and held, so a first
// round sized for the target gives the h that suits about the photons the target needs (the box at 1%: 1.24% net
// from 2M photons, 0.91% from 8M, in about the same time; docs/bake.md, "Target error").
uint64_t FirstRoundForError(float target, uint64_t photons, float at);
// The first round of --target-error, sized for it from a first round of `photons` photons, o's shadow rays and o's
// gathered paths that suits target `at`, for what was not given: the photons by FirstRoundForError, the shadow
// rays by (at / target)^(1 / LightSampler::kStratifiedOrder) (their noise falls as S^-0.75; a square, within
// [16, 4,096]) and the paths by (at / target)^2 (within [16, 65,536]), so that a round can meet the target on its
// own: the box at --quality production --target-error 0.01 reads 0.97% net in one round of 676 rays and 4,096
// paths in 4.7 s, where raising them in a second round took 6.3 s.
void SizeFirstRoundForError(BakeOptions& o, const GivenOptions& given, uint64_t photons, float at);
// `bake`'s defaults that suit the scene, for what was not given: h chosen per surface from its photons (--h auto),
// and photons and shadow rays raised in rounds to kDefaultTargetNoise within --max-seconds (--target-noise), or,
// with --target-error, from a first round sized for it (SizeFirstRoundForError, from the defaults' first round at 3%). The
// kernel and histogram estimators only (knn has no h, and its noise is set by k); not with --reference (no
// photons) or --resume (which continues to --photons).
void ApplySceneDefaults(BakeOptions& o, const GivenOptions& given);
// bake's and bake-mpi's gathering on the smallest surfaces (kDefaultSmallArea, kDefaultSmallShare) unless
// --gap-small-area is given (which then gathers on every surface it names small); not with knn, which has no h.
void ApplyGapDefaults(BakeOptions& o, const GivenOptions& given);
// --quality NAME, for what was not given: its target (unless --target-noise is given, or the bake has no rounds:
// --reference, knn), its first round's photons, shadow rays and gathered paths (for a --target-error given in
// place of an error preset's, SizeFirstRoundForError from the preset's) and its gathered edges. Before
// ApplySceneDefaults, whose `given.photons` it then implies. An InputError naming --quality for an unknown name.
void ApplyQuality(std::string_view name, const GivenOptions& given, BakeOptions& o);
// All that bake's (and bake-mpi's) command line applies for what was not given, in order: --quality `quality`
// (when not empty), the scene's defaults and the gathering's.
void ApplyDefaults(BakeOptions& o, GivenOptions given, std::string_view quality);

}  // namespace pb
