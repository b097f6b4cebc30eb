// bake: photon-traced irradiance on every vertex of an OBJ scene, written as a PLY that MeshLab opens.
// Exit status: 0 on success, 1 for bad input (message names file:line), 2 for a bad command line.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cstdio>

#include "baker/bake.h"
#include "mesh/errors.h"

namespace {

CLI::App& DefineOptions(CLI::App& app, pb::BakeOptions& o, std::string& kernel) {
  app.add_option("scene", o.scenePath, "OBJ scene (with MTL). Kd = diffuse albedo in [0,1]; Ke = emitted radiance "
                                       "[W/(m^2 sr)], one-sided along the counter-clockwise normal")
      ->required();
  app.add_option("-o,--output", o.outputPath, "PLY to write (binary little-endian unless --ascii); written to a "
                                              "temporary file and renamed into place")
      ->required();
  app.add_option("--kernel", kernel, "density kernel: " + pb::KernelNames())->capture_default_str();
  app.add_option("--h", o.bandwidth, "kernel bandwidth h [m]: support radius in the surface plane; range > 0, "
                                     "typical 0.02-0.1 for a room-sized scene")
      ->capture_default_str();
  app.add_option("--photons", o.photons, "photons emitted over all lights, split by power (N_i = n Phi_i / Phi); "
                                         "range >= 1, typical 1e6-1e7")
      ->capture_default_str();
  app.add_option("--seed", o.seed, "random seed; any integer. Same seed, same bytes, for any --threads")
      ->capture_default_str();
  app.add_option("--threads", o.threads, "worker threads; 0 = all cores")->capture_default_str();
  app.add_option("--scale", o.scale, "metres per scene unit; range > 0, typical 1, or 0.001 for millimetres")
      ->capture_default_str();
  app.add_option("--report", o.reportPath, "write the summary figures as JSON to this file");
  app.add_option("--exposure", o.exposure, "display exposure on radiance for the PLY's uchar colours; range > 0; "
                                           "default automatic (log-average luminance to 0.18)");
  app.add_flag("--ascii", o.asciiPly, "write ASCII PLY instead of binary");
  app.add_flag("-q,--quiet", o.quiet, "no progress or summary (errors and warnings still print)");
  return app;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bake: photon-traced irradiance baked onto mesh vertices (photonbake)"};
  app.get_formatter()->column_width(24);
  pb::BakeOptions options;
  std::string kernel = pb::KernelName(options.kernel);
  DefineOptions(app, options, kernel);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  const auto parsedKernel = pb::ParseKernel(kernel);
  if (!parsedKernel) {
    fmt::print(stderr, "--kernel: error: unknown kernel '{}'; choose one of: {}\n", kernel, pb::KernelNames());
    return 2;
  }
  options.kernel = *parsedKernel;
  try {
    const pb::Log log(options.quiet);
    const pb::BakeReport report = pb::Bake(options, log);
    pb::PrintSummary(report, log);
    return 0;
  } catch (const pb::InputError& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
}
