// Photons binned onto a grid of nodes in a surface's (u,v) chart [m], by linear binning (Wand and Jones 1995,
// "Kernel Smoothing", ch. 3 appendix): each photon's flux phi [W] is shared among the four nodes about it by
// bilinear weights, and so is its squared luminance (for the estimate's noise) [W^2]. The kernel estimator sums
// these nodes instead of the photons (estimators/kernel_estimator.h).
//
// The sums are fixed point, integers in units of 2^-26 of a flux unit F [W] (the flux of the brightest photon at
// emission; F^2 for the squares), so adding is exact and order-free: photons binned as they are traced, by any
// number of threads in any order, give the same bytes as photons binned one by one in store order. Each share is
// rounded once, to 1.5e-8 of F (a float photon flux is exact to 6e-8 of itself); a node holds up to 2^37 F.
#pragma once

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <span>
#include <tuple>
#include <vector>

#include "mesh/color.h"
#include "mesh/geometry.h"

namespace pb {

// Nodes lo + (i, j) spacing, i in [0, nodesU), j in [0, nodesV), row by row.
struct NodeLattice {
  Point2 lo{};
  float spacing = 0;
  int nodesU = 0, nodesV = 0;

  // The lattice of spacing h / nodesPerH over `bounds`, one node beyond its far corner.
  static NodeLattice Over(Bounds2 bounds, float h, int nodesPerH);
  size_t Count() const { return size_t(nodesU) * size_t(nodesV); }
  // Calls share(node, weight) for the four nodes about fractional node coordinates (fu, fv), with their bilinear
  // weights, leaving out nodes beyond the lattice.
  template <typename Share>
  void ShareBilinear(double fu, double fv, Share share) const {
    const int iu = int(std::floor(fu)), iv = int(std::floor(fv));
    const double su = fu - iu, sv = fv - iv;
    const std::array<std::tuple<int, int, double>, 4> corners = {
        {{iu, iv, (1 - su) * (1 - sv)}, {iu + 1, iv, su * (1 - sv)}, {iu, iv + 1, (1 - su) * sv}, {iu + 1, iv + 1, su * sv}}};
    for (const auto& [i, j, w] : corners)
      if (i >= 0 && j >= 0 && i < nodesU && j < nodesV) share(size_t(j) * nodesU + i, w);
  }
  // The same about chart point uv.
  template <typename Share>
  void ShareAt(Point2 uv, Share share) const {
    ShareBilinear((double(uv.u) - lo.u) / spacing, (double(uv.v) - lo.v) / spacing, share);
  }
};

// The fixed-point sums of one surface's photons on a lattice. Add may be called from many threads at once.
class BinnedPhotons {
 public:
  // fluxUnit: F [W] above, > 0.
  BinnedPhotons(const NodeLattice& lattice, double fluxUnit);
  BinnedPhotons(const BinnedPhotons&) = delete;
  BinnedPhotons& operator=(const BinnedPhotons&) = delete;

  void Add(Point2 uv, Rgb flux);
  // Asks the memory for the nodes Add(uv, ...) will touch. Adds are atomic, and an atomic add that misses the cache
  // stalls the thread until its line arrives: prefetched a few photons ahead, the misses overlap instead.
  void Prefetch(Point2 uv) const;
  const NodeLattice& Lattice() const { return lattice_; }
  uint64_t Photons() const { return photons_.load(std::memory_order_relaxed); }
  // Node n's flux [W], and the sum of its shares of the photons' squared luminance in units of `unit`^2 (a power
  // of two near the photons' flux keeps it within float's range, where W^2 overflows above 10^19 W a photon).
  Rgb Flux(size_t n) const;
  float Squares(size_t n, double unit = 1) const;
  double FluxUnit() const { return unit_ * kUnitsPerFlux; }  // F [W]

  static constexpr double kUnitsPerFlux = 67108864.0;  // 2^26

  // The integer sums, four per node (r, g, b, squares), and the photon count, for adding other processes' sums
  // (baker/distribution.h). Not while photons are being added.
  std::span<int64_t> Units() { return {sums_.front().data(), 4 * sums_.size()}; }
  void SetPhotons(uint64_t photons) { photons_.store(photons, std::memory_order_relaxed); }

 private:
  NodeLattice lattice_;
  double unit_, squareUnit_;                    // [W], [W^2] per integer step
  std::vector<std::array<int64_t, 4>> sums_;    // r, g, b, squares
  std::atomic<uint64_t> photons_{0};
};

// A fixed-point flux total (the flux of a surface's hits [W]), exact and order-free in the same units.
struct FluxTally {
  std::array<int64_t, 3> units{};
  void Add(Rgb flux, double fluxUnit);  // not thread-safe
  void Add(const FluxTally& other);
  Rgb ToRgb(double fluxUnit) const;
};

}  // namespace pb
