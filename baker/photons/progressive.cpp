#include "baker/photons/progressive.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "mesh/color.h"

namespace pb {
namespace {

// Each vertex's share of the mesh's area: a third of each face it is a corner of [m^2].
std::vector<double> VertexAreas(const SplitMesh& mesh) {
  std::vector<double> area(mesh.VertexCount(), 0.0);
  for (const auto& f : mesh.faces) {
    const double a = 0.5 * Length(Cross(mesh.positions[f[1]] - mesh.positions[f[0]], mesh.positions[f[2]] - mesh.positions[f[0]]));
    for (uint32_t v : f) area[v] += a / 3.0;
  }
  return area;
}

}  // namespace

double WeightedPercentile(const std::vector<double>& value, const std::vector<double>& weight, double fraction) {
  std::vector<size_t> order(value.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return value[a] < value[b]; });
  const double total = std::accumulate(weight.begin(), weight.end(), 0.0);
  if (!(total > 0)) return 0.0;
  double below = 0;
  for (size_t v : order) {
    below += weight[v];
    if (below >= fraction * total) return value[v];
  }
  return value[order.back()];
}

namespace {

// Each vertex's relative noise of displayed light split into the photons' and the points' variance, and its
// weight (luminance x area): computed once, so that RemedyForNoise's search only re-takes the percentile.
struct VertexNoise {
  std::vector<double> photonVariance, pointVariance, weight;

  explicit VertexNoise(const BakedMesh& baked) {
    const std::vector<double> area = VertexAreas(baked.mesh);
    photonVariance.resize(area.size()), pointVariance.resize(area.size()), weight.resize(area.size());
    for (size_t v = 0; v < area.size(); ++v) {
      const double radiance = Luminance(baked.Radiance(v));
      const double reflected = Luminance(OutgoingRadiance({}, baked.albedo[v], baked.irradiance[v]));
      const double noise = radiance > 0 ? reflected / radiance * baked.irradianceNoise[v] : 0.0;
      const double share = baked.photonVarianceShare.empty() ? 1.0 : baked.photonVarianceShare[v];
      photonVariance[v] = share * noise * noise;
      pointVariance[v] = (1 - share) * noise * noise;
      weight[v] = radiance * area[v];
    }
  }
  double Percentile(double photonScale, double pointScale) const {
    std::vector<double> noise(weight.size());
    for (size_t v = 0; v < noise.size(); ++v)
      noise[v] = std::sqrt(photonVariance[v] * photonScale + pointVariance[v] * pointScale);
    return WeightedPercentile(noise, weight, 0.95);
  }
};

// The largest scale s in (0, 1] (to a part in 100, by bisection in log s) for which noise(s) <= target; noise
// falls as s does. 0 when even s -> 0 leaves it above.
template <typename Noise>
double LargestScaleWithin(double target, Noise noise) {
  if (noise(1.0) <= target) return 1.0;
  if (noise(1e-9) > target) return 0.0;
  double lo = 1e-9, hi = 1.0;  // noise(lo) <= target < noise(hi)
  while (hi / lo > 1.01) {
    const double mid = std::sqrt(lo * hi);
    (noise(mid) <= target ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

double BakeNoise(const BakedMesh& baked, double photonScale, double pointScale) {
  return VertexNoise(baked).Percentile(photonScale, pointScale);
}

constexpr double kPointShare = 0.6;

NoiseRemedy RemedyForNoise(const BakedMesh& baked, double target, uint64_t photons, uint32_t pointSamples,
                           bool raisePoints) {
  const VertexNoise vertices(baked);
  NoiseRemedy remedy{photons, pointSamples};
  // The points' own noise first, to 60% of the target where it is more, which leaves 80% to the photons': raising
  // the photons instead where the points hold most of the target costs them a square of what is left (at 90%, 5x).
  if (raisePoints && pointSamples > 0 && vertices.Percentile(0, 1) > kPointShare * target) {
    const double s = LargestScaleWithin(kPointShare * target, [&](double k) { return vertices.Percentile(0, k); });
    if (s > 0) remedy.pointSamples = uint32_t(std::min(std::ceil(pointSamples / s), 1e6));
  }
  const double pointScale = double(pointSamples) / double(std::max(remedy.pointSamples, 1u));
  const double s = LargestScaleWithin(target, [&](double k) { return vertices.Percentile(k, pointScale); });
  if (s > 0) remedy.photons = uint64_t(std::ceil(double(photons) / s));
  return remedy;
}

namespace {

// The smallest square at least n, at most 1000^2: stratified shadow rays lie on a sqrt(n) x sqrt(n) grid.
uint32_t SquareAtLeast(double n) {
  const double side = std::min(std::ceil(std::sqrt(n)), 1000.0);
  return uint32_t(side * side);
}

// The predicted seconds of a round that takes the photons to n and the shadow rays to s: the new photons at the
// rate traced so far, and the estimate again, grown with the photons or the rays, whichever grows more.
double RoundSeconds(const RoundState& state, uint64_t n, uint32_t s) {
  const double photons = double(std::max<uint64_t>(state.photons, 1));
  const double growth = std::max(double(n) / photons, state.shadowRays > 0 ? double(s) / state.shadowRays : 1.0);
  return state.traceSeconds / photons * double(n - state.photons) + state.estimateSeconds * growth;
}

// Why no photon count helps, or what caps it.
std::string StopReason(const NoiseRemedy& remedy, const RoundState& state, const RoundLimits& limits) {
  if (remedy.photons <= state.photons)
    return state.raiseShadowRays || state.shadowRays == 0
               ? "the points' own noise (shadow rays or gathered paths), which more photons cannot lower"
               : "the points' own noise, which more photons cannot lower (raise --direct-samples)";
  if (state.photons >= limits.maxPhotons) return fmt::format("--max-photons {}", limits.maxPhotons);
  return fmt::format("memory (the photon store would pass {:.1f} GB)", limits.maxStoreBytes / 1e9);
}

}  // namespace

NextRound PlanNextRound(const BakedMesh& baked, const RoundState& state, const RoundLimits& limits) {
  const NoiseRemedy remedy =
      RemedyForNoise(baked, limits.target, state.photons, state.shadowRays, state.raiseShadowRays);
  NextRound next{state.photons, state.shadowRays, ""};
  if (remedy.pointSamples > state.shadowRays) next.shadowRays = SquareAtLeast(remedy.pointSamples);
  double photons = remedy.photons > state.photons ? std::max(1.25, 1.1 * remedy.photons / double(state.photons)) * double(state.photons)
                                                  : double(state.photons);
  photons = std::min(photons, double(limits.maxPhotons));
  if (state.bytesPerPhoton > 0) photons = std::min(photons, limits.maxStoreBytes / state.bytesPerPhoton);
  next.photons = std::max(state.photons, uint64_t(photons));
  const auto worthARound = [&](uint64_t n, uint32_t s) {
    return double(n) >= 1.25 * double(state.photons) || (s > state.shadowRays && double(s) >= 1.25 * state.shadowRays);
  };
  if (!worthARound(next.photons, next.shadowRays)) return {state.photons, state.shadowRays, StopReason(remedy, state, limits)};
  if (state.elapsed + RoundSeconds(state, next.photons, next.shadowRays) <= limits.maxSeconds) return next;
  return {state.photons, state.shadowRays, fmt::format("the time budget (--max-seconds {:g})", limits.maxSeconds)};
}

}  // namespace pb
