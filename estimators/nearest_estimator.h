// Irradiance on one surface by the nearest-neighbour method (the paper's "Nearest neighbour methods"): the k
// photons nearest to x in the surface's (u,v) chart, of flux phi_j [W], lie in a disc of radius r_k [m]; then
//   H(x) = ((k - 1) / k) sum_j phi_j / A(x, r_k)   [W/m^2],
// with A the disc's area on the surface (edge-corrected) or pi r_k^2. The factor (k - 1)/k makes it unbiased
// where the photon density is locally constant: A(x, r_k) times that density is Gamma(k, 1) distributed, and
// E[1 / Gamma(k, 1)] = 1 / (k - 1) (Loftsgaarden and Quesenberry 1965). A surface with fewer than k photons
// gets its mean irradiance: total flux / surface area.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "estimators/density_estimator.h"
#include "estimators/surface_region.h"

namespace pb {

class NearestEstimator final : public DensityEstimator {
 public:
  NearestEstimator(std::span<const Point2> uv, std::span<const Rgb> flux, uint32_t k, const SurfaceRegion& region,
                   bool edgeCorrection);
  ~NearestEstimator() override;

  Rgb Estimate(Point2 x) const override;
  double RelativeNoise(Point2 x) const override;

 private:
  // The k nearest photons to x (fewer only when the tree holds fewer), nearest first; distance2 [m^2].
  size_t Search(Point2 x, std::vector<uint32_t>& index, std::vector<float>& distance2) const;
  struct Tree;
  uint32_t k_;
  const SurfaceRegion& region_;
  bool edgeCorrection_;
  std::vector<Point2> uv_;
  std::vector<Rgb> photonFlux_;
  Rgb surfaceMean_;             // total flux / surface area: the answer when there are fewer than k photons
  std::unique_ptr<Tree> tree_;  // nanoflann 2-d tree over uv_
};

}  // namespace pb
