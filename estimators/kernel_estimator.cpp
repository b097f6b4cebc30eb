#include "estimators/kernel_estimator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <utility>

#include "mesh/errors.h"

namespace pb {
namespace {
// Cap on grid cells per photon, so that a tiny h on a large, sparsely hit surface cannot exhaust memory;
// cells then grow beyond h and each query scans more of them.
constexpr double kMaxCellsPerPhoton = 4.0;
constexpr double kMinCellBudget = 1 << 12;
}  // namespace

namespace {
// A kernel with a step at its rim (uniform, the truncated Gaussian) is binned only on request: its binning error is
// first order in the spacing (1.4% for the Gaussian), not second.
bool SmoothRim(Kernel kernel) { return kernel != Kernel::kUniform && kernel != Kernel::kGaussian; }
// Nor is a surface narrower than 2 h on the lattice of h: its nodes would be too few across it for the fit at its
// edges.
float Width(Bounds2 b) { return std::min(b.hi.u - b.lo.u, b.hi.v - b.lo.v); }
bool Wide(Bounds2 b, float h) { return Width(b) >= 2 * h; }

// The brightest photon's largest channel [W] (1 when there is none).
double BrightestChannel(std::span<const Rgb> flux) {
  float brightest = 0;
  for (const Rgb& f : flux) brightest = std::max(brightest, f.Max());
  return brightest > 0 ? brightest : 1.0;
}

// The power of two at or below `flux` [W], within 2^+-100 so that its inverse is a float too: scaling by it is
// exact.
double PowerOfTwoBelow(double flux) { return std::ldexp(1.0, std::clamp(std::ilogb(flux), -100, 100)); }
}  // namespace

std::optional<NodeLattice> KernelEstimator::WideLattice(Kernel kernel, const SurfaceRegion& region, float h) {
  if (!SmoothRim(kernel) || !Wide(region.Bounds(), h)) return std::nullopt;
  return NodeLattice::Over(region.Bounds(), h, kNodesPerH);
}

KernelEstimator::KernelEstimator(std::span<const Point2> uv, std::span<const Rgb> flux, float h, Kernel kernel,
                                 const SurfaceRegion* correction, bool localLinear, Binning binning, double fluxUnit)
    : h_(h), kernel_(kernel), correction_(correction), localLinear_(localLinear),
      minimumMass_(correction ? MinimumKernelMass(correction->Area(), kernel, h) : kMinEdgeMass) {
  PB_CHECK(h > 0 && std::isfinite(h), "bandwidth is positive and finite");
  PB_CHECK_EQ(uv.size(), flux.size());  // one flux per photon
  if (uv.empty()) return;
  empty_ = false;
  Bounds2 bounds;
  for (const Point2& p : uv) bounds.Extend(p);
  // The nodes span the surface, so that its coverage mask is whole (its photons lie on it).
  const Bounds2 grid = correction != nullptr ? correction->Bounds() : bounds;
  // Where photons are dense (kAuto), a surface narrower than 2 h is binned on the lattice of a quarter of its
  // width, twice as many nodes across it as a wide surface has across 2 h (its edges' fit is what the spacing
  // costs: 0.14% at most on a 1 m square at h = 0.8 m, 0.51% at half the width): a kernel as wide as the surface (h
  // from few photons) then sums more nodes per point than usual, still far fewer than the photons that it would
  // otherwise sum one by one (the office's floor at 250,000 photons, h = 4.4 m: draft 2.8 s -> 1.2 s). A bake
  // binning while traced plans the lattices of h.
  const bool wide = Wide(grid, h), narrow = !wide && binning == Binning::kAuto && Width(grid) > 0;
  const NodeLattice lattice = NodeLattice::Over(grid, narrow ? 0.25f * Width(grid) : h, kNodesPerH);
  const bool binnable = SmoothRim(kernel) && (wide || narrow);
  const bool dense = double(uv.size()) >= kBinnedPhotonsPerNode * double(lattice.Count());
  if (binning == Binning::kBinned || (binnable && (binning == Binning::kWide || (binning == Binning::kAuto && dense)))) {
    Bin(uv, flux, lattice, fluxUnit > 0 ? fluxUnit : BrightestChannel(flux));
    if (correction_ != nullptr) BinCoverage();
    return;
  }
  const double su = double(bounds.hi.u) - bounds.lo.u, sv = double(bounds.hi.v) - bounds.lo.v;
  double cell = h;
  const double budget = std::max(kMinCellBudget, kMaxCellsPerPhoton * double(uv.size()));
  while ((su / cell + 1) * (sv / cell + 1) > budget) cell *= 2;
  cellSize_ = float(cell);
  lo_ = bounds.lo;
  nu_ = int(su / cell) + 1;
  nv_ = int(sv / cell) + 1;

  // Counting sort by cell: stable, so photons within a cell stay in input order.
  std::vector<uint32_t> cellOf(uv.size());
  cellStart_.assign(size_t(nu_) * nv_ + 1, 0);
  for (size_t i = 0; i < uv.size(); ++i) {
    cellOf[i] = uint32_t(CellIndex(uv[i].v, lo_.v, nv_) * nu_ + CellIndex(uv[i].u, lo_.u, nu_));
    ++cellStart_[cellOf[i] + 1];
  }
  for (size_t c = 1; c < cellStart_.size(); ++c) cellStart_[c] += cellStart_[c - 1];
  std::vector<uint32_t> cursor(cellStart_.begin(), cellStart_.end() - 1);
  noiseUnit_ = PowerOfTwoBelow(BrightestChannel(flux));
  uv_.resize(uv.size());
  photonFlux_.resize(uv.size());
  for (size_t i = 0; i < uv.size(); ++i) {
    const uint32_t slot = cursor[cellOf[i]]++;
    uv_[slot] = uv[i];
    photonFlux_[slot] = flux[i];
  }
}

KernelEstimator::KernelEstimator(const BinnedPhotons& binned, float h, Kernel kernel, const SurfaceRegion& correction,
                                 bool localLinear)
    : h_(h), kernel_(kernel), correction_(&correction), localLinear_(localLinear),
      minimumMass_(MinimumKernelMass(correction.Area(), kernel, h)) {
  PB_CHECK(h > 0 && std::isfinite(h), "bandwidth is positive and finite");
  if (binned.Photons() == 0) return;
  empty_ = false;
  TakeNodes(binned);
  BinCoverage();
}

void KernelEstimator::Bin(std::span<const Point2> uv, std::span<const Rgb> flux, const NodeLattice& lattice, double fluxUnit) {
  BinnedPhotons binned(lattice, fluxUnit);
  for (size_t j = 0; j < uv.size(); ++j) binned.Add(uv[j], flux[j]);
  TakeNodes(binned);
}

void KernelEstimator::TakeNodes(const BinnedPhotons& binned) {
  const NodeLattice& lattice = binned.Lattice();
  lo_ = lattice.lo, spacing_ = lattice.spacing, nodesU_ = lattice.nodesU, nodesV_ = lattice.nodesV;
  nodeFlux_.resize(lattice.Count());
  nodeSquares_.resize(lattice.Count());
  noiseUnit_ = PowerOfTwoBelow(binned.FluxUnit());
  for (size_t n = 0; n < lattice.Count(); ++n)
    nodeFlux_[n] = binned.Flux(n), nodeSquares_[n] = binned.Squares(n, noiseUnit_);
}

// The coverage mask, binned like the photons: the surface's area in each cell of a grid of side spacing / 2 (exact,
// SurfaceRegion::GridOverlapAreas, holes removed), shared among the four nodes about the cell's centre.
void KernelEstimator::BinCoverage() {
  const float side = 0.5f * spacing_;
  const Point2 origin{lo_.u - spacing_, lo_.v - spacing_};
  const int cu = 2 * nodesU_ + 2, cv = 2 * nodesV_ + 2;
  const std::vector<double> areas = correction_->GridOverlapAreas(origin, side, cu, cv);
  const NodeLattice nodes = Nodes();
  std::vector<double> shares(nodes.Count(), 0.0);
  for (int b = 0; b < cv; ++b)
    for (int a = 0; a < cu; ++a) {
      const double area = areas[size_t(b) * cu + a];
      if (area <= 0) continue;
      // The centre, in node units from lo_.
      nodes.ShareBilinear((a + 0.5) * 0.5 - 1, (b + 0.5) * 0.5 - 1, [&](size_t n, double w) { shares[n] += w * area; });
    }
  nodeArea_.assign(shares.begin(), shares.end());
  const float whole = WholeNodeArea();
  const size_t row = size_t(nodesU_) + 1;
  partialTable_.assign(row * (size_t(nodesV_) + 1), 0);
  for (int j = 0; j < nodesV_; ++j)
    for (int i = 0; i < nodesU_; ++i) {
      const uint32_t partial = nodeArea_[size_t(j) * nodesU_ + i] < whole ? 1 : 0;
      partialTable_[size_t(j + 1) * row + i + 1] = partial + partialTable_[size_t(j) * row + i + 1] +
                                                   partialTable_[size_t(j + 1) * row + i] - partialTable_[size_t(j) * row + i];
    }
}

namespace {

// Adds w times 1, a, b, aa, ab, bb.
void AddMoments(std::array<float, 6>& into, float w, float a, float b) {
  into[0] += w, into[1] += w * a, into[2] += w * b;
  into[3] += w * a * a, into[4] += w * a * b, into[5] += w * b * b;
}

}  // namespace

std::array<int, 4> KernelEstimator::NodesNear(Point2 x) const {
  return {std::max(0, int(std::ceil((x.u - h_ - lo_.u) / spacing_))),
          std::min(nodesU_ - 1, int(std::floor((x.u + h_ - lo_.u) / spacing_))),
          std::max(0, int(std::ceil((x.v - h_ - lo_.v) / spacing_))),
          std::min(nodesV_ - 1, int(std::floor((x.v + h_ - lo_.v) / spacing_)))};
}

// The node sums over the nodes within h of x (kEdge: every moment; else the flux, the mass and the noise's first
// terms only), in float within a row and in double across rows. `partial` is set when some node within h is not
// wholly on the surface.
template <bool kNoise, bool kEdge, typename Profile>
KernelEstimator::NodeSums KernelEstimator::SumNodes(Point2 x, Profile profile, bool& partial) const {
  const float inverseH2 = 1.0f / (h_ * h_), inverseH = 1.0f / h_;
  const auto [u0, u1, v0, v1] = NodesNear(x);
  const bool corrected = !nodeArea_.empty();
  const float whole = WholeNodeArea();
  NodeSums s;
  for (int j = v0; j <= v1; ++j) {
    const float dv = lo_.v + float(j) * spacing_ - x.v, b = dv * inverseH;
    Rgb flux, fluxA, fluxB;
    std::array<float, 6> mass{}, squares{};
    for (int i = u0; i <= u1; ++i) {
      const float du = lo_.u + float(i) * spacing_ - x.u;
      const float t2 = (du * du + dv * dv) * inverseH2;
      if (t2 >= 1.0f) continue;
      const float k = profile(t2);
      const size_t n = size_t(j) * nodesU_ + i;
      const Rgb w = nodeFlux_[n] * k;
      flux += w;
      if constexpr (kEdge) {
        const float a = du * inverseH;
        fluxA += w * a, fluxB += w * b;
        if (corrected) AddMoments(mass, nodeArea_[n] * k, a, b), partial |= nodeArea_[n] < whole;
        if constexpr (kNoise) AddMoments(squares, nodeSquares_[n] * k * k, a, b);
      } else {
        if (corrected) mass[0] += nodeArea_[n] * k;
        if constexpr (kNoise) squares[0] += nodeSquares_[n] * k * k;
      }
    }
    s.flux.Add(flux), s.fluxA.Add(fluxA), s.fluxB.Add(fluxB);
    for (int m = 0; m < 6; ++m) s.mass[m] += mass[m], s.squares[m] += squares[m];
  }
  return s;
}

// Whether a node of the square of nodes about x, h on each side, is not wholly on the surface: O(1), from the
// summed-area table of such nodes.
bool KernelEstimator::NearEdge(Point2 x) const {
  const auto [u0, u1, v0, v1] = NodesNear(x);
  if (u0 > u1 || v0 > v1) return false;
  const size_t row = size_t(nodesU_) + 1;
  const auto at = [&](int i, int j) { return partialTable_[size_t(j) * row + size_t(i)]; };
  return at(u1 + 1, v1 + 1) - at(u0, v1 + 1) - at(u1 + 1, v0) + at(u0, v0) > 0;
}

// Binned: the renormalised or local linear estimate from the node sums, with the kernel's moments taken over the
// binned coverage mask rather than the exact boundary integral, so that numerator and denominator share the
// binning's error and it cancels (an exact denominator left the fit 4% off at corners). Far from the edges only
// the flux and the mass are summed.
template <bool kNoise, typename Profile>
NoisyIrradiance KernelEstimator::EvaluateBinned(Point2 x, Profile profile) const {
  const double inverseH2 = 1.0 / (double(h_) * h_);
  const bool corrected = correction_ != nullptr;
  bool partial = false;
  const bool edge = corrected && localLinear_ && NearEdge(x);
  const NodeSums s = edge ? SumNodes<kNoise, true>(x, profile, partial) : SumNodes<kNoise, false>(x, profile, partial);
  const Rgb flux = s.flux.ToRgb();
  const auto noiseOf = [&](double sum, double squares) {  // sum [W], squares [noiseUnit_^2]
    return kNoise && sum > 0 ? std::sqrt(std::max(squares, 0.0)) / (sum / noiseUnit_) : 0.0;
  };
  if (!corrected) return {flux * float(inverseH2), noiseOf(Luminance(flux), s.squares[0])};
  const std::array<double, 6>& m = s.mass;  // times h^2
  const double det = m[3] * m[5] - m[4] * m[4];
  const double minimum = minimumMass_ / inverseH2;
  if (partial && det > 0 && m[0] >= minimum) {  // inside, the fit is the plain estimate
    const double cu = (m[5] * m[1] - m[4] * m[2]) / det, cv = (m[3] * m[2] - m[4] * m[1]) / det;
    const double denominator = m[0] - (cu * m[1] + cv * m[2]);
    if (denominator > 0.01 * m[0]) {
      const Rgb a = s.fluxA.ToRgb(), b = s.fluxB.ToRgb();
      const auto channel = [&](float f, float fa, float fb) { return std::max(float((f - cu * fa - cv * fb) / denominator), 0.0f); };
      const Rgb h{channel(flux.r, a.r, b.r), channel(flux.g, a.g, b.g), channel(flux.b, a.b, b.b)};
      const std::array<double, 6>& q = s.squares;
      const double squares = q[0] - 2 * (cu * q[1] + cv * q[2]) + cu * cu * q[3] + 2 * cu * cv * q[4] + cv * cv * q[5];
      return {h, noiseOf(Luminance(flux) - cu * Luminance(a) - cv * Luminance(b), squares)};
    }
  }
  return {flux * float(1.0 / std::max(m[0], minimum)), noiseOf(Luminance(flux), s.squares[0])};
}

int KernelEstimator::CellIndex(float coordinate, float lo, int count) const {
  return std::clamp(int(std::floor((coordinate - lo) / cellSize_)), 0, count - 1);
}

Rgb KernelEstimator::Estimate(Point2 x) const { return Evaluate<false>(x).irradiance; }

// The kernel mass M(x) (or the fit's denominator) cancels in the ratio, as does 1/h^2.
double KernelEstimator::RelativeNoise(Point2 x) const { return Evaluate<true>(x).relativeNoise; }

NoisyIrradiance KernelEstimator::EstimateWithNoise(Point2 x) const { return Evaluate<true>(x); }

template <bool kNoise>
NoisyIrradiance KernelEstimator::Evaluate(Point2 x) const {
  if (Binned()) return WithSquaredProfile(kernel_, [&](auto profile) { return EvaluateBinned<kNoise>(x, profile); });
  NoiseSums noise;
  if (const std::optional<LinearFit> fit = LinearFitAt(x)) {
    const Rgb sum = WithSquaredProfile(kernel_, [&](auto profile) { return ProfileSum<kNoise, true>(x, profile, noise, *fit); });
    const float scale = float(1.0 / (double(h_) * h_ * fit->denominator));
    return {{std::max(sum.r * scale, 0.0f), std::max(sum.g * scale, 0.0f), std::max(sum.b * scale, 0.0f)}, noise.Relative()};
  }
  const Rgb sum = KernelSum<kNoise>(x, noise);
  return {Normalised(sum, x), noise.Relative()};
}

std::optional<KernelEstimator::LinearFit> KernelEstimator::LinearFitAt(Point2 x) const {
  if (!localLinear_ || correction_ == nullptr || empty_) return std::nullopt;
  const KernelMomentsAt m = correction_->Moments(x, kernel_, h_);
  if (m.first[0] == 0 && m.first[1] == 0) return std::nullopt;  // inside: the plain estimate
  const double det = m.second[0] * m.second[2] - m.second[1] * m.second[1];
  if (!(det > 0) || m.mass < minimumMass_) return std::nullopt;
  const double cu = (m.second[2] * m.first[0] - m.second[1] * m.first[1]) / det;
  const double cv = (m.second[0] * m.first[1] - m.second[1] * m.first[0]) / det;
  const double denominator = m.mass - (cu * m.first[0] + cv * m.first[1]);
  if (!(denominator > 0.01 * m.mass)) return std::nullopt;  // ill-conditioned: renormalise
  return LinearFit{float(cu), float(cv), denominator};
}

Rgb KernelEstimator::Normalised(Rgb profileSum, Point2 x) const {
  if (empty_) return {};
  const Rgb sum = profileSum * (1.0f / (h_ * h_));
  if (correction_ == nullptr) return sum;
  return sum * float(1.0 / std::max(correction_->KernelMass(x, kernel_, h_), minimumMass_));
}

template <bool kNoise>
Rgb KernelEstimator::KernelSum(Point2 x, NoiseSums& noise) const {
  if (empty_) return {};
  return WithSquaredProfile(kernel_, [&](auto profile) { return ProfileSum<kNoise, false>(x, profile, noise, {}); });
}

template <typename Visit>
void KernelEstimator::ForEachCellNear(Point2 x, Visit visit) const {
  const int u0 = int(std::floor((x.u - h_ - lo_.u) / cellSize_)), u1 = int(std::floor((x.u + h_ - lo_.u) / cellSize_));
  const int v0 = int(std::floor((x.v - h_ - lo_.v) / cellSize_)), v1 = int(std::floor((x.v + h_ - lo_.v) / cellSize_));
  for (int cv = std::max(v0, 0); cv <= std::min(v1, nv_ - 1); ++cv)
    for (int cu = std::max(u0, 0); cu <= std::min(u1, nu_ - 1); ++cu) {
      const size_t c = size_t(cv) * nu_ + cu;
      visit(cellStart_[c], cellStart_[c + 1]);
    }
}

// In cell order: in float within a cell (a few hundred terms), in double across cells. The noise sums do not
// touch the flux sum, so Estimate and EstimateWithNoise agree bit for bit.
template <bool kNoise, bool kLinear, typename Profile>
Rgb KernelEstimator::ProfileSum(Point2 x, Profile profile, NoiseSums& noise, LinearFit fit) const {
  const float inverseH2 = 1.0f / (h_ * h_), inverseH = 1.0f / h_, inNoiseUnits = float(1 / noiseUnit_);
  RgbSum sum;
  ForEachCellNear(x, [&](uint32_t begin, uint32_t end) {
    Rgb cell;
    float cellSum = 0, cellSquares = 0;  // noise sums, in float within a cell like the flux
    for (uint32_t i = begin; i < end; ++i) {
      const float t2 = LengthSquared(uv_[i] - x) * inverseH2;
      if (t2 >= 1.0f) continue;
      float k = profile(t2);
      if constexpr (kLinear) k *= 1.0f - (fit.cu * (uv_[i].u - x.u) + fit.cv * (uv_[i].v - x.v)) * inverseH;
      cell += photonFlux_[i] * k;
      if constexpr (kNoise) {
        const float w = Luminance(photonFlux_[i]) * k * inNoiseUnits;
        cellSum += w;
        cellSquares += w * w;
      }
    }
    sum.Add(cell);
    if constexpr (kNoise) {
      noise.sum += cellSum;
      noise.squares += cellSquares;
    }
  });
  return sum.ToRgb();
}

}  // namespace pb
