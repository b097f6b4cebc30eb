#include "baker/options.h"

#include "mesh/scene_file.h"

#include <fmt/format.h>

#include <cmath>

#include "baker/0_plan_transport.h"
#include "baker/option_ranges.h"
#include "mesh/errors.h"

namespace pb {
namespace {

// knn's noise does not fall with more photons (estimators/density_estimator.h, UniformRelativeNoise): a target
// below it can never be met.
void RequireReachableNoise(const EstimatorSettings& e, float target) {
  if (e.kind != EstimatorKind::kNearest) return;
  const double floor = UniformRelativeNoise(e, INFINITY);
  if (target >= floor) return;
  throw InputError("--target-noise", 0,
                   fmt::format("knn's noise is 1/sqrt(k - 2) = {:.3f} for --k {}, whatever the photon count: raise "
                               "--k to {} or more, or use the kernel estimator",
                               floor, e.neighbours, uint32_t(std::ceil(2 + 1 / (double(target) * target)))));
}

}  // namespace

std::optional<DirectLight> ParseDirectLight(std::string_view name) {
  if (name == "photons") return DirectLight::kPhotons;
  if (name == "sampled") return DirectLight::kSampled;
  return std::nullopt;
}

std::optional<QualityPreset> ParseQuality(std::string_view name) {
  if (name == "draft") return QualityPreset{250'000, 0.08f, 64};
  if (name == "medium") return QualityPreset{1'000'000, 0.08f, 256};
  if (name == "high") return QualityPreset{4'000'000, 0.05f, 256};
  if (name == "production") return QualityPreset{16'000'000, 0.03f, 1024};
  return std::nullopt;
}

std::string QualityNames() { return "draft, medium, high, production"; }

std::string DirectLightName(DirectLight mode) { return mode == DirectLight::kSampled ? "sampled" : "photons"; }
std::string DirectLightNames() { return "photons, sampled"; }

void BakeOptions::Validate() const {
  // Lengths far outside these lose the estimate to float precision (h^2 under- or overflows against the scene).
  RequireOption(Within(estimator.bandwidth, kMinOptionLength, 1e4), "--h", "must be a length in [1e-6, 1e4] m");
  RequireOption(estimator.neighbours >= 2 && estimator.neighbours <= 1'000'000, "--k", "must lie in [2, 1000000]");
  RequirePhotons(photons, "--photons");
  RequireThreads(threads);
  RequireScale(scale);
  RequireOption(direct.samples >= 1 && direct.samples <= 1'000'000, "--direct-samples", "must lie in [1, 1000000]");
  RequireOption(direct.noise == 0 || (direct.noise >= 1e-4 && direct.noise <= 1), "--direct-noise",
                "must be 0 (off) or lie in [0.0001, 1]");
  RequireOption(gaps.paths <= 1'000'000, "--gap-paths", "must lie in [0, 1000000] paths per point");
  RequireOption(gaps.noise == 0 || (gaps.noise >= 1e-4 && gaps.noise <= 1), "--gap-noise",
                "must be 0 (off) or lie in [0.0001, 1]");
  RequireOption(gaps.smallArea >= 0 && gaps.smallArea <= 1000, "--gap-small-area", "must lie in [0, 1000] h^2");
  RequireOption(referencePaths <= 10'000'000, "--reference", "must lie in [0, 10000000] paths per point");
  RequireOption(referencePaths == 0 || (resumePath.empty() && savePhotonsPath.empty() && !targetNoise), "--reference",
                "traces no photons, so it cannot be combined with --resume, --save-photons or --target-noise");
  RequireOption(maxBounces <= kDefaultMaxBounces, "--max-bounces",
                fmt::format("must lie in [0, {}]", kDefaultMaxBounces));
  RequireExposure(exposure);
  RequireOption(Within(texel, kMinOptionLength, 1e4), "--texel", "must be a length in [1e-6, 1e4] m");
  RequireImageSize(previewWidth, previewHeight, "--preview-size", 8192);
  RequireOption(cameraPath.empty() || !previewPath.empty(), "--camera",
                "is the --preview's camera; give --preview too");
  RequireOption(refine.tolerance > 0 && refine.tolerance < 1, "--tolerance", "must lie in (0, 1)");
  RequireOption(refine.subdivide >= 0 && refine.subdivide <= 8, "--subdivide", "must lie in [0, 8]");
  RequireOption(refine.maxVertices >= 3 && refine.maxVertices <= 1'000'000'000, "--max-vertices",
                "must lie in [3, 1e9]");
  RequireOption(!targetNoise || (*targetNoise > 0 && *targetNoise < 1), "--target-noise", "must lie in (0, 1)");
  RequireOption(!targetNoise || maxPhotons >= photons, "--max-photons",
                "must be at least --photons, the first round of --target-noise");
  RequireOption(maxPhotons <= kMostPhotons, "--max-photons", "must be at most 2^40");
  RequireOption(Within(maxSeconds, 1, 1e7), "--max-seconds", "must lie in [1, 1e7] seconds");
  RequireOption(maxRounds <= 1000, "--max-rounds", "must lie in [0, 1000]");
  if (targetNoise) RequireReachableNoise(estimator, *targetNoise);
  RequireLuminousEfficacy(luminousEfficacy);
  RequireOption(!asciiPly || !HasGltfExtension(outputPath), "--ascii", "writes ASCII PLY; -o names a glTF file");
  ParseEffectOverrides(effectsText);
}

void ApplySceneDefaults(BakeOptions& o, const GivenOptions& given) {
  o.direct.fixedSamples = o.direct.fixedSamples || given.shadowRays;
  if (o.estimator.kind == EstimatorKind::kNearest) return;
  if (!given.bandwidth) o.autoBandwidth = true;
  if (!given.photons && !o.targetNoise && o.referencePaths == 0 && o.resumePath.empty())
    o.targetNoise = kDefaultTargetNoise;
}

}  // namespace pb
