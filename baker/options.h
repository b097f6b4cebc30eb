// Options of one bake, as the user gives them. Units: lengths in metres, counts dimensionless.
// Each field states its range and a typical value; tools/bake.cpp shows the same text in --help, and Validate()
// checks every range before any work is done (STYLE.md habit 14: validation beside the parameter's owner).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "baker/1_trace_settings.h"
#include "baker/3_direct_settings.h"
#include "baker/3_gap_settings.h"
#include "baker/4_refine_settings.h"
#include "estimators/estimator_settings.h"

namespace pb {

struct BakeOptions {
  std::string scenePath;   // OBJ file; its MTL files are found relative to it.
  std::string lightsPath;         // --lights: a lights file; empty: SCENE.lights.json where it exists
  double luminousEfficacy = 683;  // --luminous-efficacy [lm/W]: glTF's candela and lux to watts; [1, 683]
  std::string outputPath;  // PLY file, written atomically (temporary file, then rename).
  std::string reportPath;  // JSON report; empty for none.
  bool reportAll = false;  // --report-all: every surface and light in the JSON, not only the largest (report.h)
  // Estimator, kernel, h [m] (kernel support radius or bucket side; range (0, inf), typical 0.02-0.1 for a
  // room; none with --h auto: chosen per surface from its photons), k (knn) and edge correction.
  // estimators/density_estimator.h.
  EstimatorSettings estimator;
  // --effects: which transport to simulate; "auto" lets the scene decide (baker/0_plan_transport.h).
  std::string effectsText = "auto";
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

}  // namespace pb
