#include "baker/options.h"

#include "mesh/gltf_loader.h"

#include <fmt/format.h>

#include <cmath>

#include "baker/0_plan_transport.h"
#include "mesh/errors.h"

namespace pb {
namespace {

bool FinitePositive(double x) { return x > 0 && std::isfinite(x); }
bool Within(double x, double lo, double hi) { return x >= lo && x <= hi; }  // false for NaN
// The shortest length option, as the float it is read into (1e-6f is a shade below 1e-6).
constexpr double kMinLength = double(1e-6f);

void Require(bool ok, const char* option, const std::string& rule) {
  if (!ok) throw InputError(option, 0, rule);
}

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
  Require(Within(estimator.bandwidth, kMinLength, 1e4), "--h", "must be a length in [1e-6, 1e4] m");
  Require(estimator.neighbours >= 2 && estimator.neighbours <= 1'000'000, "--k", "must lie in [2, 1000000]");
  Require(photons >= 1 && photons <= (uint64_t(1) << 40), "--photons", "must lie in [1, 2^40]");
  Require(threads <= 1024, "--threads", "must lie in [0, 1024]");
  Require(Within(scale, kMinLength, 1e6), "--scale", "must lie in [1e-6, 1e6] metres per scene unit");
  Require(direct.samples >= 1 && direct.samples <= 1'000'000, "--direct-samples", "must lie in [1, 1000000]");
  Require(direct.noise == 0 || (direct.noise >= 1e-4 && direct.noise <= 1), "--direct-noise",
          "must be 0 (off) or lie in [0.0001, 1]");
  Require(gaps.paths <= 1'000'000, "--gap-paths", "must lie in [0, 1000000] paths per point");
  Require(gaps.noise == 0 || (gaps.noise >= 1e-4 && gaps.noise <= 1), "--gap-noise",
          "must be 0 (off) or lie in [0.0001, 1]");
  Require(gaps.smallArea >= 0 && gaps.smallArea <= 1000, "--gap-small-area", "must lie in [0, 1000] h^2");
  Require(referencePaths <= 10'000'000, "--reference", "must lie in [0, 10000000] paths per point");
  Require(referencePaths == 0 || (resumePath.empty() && savePhotonsPath.empty() && !targetNoise), "--reference",
          "traces no photons, so it cannot be combined with --resume, --save-photons or --target-noise");
  Require(maxBounces <= kDefaultMaxBounces, "--max-bounces", fmt::format("must lie in [0, {}]", kDefaultMaxBounces));
  Require(!exposure || FinitePositive(*exposure), "--exposure", "must be a finite number > 0");
  Require(Within(texel, kMinLength, 1e4), "--texel", "must be a length in [1e-6, 1e4] m");
  Require(previewWidth >= 1 && previewWidth <= 8192 && previewHeight >= 1 && previewHeight <= 8192, "--preview-size",
          "must be WIDTHxHEIGHT with each in [1, 8192]");
  Require(cameraPath.empty() || !previewPath.empty(), "--camera", "is the --preview's camera; give --preview too");
  Require(refine.tolerance > 0 && refine.tolerance < 1, "--tolerance", "must lie in (0, 1)");
  Require(refine.subdivide >= 0 && refine.subdivide <= 8, "--subdivide", "must lie in [0, 8]");
  Require(refine.maxVertices >= 3 && refine.maxVertices <= 1'000'000'000, "--max-vertices", "must lie in [3, 1e9]");
  Require(!targetNoise || (*targetNoise > 0 && *targetNoise < 1), "--target-noise", "must lie in (0, 1)");
  Require(!targetNoise || maxPhotons >= photons, "--max-photons",
          "must be at least --photons, the first round of --target-noise");
  Require(maxPhotons <= (uint64_t(1) << 40), "--max-photons", "must be at most 2^40");
  Require(Within(maxSeconds, 1, 1e7), "--max-seconds", "must lie in [1, 1e7] seconds");
  Require(maxRounds <= 1000, "--max-rounds", "must lie in [0, 1000]");
  if (targetNoise) RequireReachableNoise(estimator, *targetNoise);
  Require(luminousEfficacy >= 1 && luminousEfficacy <= 683, "--luminous-efficacy", "must lie in [1, 683] lm/W");
  Require(!asciiPly || !HasGltfExtension(outputPath), "--ascii", "writes ASCII PLY; -o names a glTF file");
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
