// bake: photon-traced irradiance on every vertex of an OBJ or glTF scene, written as a PLY that MeshLab opens.
// Exit status: 0 on success, 1 for bad input (message names file:line), 2 for a bad command line.
#include <CLI/CLI.hpp>

#include "baker/bake.h"
#include "tools/bake_cli.h"
#include "tools/cli_options.h"

int main(int argc, char** argv) {
  CLI::App app{"bake: photon-traced irradiance baked onto mesh vertices (photonbake)"};
  pb::tools::BakeCommandLine c;
  pb::tools::DefineBakeCommandLine(app, c);
  return pb::tools::RunTool(app, argc, argv, [&] { pb::tools::ApplyBakeCommandLine(app, c); }, [&] {
    const pb::Log log(c.options.quiet);
    pb::PrintSummary(pb::Bake(c.options, log), log);
  });
}
