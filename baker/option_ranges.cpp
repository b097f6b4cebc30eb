#include "baker/option_ranges.h"

#include <fmt/format.h>

#include <cmath>

#include "mesh/errors.h"

namespace pb {

void RequireOption(bool ok, const char* option, const std::string& rule) {
  if (!ok) throw InputError(option, 0, rule);
}

bool Within(double x, double lo, double hi) { return x >= lo && x <= hi; }

void RequireScale(double metresPerUnit) {
  RequireOption(Within(metresPerUnit, kMinOptionLength, 1e6), "--scale", "must lie in [1e-6, 1e6] metres per scene unit");
}

void RequirePhotons(uint64_t photons, const char* option) {
  RequireOption(photons >= 1 && photons <= kMostPhotons, option, "must lie in [1, 2^40]");
}

void RequireThreads(unsigned threads) { RequireOption(threads <= 1024, "--threads", "must lie in [0, 1024]"); }

void RequireExposure(const std::optional<float>& exposure) {
  RequireOption(!exposure || Within(*exposure, 1e-30, 1e30), "--exposure",
                "must lie in [1e-30, 1e30] (the display shows the tone curve of exposure x radiance)");
}

void RequireLuminousEfficacy(double lumensPerWatt) {
  RequireOption(Within(lumensPerWatt, 1, 683), "--luminous-efficacy", "must lie in [1, 683] lm/W");
}

void RequireImageSize(int width, int height, const char* option, int most) {
  RequireOption(width >= 1 && width <= most && height >= 1 && height <= most, option,
                fmt::format("must be WIDTHxHEIGHT with each in [1, {}] pixels", most));
}

}  // namespace pb
