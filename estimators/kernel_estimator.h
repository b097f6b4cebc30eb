// Irradiance on one surface by kernel density estimation (Shirley et al. 1995; the paper's "Kernel
// estimators"): H(x) = sum_j phi_j K_h(|x - x_j|) [W/m^2], over the surface's photon hits x_j in its (u,v)
// chart [m] with flux phi_j [W] each. Neighbours are found with a uniform grid of cells about h wide.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "estimators/kernels.h"
#include "mesh/color.h"
#include "mesh/geometry.h"

namespace pb {

class KernelEstimator {
 public:
  // h: bandwidth [m], > 0. The photon arrays are copied, reordered by cell.
  KernelEstimator(std::span<const Point2> uv, std::span<const Rgb> power, float h, Kernel kernel);

  // H at chart point x [W/m^2]. Sums in a fixed order, so the result is reproducible bit for bit.
  Rgb Estimate(Point2 x) const;

 private:
  int CellIndex(float coordinate, float lo, int count) const;

  float h_;
  Kernel kernel_;
  Point2 lo_{};
  float cellSize_ = 1;
  int nu_ = 0, nv_ = 0;
  std::vector<uint32_t> cellStart_;  // CSR: photons of cell c are [cellStart_[c], cellStart_[c+1])
  std::vector<Point2> uv_;
  std::vector<Rgb> power_;
};

}  // namespace pb
