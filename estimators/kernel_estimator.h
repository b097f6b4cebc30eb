// Irradiance on one surface by kernel density estimation (Shirley et al. 1995; the paper's "Kernel
// estimators"): H(x) = sum_j phi_j K_h(|x - x_j|) / M(x) [W/m^2], over the surface's photon hits x_j in its
// (u,v) chart [m] with flux phi_j [W] each. M(x) is the kernel's mass on the surface (renormalisation boundary
// correction, Jones 1993), or 1 without correction. Neighbours are found with a uniform grid of cells about h
// wide.
//
// Near the surface's boundary (an edge, a corner, a contact line) renormalisation leaves a first-order bias where
// H has a gradient across it, about 0.34 h |grad H| at a straight edge. Local linear density estimation (Walter,
// Hubbard, Shirley and Greenberg 1997, "Global illumination using local linear density estimation", ACM TOG
// 16(3); the boundary kernels of Jones 1993) removes it: the estimate is the intercept of a kernel-weighted
// linear fit, which is exact for any H linear over the kernel's part of the surface:
//   H(x) = sum_j phi_j K_h(d_j) (1 - c . d_j / h) / (m0 - c . m1),   c = m2^-1 m1,   d_j = x_j - x,
// with m0, m1 and m2 the kernel's mass, first and second moments over the surface (SurfaceRegion::Moments).
// Inside the surface m1 = 0 and it is the plain estimate. Where the fit is ill-conditioned (m0 - c . m1 below
// 1% of m0, a needle-sharp corner) renormalisation is used instead. Negative channels (possible with weights
// 1 - c . d_j < 0 on steep light) are clamped to 0.
//
// Dense photons are binned (Binning::kAuto): where a surface holds at least kBinnedPhotonsPerNode photons per
// node of a grid of spacing h / kNodesPerH, each photon's flux is shared among the four nodes around it by
// bilinear weights (linear binning; Wand and Jones 1995, "Kernel Smoothing", ch. 3 appendix), and the sums run
// over the nodes within h instead of the photons: sum_n W_n k(n - x). That is the exact sum with each photon's
// kernel value replaced by its bilinear interpolation from the nodes, so the error is second order in the
// spacing and the cost per point is about pi kNodesPerH^2 nodes, whatever the photon density. The boundary
// correction's mass and moments then come from the surface's coverage mask binned onto the same nodes (its exact
// area per half-spacing cell, SurfaceRegion::GridOverlapAreas), not from the boundary integral: numerator and
// denominator share the binning's error, which then cancels, and no boundary edge is visited per point. The noise
// sums use each node's share of the photons' squared luminance. The photon arrays are not kept. Kernels that step
// at their rim (uniform, the truncated Gaussian) are not binned: their error would be first order. A surface
// narrower than 2 h would have too few nodes across for the fit at its edges: it is binned on a lattice of a
// quarter of its width instead (kAuto; kWide leaves it unbinned). The node sums are fixed point
// (estimators/binned_photons.h), so photons binned as they were traced (the second constructor) give the same
// estimator, bit for bit, as the same photons listed; Binning::kWide bins every surface that can be, whatever its
// density, as a bake that bins while tracing does.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "estimators/binned_photons.h"
#include "estimators/density_estimator.h"
#include "estimators/kernels.h"
#include "estimators/surface_region.h"
#include "mesh/color.h"
#include "mesh/geometry.h"

namespace pb {

class KernelEstimator final : public DensityEstimator {
 public:
  // kAuto: dense photons on a wide surface; kWide: every wide surface; kExact: none; kBinned: every surface.
  enum class Binning { kAuto, kWide, kExact, kBinned };
  static constexpr int kNodesPerH = 8;
  static constexpr double kBinnedPhotonsPerNode = 2.0;

  // h: bandwidth [m], > 0. The photon arrays are copied, reordered by cell. `correction`: the surface's region
  // for boundary correction (must outlive this), or null for none.
  // `localLinear`: at the boundary, fit locally linear (above) rather than only renormalise.
  // `binning`: as above. `fluxUnit`: of the node sums (estimators/binned_photons.h), or 0 for the brightest
  // photon's largest channel.
  KernelEstimator(std::span<const Point2> uv, std::span<const Rgb> flux, float h, Kernel kernel,
                  const SurfaceRegion* correction, bool localLinear = false, Binning binning = Binning::kAuto,
                  double fluxUnit = 0);
  // From photons binned as they were traced, on WideLattice(kernel, *correction, h).
  KernelEstimator(const BinnedPhotons& binned, float h, Kernel kernel, const SurfaceRegion& correction, bool localLinear);
  bool Binned() const { return !nodeFlux_.empty(); }

