// Irradiance H(x) [W/m^2] on one surface, estimated from the photon hits on it: positions x_j in the surface's
// (u,v) chart [m] and fluxes phi_j [W] (the paper's "Mesh generator algorithms"). The three classes the paper
// names, each boundary-corrected so that edges and corners of a uniformly lit surface read like its interior:
//   kernel     sum_j phi_j K_h(|x - x_j|) / M(x)            estimators/kernel_estimator.h
//   histogram  (flux in x's bucket of side h) / (bucket area on the surface)   estimators/histogram_estimator.h
//   knn        (k-1)/k (flux of the k nearest) / (area of their disc on the surface)   estimators/nearest_estimator.h
// M(x) is the kernel mass on the surface (estimators/surface_region.h). Where other geometry covers part of the
// surface, the covered part is a domain of its own (MakeCoveredDensityEstimator).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "estimators/estimator_settings.h"
#include "estimators/kernels.h"
#include "estimators/noisy_irradiance.h"
#include "estimators/surface_region.h"
#include "mesh/color.h"
#include "mesh/geometry.h"
#include "estimators/surface_cover.h"

namespace pb {


// Smallest kernel mass M(x) divided by: a corner sharper than about 11 degrees (M < 1/32) is corrected only as
// far as 1/32, so that a needle-thin corner cannot multiply a few photons into a spike.
inline constexpr double kMinEdgeMass = 1.0 / 32.0;

// The floor for M(x) on a surface of area A [m^2]: kMinEdgeMass of the most mass the surface could offer any
// point, min(1, A K_h(0)). When h is far above the surface's size every point sees only a small mass, and
// dividing by it is exact (the estimate becomes the surface's flux over its area), not a spike.
inline double MinimumKernelMass(double surfaceArea, Kernel kernel, float h) {
  return kMinEdgeMass * std::min(1.0, surfaceArea * double(KernelDensity(kernel, 0.0f, h)));
}

class DensityEstimator {
 public:
  virtual ~DensityEstimator() = default;
  // H [W/m^2] at x, a point of the surface's region. Reproducible bit for bit for the same photons.
  virtual Rgb Estimate(Point2 x) const = 0;
  // The relative standard deviation of Estimate(x)'s luminance, predicted from the photons it uses, as if their
  // positions were a Poisson process: sqrt(sum_j w_j^2) / sum_j w_j, with w_j photon j's luminance times its
  // weight in the estimate (knn: times sqrt(k / (k - 2)), its exact factor for equal fluxes). 0 when no photon
  // contributes. Dimensionless. The smoothing bias is not included.
  virtual double RelativeNoise(Point2 x) const = 0;
  // Both at once: the same H as Estimate(x), bit for bit, and its RelativeNoise(x). Estimators whose noise comes
  // from the same photons' sums override this to query them once.
  virtual NoisyIrradiance EstimateWithNoise(Point2 x) const { return {Estimate(x), RelativeNoise(x)}; }
};

// The noise model of the three estimators, in one place: the relative standard deviation of one estimate inside
// a surface where photons of equal flux land uniformly, `photonsPerArea` [1/m^2] of them. It is the expectation
// of DensityEstimator::RelativeNoise there:
//   kernel     sqrt(R(K) / (n h^2)), R(K) the kernel's roughness (estimators/kernels.h)
//   histogram  1 / sqrt(n h^2), the bucket's photon count
//   knn        1 / sqrt(k - 2), whatever n: more photons only shrink its disc
// Infinite for a kernel or histogram with n = 0; 0 for them as n grows without bound. Dimensionless.
double UniformRelativeNoise(const EstimatorSettings& settings, double photonsPerArea);

class BinnedPhotons;

// How a kernel estimate's photons are binned (estimators/kernel_estimator.h): on every surface wide enough
// (`wide`), else where they are dense, in node sums of flux unit `fluxUnit` [W] (0: from the photons); or
// already binned as they were traced (`traced`, which then replaces the photon arrays). Other estimators
// ignore it.
struct KernelBinning {
  bool wide = false;
  double fluxUnit = 0;
  const BinnedPhotons* traced = nullptr;
};

// `region` must outlive the estimator; the photon arrays are copied.
std::unique_ptr<DensityEstimator> MakeDensityEstimator(const EstimatorSettings& settings, const SurfaceRegion& region,
                                                       std::span<const Point2> uv, std::span<const Rgb> flux,
                                                       const KernelBinning& binning = {});

// The same on a surface part of which other geometry covers (estimators/surface_cover.h): two domains, the open region
// (the surface less the cover's pieces) and the covered one (the pieces), each estimated from the photons that
// landed in it, each edge-corrected over itself. A point is answered by the domain it lies in, so no light
// crosses the contact line. `open`, `covered` and `cover` must outlive the estimator.
std::unique_ptr<DensityEstimator> MakeCoveredDensityEstimator(const EstimatorSettings& settings, const SurfaceRegion& open,
                                                              const SurfaceRegion& covered, const SurfaceCover& cover,
                                                              std::span<const Point2> uv, std::span<const Rgb> flux,
                                                              const KernelBinning& openBinning = {}, const KernelBinning& coveredBinning = {});


}  // namespace pb
