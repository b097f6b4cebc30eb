#include "estimators/bandwidth.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace pb {
namespace {

constexpr double kPilotPhotonsPerCell = 400;
constexpr int kMinPilotCells = 4, kMaxPilotCells = 64;
constexpr double kFallbackPhotons = 50, kMinPhotons = 20;

// Pilot histogram: per cell, the flux, the sum of squared flux, and the cell's area on the surface.
struct Pilot {
  int n = 0;          // cells per axis
  double side = 0;    // [m]
  std::vector<double> flux, flux2, area;
  int Index(int i, int j) const { return j * n + i; }
  bool Full(int i, int j) const { return i >= 0 && j >= 0 && i < n && j < n && area[Index(i, j)] >= 0.999 * side * side; }
  double H(int i, int j) const { return flux[Index(i, j)] / area[Index(i, j)]; }
};

Pilot BuildPilot(const SurfaceRegion& region, std::span<const Point2> uv, std::span<const Rgb> flux) {
  Pilot p;
  const Bounds2& b = region.Bounds();
  p.side = std::max(double(b.hi.u) - b.lo.u, double(b.hi.v) - b.lo.v);
  p.n = std::clamp(int(std::sqrt(double(uv.size()) / kPilotPhotonsPerCell)), kMinPilotCells, kMaxPilotCells);
  p.side /= p.n;
  const size_t cells = size_t(p.n) * p.n;
  p.flux.assign(cells, 0), p.flux2.assign(cells, 0);
  const auto cellOf = [&](float c, float lo) { return std::clamp(int((c - lo) / p.side), 0, p.n - 1); };
  for (size_t k = 0; k < uv.size(); ++k) {
    const int c = p.Index(cellOf(uv[k].u, b.lo.u), cellOf(uv[k].v, b.lo.v));
    const double phi = Luminance(flux[k]);
    p.flux[c] += phi, p.flux2[c] += phi * phi;
  }
  p.area = region.GridOverlapAreas(b.lo, float(p.side), p.n, p.n);
  return p;
}

// integral(phi2 / H^2) and integral((lap H / H)^2) over the surface, from the pilot; the second is scaled
// from the cells where the stencil fits to the whole surface area.
struct PilotIntegrals {
  double variance = 0, curvature = 0;
  int stencils = 0;
};

PilotIntegrals Integrate(const Pilot& p, double surfaceArea) {
  PilotIntegrals r;
  double stencilArea = 0;
  const double g2 = p.side * p.side;
  for (int j = 0; j < p.n; ++j)
    for (int i = 0; i < p.n; ++i) {
      const int c = p.Index(i, j);
      if (p.area[c] <= 0 || p.flux[c] <= 0) continue;
      const double H = p.flux[c] / p.area[c];
      r.variance += (p.flux2[c] / p.area[c]) / (H * H) * p.area[c];
      if (!(p.Full(i, j) && p.Full(i - 1, j) && p.Full(i + 1, j) && p.Full(i, j - 1) && p.Full(i, j + 1))) continue;
      const double lap = (p.H(i - 1, j) + p.H(i + 1, j) + p.H(i, j - 1) + p.H(i, j + 1) - 4 * H) / g2;
      const auto var = [&](int a, int b) { return p.flux2[p.Index(a, b)] / (g2 * g2); };  // Var of a cell's H
      const double lapNoise = (var(i - 1, j) + var(i + 1, j) + var(i, j - 1) + var(i, j + 1) + 16 * var(i, j)) / (g2 * g2);
      r.curvature += (lap * lap - lapNoise) / (H * H) * g2;  // unbiased; clipped only in total
      stencilArea += g2;
      ++r.stencils;
    }
  if (stencilArea > 0) r.curvature *= surfaceArea / stencilArea;
  return r;
}

}  // namespace

float ChooseBandwidth(EstimatorKind kind, Kernel kernel, const SurfaceRegion& region, std::span<const Point2> uv,
                      std::span<const Rgb> flux) {
  const double area = std::max(region.Area(), 1e-30), n = double(uv.size());
  const double hMax = 0.25 * std::sqrt(area);
  if (n < kPilotPhotonsPerCell * 9) return float(std::min(hMax, std::sqrt(kFallbackPhotons * area / (M_PI * std::max(n, 1.0)))));
  const double hMin = std::sqrt(kMinPhotons * area / (M_PI * n));
  const KernelMoments m = kind == EstimatorKind::kHistogram ? KernelMoments{1.0, 1.0 / 12.0} : MomentsOf(kernel);
  const PilotIntegrals I = Integrate(BuildPilot(region, uv, flux), area);
  if (I.stencils == 0 || !(I.curvature > 0)) return float(hMax);
  const double h = std::pow(2 * m.roughness * I.variance / (m.moment2 * m.moment2 * I.curvature), 1.0 / 6.0);
  return float(std::clamp(h, hMin, std::max(hMin, hMax)));
}

}  // namespace pb
