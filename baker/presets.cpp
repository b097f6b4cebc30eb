#include "baker/presets.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "estimators/light_sampler.h"
#include "mesh/errors.h"

namespace pb {

std::optional<QualityPreset> ParseQuality(std::string_view name) {
  // draft's 160,000 photons and 16 rays and paths: the error they leave is what its target allows (box 6.7%, office
  // 7.4% net), in a fraction of the time that the defaults' 256 take to land at 4% (docs/bake.md, "Quality presets").
  // At 32 rays and paths, since the small surfaces' gathered light is weighed against their photons, it read 5.2% and
  // 5.6%: more than the target asks, at twice the rays.
  if (name == "draft") return QualityPreset{.target = 0.08f, .photons = 160'000, .error = true, .shadowRays = 16, .gapPaths = 16};
  if (name == "medium") return QualityPreset{.target = kDefaultTargetNoise, .photons = 1'000'000};
  if (name == "high") return QualityPreset{.target = 0.03f, .photons = 2'000'000, .error = true};
  if (name == "production")
    return QualityPreset{.target = 0.02f, .photons = 2'000'000, .error = true, .gatherEdges = true, .gapPaths = 1024};
  return std::nullopt;
}

std::string QualityNames() { return "draft, medium, high, production"; }

uint64_t FirstRoundForError(float target, uint64_t photons, float at) {
  const double n = double(photons) * std::pow(double(at) / target, 2);
  return uint64_t(std::llround(std::clamp(n, 250'000.0, 32'000'000.0)));
}

void SizeFirstRoundForError(BakeOptions& o, const GivenOptions& given, uint64_t photons, float at) {
  const double k = double(at) / *o.targetError;
  if (!given.photons) o.photons = FirstRoundForError(*o.targetError, photons, at);
  if (!given.shadowRays) {  // stratified: their noise falls as S^-kStratifiedOrder; a square, for the strata
    const double rays = std::clamp(o.direct.samples * std::pow(k, 1 / LightSampler::kStratifiedOrder), 16.0, 4096.0);
    o.direct.samples = uint32_t(std::pow(std::ceil(std::sqrt(rays)), 2));
  }
  if (!given.gapPaths && o.gaps.paths > 0)
    o.gaps.paths = uint32_t(std::llround(std::clamp(o.gaps.paths * k * k, 16.0, double(1 << 16))));
}

void ApplySceneDefaults(BakeOptions& o, const GivenOptions& given) {
  o.direct.fixedSamples = o.direct.fixedSamples || given.shadowRays;
  o.gaps.fixedPaths = o.gaps.fixedPaths || given.gapPaths;
  if (o.estimator.kind == EstimatorKind::kNearest) return;
  if (!given.bandwidth) o.estimator.bandwidth.reset();
  if (given.photons || o.referencePaths > 0 || !o.resumePath.empty()) return;
  if (o.targetError) SizeFirstRoundForError(o, given, o.photons, kDefaultTargetNoise);
  if (!o.Rounds()) o.targetNoise = kDefaultTargetNoise;
}

void ApplyGapDefaults(BakeOptions& o, const GivenOptions& given) {
  if (given.smallArea || o.estimator.kind == EstimatorKind::kNearest) return;
  o.gaps.smallArea = kDefaultSmallArea, o.gaps.smallShare = kDefaultSmallShare;
}

void ApplyDefaults(BakeOptions& o, GivenOptions given, std::string_view quality) {
  if (!quality.empty()) ApplyQuality(quality, given, o), given.photons = true;
  ApplySceneDefaults(o, given);
  ApplyGapDefaults(o, given);
}

void ApplyQuality(std::string_view name, const GivenOptions& given, BakeOptions& o) {
  const std::optional<QualityPreset> preset = ParseQuality(name);
  if (!preset)
    throw InputError("--quality", 0, fmt::format("unknown preset '{}'; choose one of: {}", name, QualityNames()));
  if (!given.photons) o.photons = preset->photons;
  if (preset->gatherEdges) o.gaps.edges = true;
  if (preset->gapPaths > 0 && !given.gapPaths) o.gaps.paths = preset->gapPaths;
  if (preset->shadowRays > 0 && !given.shadowRays) o.direct.samples = preset->shadowRays;
  // a --target-error given in the preset's place scales its first round
  if (o.targetError && preset->error) SizeFirstRoundForError(o, given, preset->photons, preset->target);
  const bool rounds = o.referencePaths == 0 && o.estimator.kind != EstimatorKind::kNearest;
  if (rounds && !o.Rounds()) (preset->error ? o.targetError : o.targetNoise) = preset->target;
}

}  // namespace pb
