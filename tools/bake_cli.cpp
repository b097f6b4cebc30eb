#include "tools/bake_cli.h"

#include <fmt/core.h>

#include <cstdio>
#include <optional>
#include <string>
#include <string_view>

#include "baker/runtime/interrupt.h"
#include "baker/0_effects.h"
#include "baker/bake_run.h"
#include "estimators/enum_names.h"
#include "mesh/errors.h"
#include "tools/cli_options.h"

namespace pb::tools {
namespace {


void DefineEstimatorOptions(CLI::App& app, pb::EstimatorSettings& e) {
  pb::tools::AddNamedOption(app, "--estimator", e.kind, pb::ParseEstimator, pb::EstimatorName, pb::EstimatorNames(), "estimator",
                 "density estimator (the paper's three classes)");
  pb::tools::AddNamedOption(app, "--kernel", e.kernel, pb::ParseKernel, pb::KernelName, pb::KernelNames(), "kernel",
                 "kernel of --estimator kernel");
  app.add_option_function<std::string>(
         "--h",
         [&e](const std::string& text) {
           if (text == "auto") e.bandwidth.reset();
           else e.bandwidth = float(pb::tools::ParseNumber(text));
         },
         "bandwidth h [m]: kernel support radius, or histogram bucket side, in the surface; range 1e-6 to 1e4, typical "
         "0.02-0.1 for a room-sized scene; or 'auto': chosen per surface from its photons (docs/conventions.md, 'Automatic h'), "
         "the default where the scene chooses (docs/bake.md, 'Defaults that suit the scene')")
      ->check(CLI::Validator(
          [](const std::string& text) {
            float value = 0;
            return text == "auto" || CLI::detail::lexical_cast(text, value) ? std::string()
                                                                            : "expects a length in metres or 'auto'";
          },
          "FLOAT|auto", "length"))
      ->default_str("auto");
  app.add_option("--k", e.neighbours, "photons per estimate of --estimator knn; range 2-1e6, typical 20-200")
      ->capture_default_str();
  app.add_flag("!--renormalise-edges", e.localLinear,
               "kernel estimator: at surface edges and contact lines, only renormalise by the kernel's mass there, "
               "instead of fitting the light locally linear (Walter et al. 1997); less noise at edges, but the "
               "gradient bias stays");
  app.add_flag("!--no-edge-correction", e.edgeCorrection, "do not renormalise estimates by the part of the kernel, "
                                                         "bucket or disc that lies on the surface (edges darken)");
}

void DefineSceneOptions(CLI::App& app, pb::BakeOptions& o) {
  app.option_defaults()->group("Scene");
  app.add_option("scene", o.scenePath, "OBJ scene (with MTL) or glTF 2.0 (.gltf, .glb). Kd = diffuse albedo in [0,1]; Ke = emitted radiance "
                                       "[W/(m^2 sr)], one-sided along the counter-clockwise normal")
      ->required();
  app.add_option("-o,--output", o.outputPath, "PLY to write (binary little-endian unless --ascii), or glTF 2.0 when it ends in .glb or .gltf; written to a "
                                              "temporary file and renamed into place")
      ->required();
  app.add_option("--lights", o.lightsPath, "lights file: point (plain or by an IES profile), spot, sun and sky lights (JSON; docs/bake.md, \"Lights that are not surfaces\"); "
                                          "default SCENE.lights.json where it exists");
  app.add_option("--luminous-efficacy", o.luminousEfficacy, "lm/W that turn glTF's candela and lux into watts; "
                                                          "range [1, 683], default 683");
  app.add_option("--scale", o.scale, "metres per scene unit; range 1e-6 to 1e6, typical 1, or 0.001 for millimetres")
      ->capture_default_str();
}

void DefinePhotonOptions(CLI::App& app, pb::BakeOptions& o) {
  app.option_defaults()->group("Photons");
  app.add_option("--photons", o.photons,
                 fmt::format("photons emitted over all lights, split by power (N_i = n Phi_i / Phi); range 1 to 2^40, "
                             "typical 1e6-1e7; default: rounds from {} until the noise is {:g}% (--target-noise {:g}), "
                             "within --max-seconds",
                             o.photons, 100 * pb::kDefaultTargetNoise, pb::kDefaultTargetNoise))
      ->default_str("auto");
  pb::tools::AddSeedOption(app, o.seed, "random seed, 0 to 2^64 - 1. Same seed, same bytes, for any --threads");
  app.add_option("--effects", o.effectsText,
                 "light transport to simulate: 'auto' (what the scene's materials call for), 'all', or a list such as "
                 "'+caustics,-refraction' (NAME or +NAME forces on, -NAME forbids); names: " +
                     pb::JoinNames(pb::kAllEffects, pb::EffectName))
      ->check(CLI::Validator(
          [](const std::string& text) {
            try {
              pb::ParseEffectOverrides(text);
              return std::string();
            } catch (const pb::InputError& e) {
              return e.message();
            }
          },
          "EFFECTS", "effects"))
      ->capture_default_str();
  app.add_option("--max-bounces", o.maxBounces,
                 "scattering events a photon may undergo after its first hit; 0 = direct light only; range 0-10000; "
                 "the default is unlimited in practice (Russian roulette ends paths)")
      ->capture_default_str();
}

void DefineRoundOptions(CLI::App& app, pb::BakeOptions& o) {
  app.option_defaults()->group("Rounds and photon files");
  app.add_option("--target-noise", o.targetNoise,
                 "trace in rounds, the first of --photons, until the 95th percentile of the vertices' relative noise "
                 "(luminance- and area-weighted) is at most this; range (0, 1), typical 0.01-0.05");
  app.add_option("--target-error", o.targetError,
                 "trace in rounds until the predicted error of H (the RMS over the vertices of its noise and "
                 "smoothing bias, relative to their mean H) is at most this, the first of --photons, or without it "
                 "of 1e6 x (0.03 / this)^2; range (0, 1), typical 0.01-0.05; not with --target-noise");
  app.add_option("--max-photons", o.maxPhotons, "--target-noise's photon budget over all lights")->capture_default_str();
  app.add_option("--max-seconds", o.maxSeconds,
                 "--target-noise's time budget: no round starts that would end after this many seconds of the bake; "
                 "range 1-1e7; the one limit that makes a bake depend on the machine (the summary says when it did)")
      ->capture_default_str();
  app.add_option("--max-rounds", o.maxRounds,
                 "--target-noise's rounds at most; 0 = no limit; repeats on any machine a bake that --max-seconds "
                 "stopped")
      ->capture_default_str();
  app.add_option("--save-photons", o.savePhotonsPath,
                 "also write the photon store to this file (docs/photon-file.md), to add photons later with --resume; "
                 "may be the --resume file");
  app.add_option("--resume", o.resumePath,
                 "continue the photon store in this file: each light's stream goes on where it stopped, up to "
                 "--photons in all; the result equals one bake with that many photons. Same scene, --seed, --scale, "
                 "--effects and --max-bounces, or it is refused");
}

void DefineDirectOptions(CLI::App& app, pb::BakeOptions& o) {
  app.option_defaults()->group("Direct light and gathered paths");
  pb::tools::AddNamedOption(app, "--direct", o.direct.mode, pb::ParseDirectLight, pb::DirectLightName,
                            pb::DirectLightNames(), "direct-light mode",
                            "the light straight from the lights: 'sampled' computes it at every vertex and texel by "
                            "shadow rays, and the photons carry only the rest; 'photons' takes it from the photons "
                            "like every bounce (the paper's method; docs/bake.md, 'Direct light')");
  app.add_option("--direct-samples", o.direct.samples,
                 "shadow rays per point with --direct sampled (with --direct-noise, the most a point may take); "
                 "range 1-1e6, typical 16-256")
      ->capture_default_str();
  app.add_option("--direct-noise", o.direct.noise,
                 "with --direct sampled: each point takes the shadow rays that bring its direct light's relative "
                 "standard error to this, up to --direct-samples (a pilot of 16 chooses; docs/bake.md, 'Direct light'); "
                 "0 = off; range 0 or 1e-4 to 1, typical 0.005-0.02")
      ->capture_default_str();
  app.add_option("--gap-paths", o.gaps.paths,
                 "with --direct sampled: paths gathered at each point in a narrow gap (between books, behind a "
                 "mirror), where no kernel can follow the light, instead of the photons' estimate (docs/bake.md, "
                 "'Narrow gaps'); 0 = off; range 0-1e6, typical 64-1024")
      ->capture_default_str();
  app.add_option("--gap-noise", o.gaps.noise,
                 "with --gap-paths: each gathered point takes the paths that bring its relative standard error to "
                 "this, up to --gap-paths (a pilot of 64 chooses; docs/bake.md, 'Narrow gaps'); 0 = off, always "
                 "--gap-paths; range 0 or 1e-4 to 1, typical 0.01-0.03")
      ->capture_default_str();
  app.add_flag("--gap-edges", o.gaps.edges,
               "with --direct sampled and --gap-paths: also gather at every vertex on a flat surface's boundary (a "
               "floor along a wall, a block's contact line), where the light turns closer than h (docs/bake.md, "
               "'Narrow gaps'); typical with --gap-paths 4096 for 1% accuracy");
  app.add_option("--gap-small-area", o.gaps.smallArea,
                 "with --direct sampled and --gap-paths: also gather on every surface whose area is below this many "
                 "h^2, smaller than its kernel (books, table legs at a wide h; docs/bake.md, 'Narrow gaps'); not "
                 "given: 6, on the smallest such surfaces up to a tenth of the triangles; 0 = off; range 0-1e3, "
                 "typical 4-8");
  app.add_option("--reference", o.referencePaths,
                 "trace no photons: gather this many paths at every vertex and texel instead, an unbiased path-traced "
                 "vertex bake to measure against (docs/bake.md, 'A reference'); range 1-1e7, typical 1024-16384");
  app.add_option("--guide-photons", o.guidePhotons,
                 "draw the first direction of --reference's and the gap gather's paths from importance maps of this "
                 "many photons (render's photon sampling) instead of the cosine lobe; 0 = off; range 0-1e9, typical "
                 "250000 (docs/bake.md, 'Guided paths')")
      ->capture_default_str();
}

void DefineMeshOptions(CLI::App& app, pb::BakeOptions& o) {
  app.option_defaults()->group("Mesh");
  app.add_flag("--refine", o.refine.adaptive,
               "adapt the mesh to the light: remove vertices where it is flat, add them where it changes (docs/bake.md, "
               "'Meshes that follow the light'); the geometry is unchanged");
  app.add_option("--tolerance", o.refine.tolerance,
                 "--refine's largest interpolation error in displayed luminance, as a fraction of the display range; "
                 "range (0, 1), typical 0.01-0.05")
      ->capture_default_str();
  app.add_option("--max-vertices", o.refine.maxVertices, "--refine's budget of output vertices; range 3 to 1e9, typical 1e4-1e6")
      ->capture_default_str();
  app.add_option("--subdivide", o.refine.subdivide,
                 "split every triangle into 4^N first (uniform, OpenSubdiv); range 0-8, 0 = off")
      ->capture_default_str();
}

void DefineOutputOptions(CLI::App& app, pb::BakeOptions& o) {
  app.option_defaults()->group("Outputs");
  app.add_option("--only", o.only, "estimate and write only the objects or materials these comma-separated names or "
                                   "globs match ('table*,book_?'), the light still traced through the whole scene; "
                                   "their vertices are those of the whole bake (docs/bake.md, 'Baking part of a scene')");
  app.add_option("--maps", o.mapsDirectory, "also write each surface's irradiance H(u,v) as an OpenEXR map into "
                                            "this folder, created if missing (surface_N.exr; docs/bake.md, 'Irradiance maps')");
  app.add_flag("--sh", o.sh, "also write where each vertex's light comes from: the L1 spherical harmonics of its "
                             "incident radiance per colour (PLY sh_r0..sh_b3, glTF _SH_R/_SH_G/_SH_B, --maps channels "
                             "sh_r0..sh_b3; docs/bake.md, 'Directional light')");
  app.add_option("--texel", o.texel, "texel side of --maps [m]; range 1e-6 to 1e4, typical 0.005-0.05")->capture_default_str();
  app.add_option("--preview", o.previewPath, "also write a PNG of the baked mesh as a viewer shows it (vertex colours, "
                                            "no lighting), from the scene's camera SCENE.camera.json or --camera");
  app.add_option("--camera", o.cameraPath, "--preview's camera JSON (position_m, look_at_m, up, vertical_fov_deg)");
  pb::tools::AddPairOption(app, "--preview-size", o.previewWidth, o.previewHeight,
                           "--preview's size in pixels, WIDTHxHEIGHT, each 1-8192");
  app.add_option("--report", o.reportPath, "write the summary figures as JSON to this file");
  app.add_flag("--report-all", o.reportAll,
               "list every surface and light in --report's JSON; by default the 1,000 largest surfaces and 1,000 "
               "brightest lights, with a summary of all");
  app.add_option("--exposure", o.exposure, "display exposure on radiance for the PLY's uchar colours; range 1e-30 to 1e30; "
                                           "default automatic (log-average luminance to 0.18)");
  app.add_flag("--ascii", o.asciiPly, "write ASCII PLY instead of binary");
}

void DefineRunOptions(CLI::App& app, pb::BakeOptions& o) {
  app.option_defaults()->group("Running");
  app.add_option("--threads", o.threads, "worker threads; 0 = all cores; range 0-1024")->capture_default_str();
  app.add_flag("-q,--quiet", o.quiet, "no progress or summary (errors and warnings still print)");
}
void DefineOptions(CLI::App& app, pb::BakeOptions& o) {
  DefineSceneOptions(app, o);
  DefinePhotonOptions(app, o);
  DefineRoundOptions(app, o);
  app.option_defaults()->group("Density estimation");
  DefineEstimatorOptions(app, o.estimator);
  app.add_flag("!--no-cover", o.findCovers, "do not find where other geometry covers a surface (a block on a floor); "
                                           "light then bleeds under objects and is lost beside them");
  DefineDirectOptions(app, o);
  DefineMeshOptions(app, o);
  DefineOutputOptions(app, o);
  DefineRunOptions(app, o);
}

}  // namespace

void DefineBakeCommandLine(CLI::App& app, BakeCommandLine& c) {
  DefineOptions(app, c.options);
  app.option_defaults()->group("Photons");
  app.add_option("--quality", c.quality, "a target and the first round's photons, with h and shadow rays chosen "
                                           "for the scene: " + pb::QualityNames() + " (error 8%, the defaults' noise "
                                           "3%, error 3%, error 2%; docs/bake.md, 'Quality presets'; production also "
                                           "gathers the edges); options given explicitly win");
  app.option_defaults()->group("Options");  // CLI11's own group, for what the tools add after
}

void ApplyBakeCommandLine(const CLI::App& app, BakeCommandLine& c) {
  pb::GivenOptions given{.bandwidth = app.count("--h") > 0,
                         .photons = app.count("--photons") > 0,
                         .shadowRays = app.count("--direct-samples") + app.count("--direct-noise") > 0,
                         .gapPaths = app.count("--gap-paths") > 0,
                         .smallArea = app.count("--gap-small-area") > 0};
  pb::ApplyDefaults(c.options, given, c.quality);
  c.options.Validate();
}

int RunBake(int argc, char** argv) {
  CLI::App app{"bake: photon-traced irradiance baked onto mesh vertices (photonbake)"};
  BakeCommandLine c;
  DefineBakeCommandLine(app, c);
  return RunTool(app, argc, argv, [&] { ApplyBakeCommandLine(app, c); }, [&] {
    pb::RemoveTemporariesOnTermination();
    const Log log(c.options.quiet);
    BakeAndSummarise(c.options, log);
  });
}

}  // namespace pb::tools