  // The lattice a surface of region `region` is binned on whatever its photons' density (Binning::kWide), or none
  // when its kernel or its width rules binning out.
  static std::optional<NodeLattice> WideLattice(Kernel kernel, const SurfaceRegion& region, float h);

  // H at chart point x [W/m^2]. Sums in a fixed order, so the result is reproducible bit for bit.
  Rgb Estimate(Point2 x) const override;
  double RelativeNoise(Point2 x) const override;
  NoisyIrradiance EstimateWithNoise(Point2 x) const override;

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
  // The local linear fit at x: c = m2^-1 m1 and the denominator m0 - c . m1; nothing inside the surface or where
  // the fit is ill-conditioned.
  struct LinearFit {
    float cu = 0, cv = 0;
    double denominator = 1;
  };
  std::optional<LinearFit> LinearFitAt(Point2 x) const;
  // sum_j phi_j k(r_j^2 / h^2) over the photons within h of x, each times 1 - c . d_j / h with kLinear; with
  // kNoise, also the noise sums of those weights.
  template <bool kNoise, bool kLinear, typename Profile>
  Rgb ProfileSum(Point2 x, Profile profile, NoiseSums& noise, LinearFit fit) const;
  // Binned: the grid of nodes, the coverage mask, and H with its noise from them.
  void Bin(std::span<const Point2> uv, std::span<const Rgb> flux, const NodeLattice& lattice, double fluxUnit);
  void TakeNodes(const BinnedPhotons& binned);
  void BinCoverage();
  NodeLattice Nodes() const { return {lo_, spacing_, nodesU_, nodesV_}; }
  // A node's coverage when the surface covers its whole tent (less rounding).
  float WholeNodeArea() const { return 0.999f * spacing_ * spacing_; }
  template <bool kNoise, typename Profile>
  NoisyIrradiance EvaluateBinned(Point2 x, Profile profile) const;
  // The binned sums at x, offsets (a, b) = (n - x) / h: of the flux W_n k_n times 1, a and b; of the coverage
  // A_n k_n times 1, a, b, aa, ab, bb (the kernel's moments on the surface, times h^2); and of the photons'
  // squared luminance Q_n k_n^2 times the same six, for the noise of the linear fit's weights.
  struct NodeSums {
    RgbSum flux, fluxA, fluxB;
    std::array<double, 6> mass{}, squares{};
  };
  template <bool kNoise, bool kEdge, typename Profile>
  NodeSums SumNodes(Point2 x, Profile profile, bool& partial) const;
  bool NearEdge(Point2 x) const;
  // The nodes of the square about x, h on each side: {u0, u1, v0, v1}, inclusive (empty when u0 > u1 or v0 > v1).
  std::array<int, 4> NodesNear(Point2 x) const;
  // H and its noise at x (the noise sums only with kNoise).
  template <bool kNoise>
  NoisyIrradiance Evaluate(Point2 x) const;
  template <bool kNoise>
  Rgb KernelSum(Point2 x, NoiseSums& noise) const;
  Rgb Normalised(Rgb profileSum, Point2 x) const;  // times 1/h^2 and 1/M(x)

  float h_;
  Kernel kernel_;
  const SurfaceRegion* correction_;
  bool localLinear_ = true;
  double minimumMass_ = kMinEdgeMass;  // MinimumKernelMass of the corrected surface
  Point2 lo_{};
  float cellSize_ = 1;
  int nu_ = 0, nv_ = 0;
  std::vector<uint32_t> cellStart_;  // CSR: photons of cell c are [cellStart_[c], cellStart_[c+1])
  std::vector<Point2> uv_;
  std::vector<Rgb> photonFlux_;
  // Binned: nodes lo_ + (i, j) spacing_, i in [0, nodesU_), j in [0, nodesV_), row by row.
  bool empty_ = true;
  float spacing_ = 0;
  int nodesU_ = 0, nodesV_ = 0;
  std::vector<Rgb> nodeFlux_;        // [W]
  std::vector<float> nodeSquares_;   // sum of the bilinear share times luminance(phi_j)^2 [noiseUnit_^2]
  // The noise sums' unit [W]: a power of two near the brightest photon, so that the sums of squared flux stay
  // within float's range at any light power (10^30 W: 10^48 W^2), and their ratios keep every bit.
  double noiseUnit_ = 1;
  std::vector<float> nodeArea_;      // A_n [m^2]: the surface's area binned to node n (with a correction)
  std::vector<uint32_t> partialTable_;  // summed-area table of the nodes not wholly on the surface, (nu+1) x (nv+1)
};

}  // namespace pb
