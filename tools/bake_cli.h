// The bake command line, shared by bake and bake-mpi (tools/bake.cpp, tools/bake_mpi.cpp): every option of
// BakeOptions, and --quality, which sets --photons, --h and --direct-samples except those given.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "baker/options.h"

namespace pb::tools {

struct BakeCommandLine {
  BakeOptions options;
  std::string quality;  // --quality, or empty
  // Options not given take the defaults that suit the scene (pb::ApplySceneDefaults); bake-mpi, which needs a
  // fixed h and photon count, keeps BakeOptions' own.
  bool sceneDefaults = true;
};

void DefineBakeCommandLine(CLI::App& app, BakeCommandLine& c);
// After parsing: applies --quality and the scene's defaults, and validates every option's range (InputError: a bad command line).
void ApplyBakeCommandLine(const CLI::App& app, BakeCommandLine& c);

}  // namespace pb::tools
