#include "estimators/binned_photons.h"

#include <algorithm>

#include "mesh/errors.h"

namespace pb {

NodeLattice NodeLattice::Over(Bounds2 bounds, float h, int nodesPerH) {
  NodeLattice l;
  l.spacing = h / float(nodesPerH);
  l.lo = bounds.lo;
  l.nodesU = int(std::floor((double(bounds.hi.u) - l.lo.u) / l.spacing)) + 2;
  l.nodesV = int(std::floor((double(bounds.hi.v) - l.lo.v) / l.spacing)) + 2;
  return l;
}

BinnedPhotons::BinnedPhotons(const NodeLattice& lattice, double fluxUnit)
    : lattice_(lattice), unit_(fluxUnit / kUnitsPerFlux), squareUnit_(fluxUnit * fluxUnit / kUnitsPerFlux),
      sums_(lattice.Count(), std::array<int64_t, 4>{}) {
  PB_CHECK(fluxUnit > 0 && std::isfinite(fluxUnit), "the flux unit is positive and finite");
}

namespace {
void AtomicAdd(int64_t& into, double units) {
  std::atomic_ref<int64_t>(into).fetch_add(std::llround(units), std::memory_order_relaxed);
}
}  // namespace

void BinnedPhotons::Add(Point2 uv, Rgb flux) {
  const double y = Luminance(flux), y2 = y * y;
  const double r = flux.r / unit_, g = flux.g / unit_, b = flux.b / unit_, q = y2 / squareUnit_;
  lattice_.ShareAt(uv, [&](size_t n, double w) {
    std::array<int64_t, 4>& s = sums_[n];
    AtomicAdd(s[0], w * r), AtomicAdd(s[1], w * g), AtomicAdd(s[2], w * b), AtomicAdd(s[3], w * q);
  });
  photons_.fetch_add(1, std::memory_order_relaxed);
}

void BinnedPhotons::Prefetch(Point2 uv) const {
  const double fu = (double(uv.u) - lattice_.lo.u) / lattice_.spacing, fv = (double(uv.v) - lattice_.lo.v) / lattice_.spacing;
  const int iu = std::clamp(int(std::floor(fu)), 0, lattice_.nodesU - 2), iv = std::clamp(int(std::floor(fv)), 0, lattice_.nodesV - 2);
  for (int j = iv; j <= iv + 1; ++j) {
    const std::array<int64_t, 4>* row = &sums_[size_t(j) * lattice_.nodesU + iu];
    __builtin_prefetch(row, 1), __builtin_prefetch(row + 1, 1);
  }
}

Rgb BinnedPhotons::Flux(size_t n) const {
  const std::array<int64_t, 4>& s = sums_[n];
  return {float(double(s[0]) * unit_), float(double(s[1]) * unit_), float(double(s[2]) * unit_)};
}

float BinnedPhotons::Squares(size_t n, double unit) const {
  return float(double(sums_[n][3]) * squareUnit_ / (unit * unit));
}

void FluxTally::Add(Rgb flux, double fluxUnit) {
  const double unit = fluxUnit / BinnedPhotons::kUnitsPerFlux;
  units[0] += std::llround(flux.r / unit), units[1] += std::llround(flux.g / unit), units[2] += std::llround(flux.b / unit);
}

void FluxTally::Add(const FluxTally& other) {
  for (int c = 0; c < 3; ++c) units[c] += other.units[c];
}

Rgb FluxTally::ToRgb(double fluxUnit) const {
  const double unit = fluxUnit / BinnedPhotons::kUnitsPerFlux;
  return {float(double(units[0]) * unit), float(double(units[1]) * unit), float(double(units[2]) * unit)};
}

}  // namespace pb
