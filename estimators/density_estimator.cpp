#include "estimators/density_estimator.h"

#include <vector>

#include <algorithm>
#include <cmath>

#include "estimators/enum_names.h"
#include "mesh/errors.h"
#include "estimators/histogram_estimator.h"
#include "estimators/kernel_estimator.h"
#include "estimators/nearest_estimator.h"

namespace pb {
namespace {

// The surface's own h [m]: an estimator is built once it is chosen.
float SurfaceBandwidth(const EstimatorSettings& settings) {
  PB_CHECK(settings.bandwidth.has_value(), "an estimator is built with its surface's h");
  return *settings.bandwidth;
}

}  // namespace

std::unique_ptr<DensityEstimator> MakeDensityEstimator(const EstimatorSettings& settings, const SurfaceRegion& region,
                                                       std::span<const Point2> uv, std::span<const Rgb> flux,
                                                       const KernelBinning& binning) {
  const SurfaceRegion* correction = settings.edgeCorrection ? &region : nullptr;
  using Binning = KernelEstimator::Binning;
  switch (settings.kind) {
    case EstimatorKind::kKernel:
      if (binning.traced != nullptr)
        return std::make_unique<KernelEstimator>(*binning.traced, SurfaceBandwidth(settings), settings.kernel, region, settings.localLinear);
      return std::make_unique<KernelEstimator>(uv, flux, SurfaceBandwidth(settings), settings.kernel, correction, settings.localLinear,
                                               binning.wide ? Binning::kWide : Binning::kAuto, binning.fluxUnit);
    case EstimatorKind::kHistogram:
      return std::make_unique<HistogramEstimator>(uv, flux, SurfaceBandwidth(settings), region, settings.edgeCorrection);
    case EstimatorKind::kNearest:
      return std::make_unique<NearestEstimator>(uv, flux, settings.neighbours, region, settings.edgeCorrection);
  }
  return nullptr;
}

namespace {

class CoveredEstimator final : public DensityEstimator {
 public:
  CoveredEstimator(const SurfaceCover& cover, std::unique_ptr<DensityEstimator> open, std::unique_ptr<DensityEstimator> covered)
      : cover_(cover), open_(std::move(open)), covered_(std::move(covered)) {}
  Rgb Estimate(Point2 x) const override { return Domain(x).Estimate(x); }
  double RelativeNoise(Point2 x) const override { return Domain(x).RelativeNoise(x); }
  NoisyIrradiance EstimateWithNoise(Point2 x) const override { return Domain(x).EstimateWithNoise(x); }

 private:
  const DensityEstimator& Domain(Point2 x) const { return cover_.Covered(x) ? *covered_ : *open_; }
  const SurfaceCover& cover_;
  std::unique_ptr<DensityEstimator> open_, covered_;
};

}  // namespace

std::unique_ptr<DensityEstimator> MakeCoveredDensityEstimator(const EstimatorSettings& settings, const SurfaceRegion& open,
                                                              const SurfaceRegion& covered, const SurfaceCover& cover,
                                                              std::span<const Point2> uv, std::span<const Rgb> flux,
                                                              const KernelBinning& openBinning, const KernelBinning& coveredBinning) {
  std::vector<Point2> openUv, coveredUv;
  std::vector<Rgb> openFlux, coveredFlux;
  for (size_t i = 0; i < uv.size(); ++i) {
    const bool inside = cover.Covered(uv[i]);
    (inside ? coveredUv : openUv).push_back(uv[i]);
    (inside ? coveredFlux : openFlux).push_back(flux[i]);
  }
  return std::make_unique<CoveredEstimator>(cover, MakeDensityEstimator(settings, open, openUv, openFlux, openBinning),
                                            MakeDensityEstimator(settings, covered, coveredUv, coveredFlux, coveredBinning));
}

double UniformRelativeNoise(const EstimatorSettings& settings, double photonsPerArea) {
  const auto h2 = [&] { return double(SurfaceBandwidth(settings)) * SurfaceBandwidth(settings); };
  switch (settings.kind) {
    case EstimatorKind::kKernel: return std::sqrt(MomentsOf(settings.kernel).roughness / (photonsPerArea * h2()));
    case EstimatorKind::kHistogram: return 1.0 / std::sqrt(photonsPerArea * h2());
    case EstimatorKind::kNearest: return 1.0 / std::sqrt(std::max(1.0, double(settings.neighbours) - 2.0));
  }
  return INFINITY;
}

std::optional<EstimatorKind> ParseEstimator(std::string_view name) {
  return ParseName(name, kAllEstimators, EstimatorName);
}

std::string EstimatorName(EstimatorKind kind) {
  switch (kind) {
    case EstimatorKind::kKernel: return "kernel";
    case EstimatorKind::kHistogram: return "histogram";
    case EstimatorKind::kNearest: return "knn";
  }
  return "?";
}

std::string EstimatorNames() { return JoinNames(kAllEstimators, EstimatorName); }

}  // namespace pb
