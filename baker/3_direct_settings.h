// Stage 3's direct light as the command line sets it (--direct, --direct-samples, --direct-noise); the terms that
// compute it are baker/3_contributions.h's, which validates these settings.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace pb {

// --direct: how the light that reaches a surface straight from a light (no scattering between) is computed.
//   kSampled: at every point that is asked (vertex, refined vertex, texel) by shadow rays to the lights
//             (estimators/light_sampler.h); photons are then stored only after their first scattering, so the
//             kernel estimates only the rest (interreflection, and caustics by mirrors and glass).
//   kPhotons: from the photons, like every other bounce (the paper's method).
enum class DirectLight : uint8_t { kPhotons, kSampled };
std::optional<DirectLight> ParseDirectLight(std::string_view name);  // "photons" or "sampled"
std::string DirectLightName(DirectLight mode);
std::string DirectLightNames();  // comma-separated, for --help and error messages
struct DirectSettings {
  DirectLight mode = DirectLight::kSampled;
  uint32_t samples = 256;  // --direct-samples: shadow rays per point; range [1, 1e6], typical 64-1024
  // --direct-noise: with a target (> 0), each point takes as many shadow rays as its own noise needs to reach
  // this relative standard error of its direct light, up to `samples` (LightSampler::AdaptiveIrradiance);
  // 0: every point takes `samples`. Range 0 or [1e-4, 1], typical 0.005-0.02.
  double noise = 0;
  // --direct-samples or --direct-noise given: the rounds of --target-noise keep the shadow rays as they are
  // (otherwise they raise them where the points' own noise holds the bake's; baker/photons/progressive.h).
  bool fixedSamples = false;
  void Validate() const;  // the ranges above; an InputError naming the option
};

}  // namespace pb
