#include "baker/options.h"

#include "mesh/scene_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "baker/0_plan_transport.h"
#include "baker/option_ranges.h"
#include "estimators/density_estimator.h"
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

namespace {

void ValidateScene(const BakeOptions& o) {
  RequireScale(o.scale);
  RequireLuminousEfficacy(o.luminousEfficacy);
  ParseEffectOverrides(o.effectsText);
}

void ValidatePhotons(const BakeOptions& o) {
  RequirePhotons(o.photons, "--photons");
  RequireThreads(o.threads);
  RequireOption(o.maxBounces <= kDefaultMaxBounces, "--max-bounces", fmt::format("must lie in [0, {}]", kDefaultMaxBounces));
  RequireOption(o.referencePaths <= 10'000'000, "--reference", "must lie in [0, 10000000] paths per point");
  RequireOption(o.guidePhotons <= 1'000'000'000, "--guide-photons", "must lie in [0, 1000000000]");
  RequireOption(o.guidePhotons == 0 || o.referencePaths > 0 || (o.direct.mode == DirectLight::kSampled && o.gaps.paths > 0),
                "--guide-photons", "guides the paths of --reference or of the gap gather (--direct sampled, --gap-paths "
                "above 0), and this bake gathers none");
  RequireOption(o.referencePaths == 0 || (o.resumePath.empty() && o.savePhotonsPath.empty() && !o.Rounds()),
                "--reference", "traces no photons, so it cannot be combined with --resume, --save-photons, --target-noise "
                "or --target-error");
}

// Lengths far outside these lose the estimate to float precision (h^2 under- or overflows against the scene).
void ValidateEstimator(const EstimatorSettings& e) {
  RequireOption(!e.bandwidth || Within(*e.bandwidth, kMinOptionLength, 1e4), "--h", "must be a length in [1e-6, 1e4] m");
  RequireOption(e.neighbours >= 2 && e.neighbours <= 1'000'000, "--k", "must lie in [2, 1000000]");
}

void ValidateRounds(const BakeOptions& o) {
  RequireOption(!o.targetNoise || (*o.targetNoise > 0 && *o.targetNoise < 1), "--target-noise", "must lie in (0, 1)");
  RequireOption(!o.targetError || (*o.targetError > 0 && *o.targetError < 1), "--target-error", "must lie in (0, 1)");
  RequireOption(!o.targetError || !o.targetNoise, "--target-error", "and --target-noise are two targets: give one");
  RequireOption(!o.targetError || o.estimator.kind != EstimatorKind::kNearest, "--target-error",
                "needs the kernel or histogram estimator, whose smoothing bias the bake predicts (knn's radius is its own)");
  RequireOption(!o.Rounds() || o.maxPhotons >= o.photons, "--max-photons",
                "must be at least --photons, the first round of --target-noise or --target-error");
  RequireOption(o.maxPhotons <= kMostPhotons, "--max-photons", "must be at most 2^40");
  RequireOption(Within(o.maxSeconds, 1, 1e7), "--max-seconds", "must lie in [1, 1e7] seconds");
  RequireOption(o.maxRounds <= 1000, "--max-rounds", "must lie in [0, 1000]");
  if (o.targetNoise) RequireReachableNoise(o.estimator, *o.targetNoise);
}

void ValidateOutputOptions(const BakeOptions& o) {
  RequireExposure(o.exposure);
  RequireOption(Within(o.texel, kMinOptionLength, 1e4), "--texel", "must be a length in [1e-6, 1e4] m");
  RequireImageSize(o.previewWidth, o.previewHeight, "--preview-size", 8192);
  RequireOption(o.cameraPath.empty() || !o.previewPath.empty(), "--camera", "is the --preview's camera; give --preview too");
  RequireOption(!o.asciiPly || !HasGltfExtension(o.outputPath), "--ascii", "writes ASCII PLY; -o names a glTF file");
  RequireOption(o.only.empty() || !o.refine.Enabled(), "--only", "cannot yet be combined with --refine or --subdivide");
}

}  // namespace

// Each stage's settings checked beside them, in the pipeline's order.
void BakeOptions::Validate() const {
  ValidateScene(*this);
  ValidatePhotons(*this);
  ValidateEstimator(estimator);
  direct.Validate();
  gaps.Validate();
  ValidateRounds(*this);
  refine.Validate();
  ValidateOutputOptions(*this);
}

}  // namespace pb
