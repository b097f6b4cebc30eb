// The pilot histogram from which a surface's automatic h is chosen (estimators/bandwidth.h): a grid of n x n square
// cells over the surface's chart bounds (u,v) [m], n a power of two from 4 to 64 with about 400 photons a cell, and
// per cell the sums of its photons' luminance flux [W] and of its square [W^2].
//
// The sums are fixed point, as the kernel's node sums are (estimators/binned_photons.h): integers in units of
// 2^-26 F for the flux and of F^2 / 2^k for the squares, F the bake's flux unit [W] and k as large as keeps the
// sum of the count's squares of F within an int64 (40 up to 4M photons on the surface, 35 at 100M), so that each
// photon's share is rounded once and adding is exact and order-free. The processes of a distributed bake can each
// add their own photons to a pilot of the surface's whole count and sum the integers: every one then holds the
// pilot, and chooses the h, of a single process.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "estimators/surface_region.h"
#include "mesh/color.h"
#include "mesh/geometry.h"

namespace pb {

class PilotHistogram {
 public:
  static constexpr double kPhotonsPerCell = 400;
  // The pilot of `photons` photons (the surface's whole count, which sets n) on `region`, its sums 0; fluxUnit: F
  // [W], > 0. The region must outlive the pilot.
  PilotHistogram(const SurfaceRegion& region, uint64_t photons, double fluxUnit);
  // The pilot of these photons, all of them.
  static PilotHistogram Of(const SurfaceRegion& region, std::span<const Point2> uv, std::span<const Rgb> flux,
                           double fluxUnit);

  // One photon at chart point uv carrying `flux` (its luminance is summed). Not thread-safe.
  void Add(Point2 uv, Rgb flux);
  // The integer sums, the flux's then the squares', for adding other processes' (baker/distribution.h).
  std::span<int64_t> Units() { return units_; }
  std::span<const int64_t> Units() const { return units_; }

  const SurfaceRegion& Region() const { return region_; }
  uint64_t Photons() const { return photons_; }
  int CellsPerAxis() const { return n_; }
  double Side() const { return side_; }  // a cell's side [m]
  // Cell (i, j)'s sums, row by row: c = j n + i.
  double Flux(size_t c) const { return double(units_[c]) * fluxStep_; }              // [W]
  double Squares(size_t c) const { return double(units_[cells_ + c]) * squareStep_; }  // [W^2]

 private:
  const SurfaceRegion& region_;
  uint64_t photons_;
  int n_;
  size_t cells_;
  double side_, fluxStep_, squareStep_;
  std::vector<int64_t> units_;  // flux then squares, cells_ each
};

}  // namespace pb
