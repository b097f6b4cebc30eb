#include "estimators/kernel_estimator.h"

#include <algorithm>
#include <cmath>

#include "mesh/errors.h"

namespace pb {
namespace {
// Cap on grid cells per photon, so that a tiny h on a large, sparsely hit surface cannot exhaust memory;
// cells then grow beyond h and each query scans more of them.
constexpr double kMaxCellsPerPhoton = 4.0;
constexpr double kMinCellBudget = 1 << 12;
}  // namespace

KernelEstimator::KernelEstimator(std::span<const Point2> uv, std::span<const Rgb> flux, float h, Kernel kernel,
                                 const SurfaceRegion* correction, bool localLinear)
    : h_(h), kernel_(kernel), correction_(correction), localLinear_(localLinear),
      minimumMass_(correction ? MinimumKernelMass(correction->Area(), kernel, h) : kMinEdgeMass) {
  PB_CHECK(h > 0 && std::isfinite(h), "bandwidth is positive and finite");
  PB_CHECK_EQ(uv.size(), flux.size());  // one flux per photon
  if (uv.empty()) return;
  Bounds2 bounds;
  for (const Point2& p : uv) bounds.Extend(p);
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
  uv_.resize(uv.size());
  photonFlux_.resize(uv.size());
  for (size_t i = 0; i < uv.size(); ++i) {
    const uint32_t slot = cursor[cellOf[i]]++;
    uv_[slot] = uv[i];
    photonFlux_[slot] = flux[i];
  }
}

int KernelEstimator::CellIndex(float coordinate, float lo, int count) const {
  return std::clamp(int(std::floor((coordinate - lo) / cellSize_)), 0, count - 1);
}

Rgb KernelEstimator::Estimate(Point2 x) const { return Evaluate<false>(x).irradiance; }

// The kernel mass M(x) (or the fit's denominator) cancels in the ratio, as does 1/h^2.
double KernelEstimator::RelativeNoise(Point2 x) const { return Evaluate<true>(x).relativeNoise; }

DensityEstimator::WithNoise KernelEstimator::EstimateWithNoise(Point2 x) const { return Evaluate<true>(x); }

template <bool kNoise>
DensityEstimator::WithNoise KernelEstimator::Evaluate(Point2 x) const {
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
  if (!localLinear_ || correction_ == nullptr || uv_.empty()) return std::nullopt;
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
  if (uv_.empty()) return {};
  const Rgb sum = profileSum * (1.0f / (h_ * h_));
  if (correction_ == nullptr) return sum;
  return sum * float(1.0 / std::max(correction_->KernelMass(x, kernel_, h_), minimumMass_));
}

template <bool kNoise>
Rgb KernelEstimator::KernelSum(Point2 x, NoiseSums& noise) const {
  if (uv_.empty()) return {};
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
  const float inverseH2 = 1.0f / (h_ * h_), inverseH = 1.0f / h_;
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
        const float w = Luminance(photonFlux_[i]) * k;
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
