// render: the importance-driven path tracer (Jensen 1995) of the particle-tracing paper, against BRDF sampling.
// Writes a linear OpenEXR image of radiance [W/(m^2 sr)] and a tone-mapped PNG beside it.
// Exit status: 0 on success, 1 for bad input (message names file:line), 2 for a bad command line.
#include <CLI/CLI.hpp>

#include <string>

#include "baker/render/render.h"
#include "tools/cli_options.h"

namespace {

void DefineOptions(CLI::App& app, pb::RenderOptions& o) {
  app.add_option("scene", o.scenePath, "OBJ scene (with MTL) or glTF 2.0; its camera is SCENE.camera.json unless --camera")
      ->required();
  app.add_option("-o,--output", o.outputPath, "OpenEXR image to write (radiance, W/(m^2 sr)); a PNG goes beside it")
      ->required();
  app.add_option("--camera", o.cameraPath, "camera JSON (position_m, look_at_m, up, vertical_fov_deg)");
  pb::tools::AddPairOption(app, "--size", o.width, o.height, "image size in pixels, WIDTHxHEIGHT");
  app.add_option("--spp", o.spp, "samples per pixel; >= 1")->capture_default_str();
  app.add_option("--spp-sweep", o.sppSweep, "render once per count (e.g. 1,2,4,8) and write a strip of them")
      ->delimiter(',');
  pb::tools::AddNamedOption(app, "--sampling", o.path.sampling, pb::ParseSampling, pb::SamplingName,
                            pb::JoinNames(pb::kAllSamplings, pb::SamplingName), "sampling",
                            "direction sampling at diffuse surfaces: the BRDF alone, or the photon importance map");
  app.add_flag("!--no-light-sampling", o.path.lightSampling,
               "find the lights only by hitting them, the paper's pure form; by default each diffuse hit also casts "
               "one shadow ray to them (next-event estimation), in both samplers");
  app.add_option("--photons", o.photons, "photons traced for the photon map (--sampling photons)")->capture_default_str();
  app.add_option("--neighbours", o.path.neighbours, "photons per importance map: a cached map's cell holds about N, an uncached map takes the N nearest; >= 1")
      ->capture_default_str();
  pb::tools::AddPairOption(app, "--regions", o.path.thetaRegions, o.path.phiRegions,
                "importance map regions, THETAxPHI (powers of two for --warp mipmap)");
  app.add_option("--floor", o.path.floorFraction, "fraction of the total importance spread over every region; [0, 1]")
      ->capture_default_str();
  app.add_flag("!--no-map-cache", o.path.mapCache,
               "build a map at every hit from its own nearest photons (the paper's form) instead of caching maps on a "
               "grid of cells of about --neighbours photons each");
  pb::tools::AddNamedOption(app, "--map-domain", o.path.domain, pb::ParseDomain, pb::DomainName,
                            pb::JoinNames(pb::kMapDomains, pb::DomainName), "domain",
                            "regions of the same projected solid angle (cosine: a uniform map is the BRDF's cosine lobe) "
                            "or of the same solid angle (the paper's)");
  pb::tools::AddNamedOption(app, "--warp", o.path.warp, pb::ParseWarp, pb::WarpName,
                            pb::JoinNames(pb::kAllWarps, pb::WarpName), "warp",
                            "how a region is drawn: hierarchical mip-map warping, or inversion of the region CDF");
  pb::tools::AddSeedOption(app, o.seed, "random seed, 0 to 2^64 - 1; the same seed gives the same image for any --threads");
  app.add_option("--threads", o.threads, "worker threads; 0 = all cores")->capture_default_str();
  app.add_option("--scale", o.scale, "metres per scene unit")->capture_default_str();
  app.add_option("--exposure", o.exposure, "PNG exposure on radiance; range 1e-30 to 1e30; default automatic");
  app.add_option("--report", o.reportPath, "write the summary figures as JSON to this file");
  app.add_flag("-q,--quiet", o.quiet, "no progress or summary");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"render: importance-driven path tracing with the photon map (photonbake)"};
  pb::RenderOptions options;
  DefineOptions(app, options);
  return pb::tools::RunTool(app, argc, argv, [&] { options.Validate(); }, [&] {
    const pb::Log log(options.quiet);
    pb::PrintRenderSummary(pb::Render(options, log), log);
  });
}
