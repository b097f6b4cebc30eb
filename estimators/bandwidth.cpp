#include "estimators/bandwidth.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace pb {
namespace {

// A surface with too few photons for a pilot: h holds this many on average, whose noise (about 1/sqrt(1000), 3%) is
// the defaults' target; 50 left the table legs and books of the office 40-70% in error (docs/accuracy.md).
constexpr double kFallbackPhotons = 1000, kMinPhotons = 20;
// h is at most this times the square root of the surface's area, its own size: a kernel that wide averages the
// whole of a compact surface (a quarter of it kept small surfaces' kernels to tens of photons).
constexpr double kMaxBandwidthOfSize = 1;
// The roughness a level of the pilot measures must stand this many of its own standard errors above 0.
constexpr double kRoughnessSignificance = 3;

// A level of the pilot histogram: per cell, the flux, the sum of squared flux, and the cell's area on the surface.
struct Pilot {
  int n = 0;          // cells per axis
  double side = 0;    // [m]
  std::vector<double> flux, flux2, area;
  int Index(int i, int j) const { return j * n + i; }
  bool Full(int i, int j) const { return i >= 0 && j >= 0 && i < n && j < n && area[Index(i, j)] >= 0.999 * side * side; }
  double H(int i, int j) const { return flux[Index(i, j)] / area[Index(i, j)]; }
};

// The finest level: the histogram's sums, with each cell's area on the surface.
Pilot FinestLevel(const PilotHistogram& histogram) {
  Pilot p;
  p.n = histogram.CellsPerAxis(), p.side = histogram.Side();
  const size_t cells = size_t(p.n) * p.n;
  p.flux.resize(cells), p.flux2.resize(cells);
  for (size_t c = 0; c < cells; ++c) p.flux[c] = histogram.Flux(c), p.flux2[c] = histogram.Squares(c);
  p.area = histogram.Region().GridOverlapAreas(histogram.Region().Bounds().lo, float(p.side), p.n, p.n);
  return p;
}

// The pilot with cells twice as wide: each the sum of four.
Pilot Coarsen(const Pilot& fine) {
  Pilot p;
  p.n = fine.n / 2, p.side = fine.side * 2;
  const size_t cells = size_t(p.n) * p.n;
  p.flux.assign(cells, 0), p.flux2.assign(cells, 0), p.area.assign(cells, 0);
  for (int j = 0; j < fine.n; ++j)
    for (int i = 0; i < fine.n; ++i) {
      const int from = fine.Index(i, j), to = p.Index(i / 2, j / 2);
      p.flux[to] += fine.flux[from], p.flux2[to] += fine.flux2[from], p.area[to] += fine.area[from];
    }
  return p;
}

// What the bias grows with: the kernels' with h^2 lap H (symmetric, second order), the histogram's with
// b grad H (a point's offset from its bucket's centre, first order).
enum class Roughness { kLaplacian, kGradient };

// integral(phi2 / H^2) over the surface, from one pilot: the variance's share of the relative error.
double VarianceIntegral(const Pilot& p) {
  double variance = 0;
  for (size_t c = 0; c < p.flux.size(); ++c) {
    if (p.area[c] <= 0 || p.flux[c] <= 0) continue;
    const double H = p.flux[c] / p.area[c];
    variance += (p.flux2[c] / p.area[c]) / (H * H) * p.area[c];
  }
  return variance;
}

// The roughness integral, integral((lap H / H)^2) or integral(|grad H / H|^2), over the surface from one pilot,
// with its standard error; scaled from the cells where its stencils fit to the whole surface.
struct PilotIntegrals {
  double roughness = 0, roughnessError = 0;
  int stencils = 0;
  bool Significant() const { return stencils > 0 && roughness > kRoughnessSignificance * roughnessError; }
};

// One linear stencil on the pilot's H about cell (i, j): its value sum w H and its noise variance sum w^2 Var(H).
struct Stencil {
  double value = 0, noise = 0;
  void Add(const Pilot& p, int i, int j, double w) {
    const double g2 = p.side * p.side;
    value += w * p.H(i, j), noise += w * w * p.flux2[p.Index(i, j)] / (g2 * g2);
  }
};

// The stencils whose squares sum to the roughness at full cell (i, j) (its four neighbours full too).
std::vector<Stencil> StencilsAt(const Pilot& p, int i, int j, Roughness kind) {
  if (kind == Roughness::kLaplacian) {
    const double w = 1 / (p.side * p.side);
    Stencil lap;
    for (const auto& [a, b] : {std::pair{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}}) lap.Add(p, a, b, w);
    lap.Add(p, i, j, -4 * w);
    return {lap};
  }
  const double w = 1 / (2 * p.side);
  Stencil du, dv;
  du.Add(p, i + 1, j, w), du.Add(p, i - 1, j, -w);
  dv.Add(p, i, j + 1, w), dv.Add(p, i, j - 1, -w);
  return {du, dv};
}

PilotIntegrals Integrate(const Pilot& p, double surfaceArea, Roughness kind, bool relative) {
  PilotIntegrals r;
  double stencilArea = 0, roughnessVariance = 0;
  const double g2 = p.side * p.side;
  for (int j = 0; j < p.n; ++j)
    for (int i = 0; i < p.n; ++i) {
      const int c = p.Index(i, j);
      if (p.area[c] <= 0 || p.flux[c] <= 0) continue;
      const double H = p.flux[c] / p.area[c];
      if (!(p.Full(i, j) && p.Full(i - 1, j) && p.Full(i + 1, j) && p.Full(i, j - 1) && p.Full(i, j + 1))) continue;
      const double scale = relative ? g2 / (H * H) : g2;
      for (const Stencil& s : StencilsAt(p, i, j, kind)) {
        r.roughness += (s.value * s.value - s.noise) * scale;  // unbiased; clipped only in total
        // Var(x^2) of a normal x: 2 noise^2 + 4 x^2 noise, with x^2 itself less its noise.
        roughnessVariance += (2 * s.noise * s.noise + 4 * std::max(s.value * s.value - s.noise, 0.0) * s.noise) * scale * scale;
      }
      stencilArea += g2;
      ++r.stencils;
    }
  if (stencilArea > 0) {
    r.roughness *= surfaceArea / stencilArea;
    r.roughnessError = std::sqrt(roughnessVariance) * surfaceArea / stencilArea;
  }
  return r;
}

// The roughness integral of the finest pilot level that measures one significantly (finer cells smooth the
// light less, coarser ones hold more photons: a stencil's signal grows with the cell's side, its noise falls as
// one over the side). Where no level does, `measured` is false and the value is the least roughness that no level
// can rule out (its estimate plus kRoughnessSignificance standard errors, the smallest over the levels): an h no
// wider than the photons can vouch for. 0 where no stencil fits at any level.
struct RoughnessMeasure {
  double value = 0;
  bool measured = false;
  bool fits = false;  // a stencil fits at some level
};
RoughnessMeasure MeasuredRoughness(Pilot pilot, double surfaceArea, Roughness kind, bool relative = true) {
  double bound = INFINITY;
  for (;;) {
    const PilotIntegrals I = Integrate(pilot, surfaceArea, kind, relative);
    if (I.Significant()) return {I.roughness, true, true};
    if (I.stencils > 0) bound = std::min(bound, std::max(I.roughness, 0.0) + kRoughnessSignificance * I.roughnessError);
    if (pilot.n / 2 < 3) return {std::isfinite(bound) ? bound : 0, false, std::isfinite(bound)};  // 3 cells per axis
    pilot = Coarsen(pilot);
  }
}

// At least 3 x 3 cells' photons.
bool PilotFits(double photons) { return photons >= 9 * PilotHistogram::kPhotonsPerCell; }

}  // namespace

