// Irradiance on one surface by kernel density estimation (Shirley et al. 1995; the paper's "Kernel
// estimators"): H(x) = sum_j phi_j K_h(|x - x_j|) / M(x) [W/m^2], over the surface's photon hits x_j in its
// (u,v) chart [m] with flux phi_j [W] each. M(x) is the kernel's mass on the surface (renormalisation boundary
// correction, Jones 1993), or 1 without correction. Neighbours are found with a uniform grid of cells about h
// wide.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "estimators/density_estimator.h"
#include "estimators/kernels.h"
#include "estimators/surface_region.h"
#include "mesh/color.h"
#include "mesh/geometry.h"

namespace pb {

class KernelEstimator final : public DensityEstimator {
 public:
  // h: bandwidth [m], > 0. The photon arrays are copied, reordered by cell. `correction`: the surface's region
  // for boundary correction (must outlive this), or null for none.
  KernelEstimator(std::span<const Point2> uv, std::span<const Rgb> flux, float h, Kernel kernel,
                  const SurfaceRegion* correction);

  // H at chart point x [W/m^2]. Sums in a fixed order, so the result is reproducible bit for bit.
  Rgb Estimate(Point2 x) const override;
  double RelativeNoise(Point2 x) const override;
  WithNoise EstimateWithNoise(Point2 x) const override;

 private:
  int CellIndex(float coordinate, float lo, int count) const;
  // Calls visit(begin, end) with the photon range of each grid cell within h of x, in a fixed order.
  template <typename Visit>
  void ForEachCellNear(Point2 x, Visit visit) const;
  // Sums of w_j = luminance(phi_j) k_j and of w_j^2, for RelativeNoise.
  struct NoiseSums {
    double sum = 0, squares = 0;
    double Relative() const { return sum > 0 ? std::sqrt(squares) / sum : 0.0; }
  };
  // sum_j phi_j k(r_j^2 / h^2) over the photons within h of x; with kNoise, also the noise sums.
  template <bool kNoise, typename Profile>
  Rgb ProfileSum(Point2 x, Profile profile, NoiseSums& noise) const;
  template <bool kNoise>
  Rgb KernelSum(Point2 x, NoiseSums& noise) const;
  Rgb Normalised(Rgb profileSum, Point2 x) const;  // times 1/h^2 and 1/M(x)

  float h_;
  Kernel kernel_;
  const SurfaceRegion* correction_;
  double minimumMass_ = kMinEdgeMass;  // MinimumKernelMass of the corrected surface
  Point2 lo_{};
  float cellSize_ = 1;
  int nu_ = 0, nv_ = 0;
  std::vector<uint32_t> cellStart_;  // CSR: photons of cell c are [cellStart_[c], cellStart_[c+1])
  std::vector<Point2> uv_;
  std::vector<Rgb> photonFlux_;
};

}  // namespace pb
