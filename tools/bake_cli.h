// The bake command line, shared by bake and bake-mpi (tools/bake.cpp, tools/bake_mpi.cpp): every option of
// BakeOptions, and --quality, which sets --target-error (or --target-noise) and the first round's --photons, except
// those given.
#pragma once

#include <string>

#include "baker/presets.h"

namespace CLI {
class App;
}

namespace pb::tools {

// The whole of the bake tool: parses the command line, bakes, prints the summary; the process's exit status
// (tools/cli_options.h, RunTool).
int RunBake(int argc, char** argv);

struct BakeCommandLine {
  BakeOptions options;
  std::string quality;  // --quality, or empty
};

void DefineBakeCommandLine(CLI::App& app, BakeCommandLine& c);
// After parsing: applies --quality and the scene's defaults (options not given take the defaults that suit the
// scene, pb::ApplySceneDefaults), and validates every option's range (InputError: a bad command line).
void ApplyBakeCommandLine(const CLI::App& app, BakeCommandLine& c);

}  // namespace pb::tools