float ChooseBandwidth(EstimatorKind kind, Kernel kernel, const PilotHistogram& histogram) {
  const SurfaceRegion& region = histogram.Region();
  const double area = std::max(region.Area(), 1e-30), n = double(histogram.Photons());
  const double hMax = kMaxBandwidthOfSize * std::sqrt(area);
  const double hFallback = std::min(hMax, std::sqrt(kFallbackPhotons * area / (M_PI * std::max(n, 1.0))));
  if (!PilotFits(n)) return float(hFallback);
  const double hMin = std::sqrt(kMinPhotons * area / (M_PI * n));
  const Pilot pilot = FinestLevel(histogram);
  const double variance = VarianceIntegral(pilot);
  const Roughness kindOfRoughness = kind == EstimatorKind::kHistogram ? Roughness::kGradient : Roughness::kLaplacian;
  const RoughnessMeasure roughness = MeasuredRoughness(pilot, area, kindOfRoughness);
  if (!roughness.fits) return float(std::clamp(pilot.side, hMin, std::max(hMin, hMax)));
  double h = hMax;
  if (roughness.value > 0) {
    if (kind == EstimatorKind::kHistogram) {  // b^4 = 12 V / integral(|grad H / H|^2)
      h = std::pow(12 * variance / roughness.value, 0.25);
    } else {  // h^6 = 2 R V / (mu2^2 integral((lap H / H)^2))
      const KernelMoments m = MomentsOf(kernel);
      h = std::pow(2 * m.roughness * variance / (m.moment2 * m.moment2 * roughness.value), 1.0 / 6.0);
    }
  }
  return float(std::clamp(h, hMin, std::max(hMin, hMax)));
}

namespace {

// The RMS over the surface of H's departure from its mean, from the pilot's cells, each cell's noise taken out: what
// a kernel as wide as the surface, which reads the mean everywhere, is off by at most.
double Spread(const Pilot& p) {
  double flux = 0, area = 0;
  for (size_t c = 0; c < p.flux.size(); ++c) flux += p.flux[c], area += p.area[c];
  if (!(area > 0)) return 0;
  const double mean = flux / area;
  double squares = 0;
  for (size_t c = 0; c < p.flux.size(); ++c) {
    if (!(p.area[c] > 0)) continue;
    const double H = p.flux[c] / p.area[c], noise = p.flux2[c] / (p.area[c] * p.area[c]);
    squares += ((H - mean) * (H - mean) - noise) * p.area[c];
  }
  return std::sqrt(std::max(squares, 0.0) / area);
}

}  // namespace

double PredictedBias(EstimatorKind kind, Kernel kernel, const PilotHistogram& histogram, float h) {
  const double area = histogram.Region().Area();
  if (kind == EstimatorKind::kNearest || !(area > 0) || !PilotFits(double(histogram.Photons()))) return 0;
  const Pilot pilot = FinestLevel(histogram);
  double bias = 0;
  if (kind == EstimatorKind::kHistogram) {  // bias^2 averages b^2 |grad H|^2 / 12
    const RoughnessMeasure gradient = MeasuredRoughness(pilot, area, Roughness::kGradient, false);
    if (gradient.measured) bias = double(h) * std::sqrt(std::max(gradient.value, 0.0) / (12 * area));
  } else {  // h^2 mu2 lap H / 2
    const RoughnessMeasure curvature = MeasuredRoughness(pilot, area, Roughness::kLaplacian, false);
    if (curvature.measured) bias = double(h) * h * MomentsOf(kernel).moment2 / 2 * std::sqrt(std::max(curvature.value, 0.0) / area);
  }
  return std::min(bias, Spread(pilot));
}

}  // namespace pb
