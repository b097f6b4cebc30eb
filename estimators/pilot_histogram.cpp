#include "estimators/pilot_histogram.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "mesh/errors.h"

namespace pb {
namespace {

constexpr int kMinPilotCells = 4, kMaxPilotCells = 64;
constexpr double kFluxStepsPerUnit = 67108864.0;  // 2^26, as the node sums' (estimators/binned_photons.h)

// A power of two of cells per axis, about kPhotonsPerCell photons each.
int CellsFor(uint64_t photons) {
  int n = kMinPilotCells;
  while (n < kMaxPilotCells && double(2 * n) * double(2 * n) * PilotHistogram::kPhotonsPerCell <= double(photons)) n *= 2;
  return n;
}

// F^2 / 2^k with the largest k at most 40 for which `photons` squares of F, each rounded up by a step, stay below
// 2^62.
double SquareStep(uint64_t photons, double fluxUnit) {
  const int bits = std::bit_width(photons + 1);  // photons + 1 < 2^bits
  return fluxUnit * fluxUnit / std::ldexp(1.0, std::min(40, 61 - bits));
}

int64_t Steps(double value, double step) { return std::llround(value / step); }

}  // namespace

PilotHistogram::PilotHistogram(const SurfaceRegion& region, uint64_t photons, double fluxUnit)
    : region_(region),
      photons_(photons),
      n_(CellsFor(photons)),
      cells_(size_t(n_) * size_t(n_)),
      fluxStep_(fluxUnit / kFluxStepsPerUnit),
      squareStep_(SquareStep(photons, fluxUnit)),
      units_(2 * cells_, 0) {
  PB_CHECK(fluxUnit > 0 && std::isfinite(fluxUnit), "the flux unit is positive and finite");
  const Bounds2& b = region.Bounds();
  side_ = std::max(double(b.hi.u) - b.lo.u, double(b.hi.v) - b.lo.v) / n_;
}

PilotHistogram PilotHistogram::Of(const SurfaceRegion& region, std::span<const Point2> uv, std::span<const Rgb> flux,
                                  double fluxUnit) {
  PB_CHECK_EQ(uv.size(), flux.size());  // one flux per photon
  PilotHistogram pilot(region, uv.size(), fluxUnit);
  for (size_t k = 0; k < uv.size(); ++k) pilot.Add(uv[k], flux[k]);
  return pilot;
}

void PilotHistogram::Add(Point2 uv, Rgb flux) {
  const Bounds2& b = region_.Bounds();
  const auto cellOf = [&](float c, float lo) { return std::clamp(int((c - lo) / side_), 0, n_ - 1); };
  const size_t c = size_t(cellOf(uv.v, b.lo.v)) * size_t(n_) + size_t(cellOf(uv.u, b.lo.u));
  const double phi = Luminance(flux);
  units_[c] += Steps(phi, fluxStep_);
  units_[cells_ + c] += Steps(phi * phi, squareStep_);
}

}  // namespace pb
