// The ranges of the options that several tools share (bake, bake-mpi, render, accuracy, scene-to-gltf). Each rule
// is written once, here, so that every tool refuses the same value with the same words: an InputError that names
// the option, which the tools turn into exit status 2 before any work (tools/cli_options.h).
// Lengths in metres, counts dimensionless.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace pb {

// The shortest length an option takes, as the float it is read into (1e-6f is a shade below 1e-6) [m].
inline constexpr double kMinOptionLength = double(1e-6f);
// The most photons any tool traces in one run: 2^40 (about 1.1e12).
inline constexpr uint64_t kMostPhotons = uint64_t(1) << 40;

// InputError(option) stating `rule` unless `ok`.
void RequireOption(bool ok, const char* option, const std::string& rule);
// x in [lo, hi]; false for NaN.
bool Within(double x, double lo, double hi);

void RequireScale(double metresPerUnit);                       // --scale: [1e-6, 1e6] m per scene unit
void RequirePhotons(uint64_t photons, const char* option);     // [1, 2^40]
void RequireThreads(unsigned threads);                         // --threads: [0, 1024], 0 = all cores
void RequireExposure(const std::optional<float>& exposure);    // --exposure: in [1e-30, 1e30] when given
void RequireLuminousEfficacy(double lumensPerWatt);            // --luminous-efficacy: [1, 683] lm/W
void RequireImageSize(int width, int height, const char* option, int most);  // WIDTHxHEIGHT, each in [1, most]

}  // namespace pb
