#include "baker/photons/progressive.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "estimators/light_sampler.h"
#include "mesh/color.h"

namespace pb {

std::string ShadowRays(const RoundReport& r) {
  if (r.shadowRays == 0) return "";
  const std::string gaps = r.gapPaths > 0 ? fmt::format(", {} paths in gaps", r.gapPaths) : "";
  if (r.directNoise == 0) return fmt::format("{} shadow rays per point{}", r.shadowRays, gaps);
  return fmt::format("up to {} shadow rays per point, to {:.2g}%{}", r.shadowRays, 100 * r.directNoise, gaps);
}

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

// Each vertex's weight in the bake's percentiles: the luminance of its displayed light times its area.
std::vector<double> DisplayWeights(const BakedMesh& baked) {
  std::vector<double> weight = VertexAreas(baked.mesh);
  for (size_t v = 0; v < weight.size(); ++v) weight[v] *= Luminance(baked.Radiance(v));
  return weight;
}

// A vertex's variance split into the shares of the photons, the points' own samples (shadow rays or --reference
// paths) and the paths gathered in a gap; a mesh without the split is all photons.
struct VarianceShares {
  double photons = 1, points = 0, gathered = 0;
};
VarianceShares SharesOf(const BakedMesh& baked, size_t v) {
  VarianceShares s;
  if (!baked.photonVarianceShare.empty()) s.photons = baked.photonVarianceShare[v];
  if (!baked.gatheredVarianceShare.empty()) s.gathered = baked.gatheredVarianceShare[v];
  s.points = std::max(1 - s.photons - s.gathered, 0.0);
  return s;
}

// Each vertex's relative noise of displayed light split into the photons', the points' own (shadow rays or
// --reference paths) and the gathered paths' variance, and its weight (DisplayWeights): computed once, so that
// RemedyForNoise's search only re-takes the percentile.
struct VertexNoise {
  std::vector<double> photonVariance, pointVariance, gatheredVariance, weight;

  explicit VertexNoise(const BakedMesh& baked) : weight(DisplayWeights(baked)) {
    photonVariance.resize(weight.size()), pointVariance.resize(weight.size()), gatheredVariance.resize(weight.size());
    for (size_t v = 0; v < weight.size(); ++v) {
      const double radiance = Luminance(baked.Radiance(v));
      const double reflected = Luminance(OutgoingRadiance({}, baked.albedo[v], baked.irradiance[v]));
      const double noise = radiance > 0 ? reflected / radiance * baked.irradianceNoise[v] : 0.0;
      const VarianceShares share = SharesOf(baked, v);
      photonVariance[v] = share.photons * noise * noise;
      pointVariance[v] = share.points * noise * noise;
      gatheredVariance[v] = share.gathered * noise * noise;
    }
  }
  double Percentile(double photonScale, double pointScale, double gatheredScale = 1) const {
    std::vector<double> noise(weight.size());
    for (size_t v = 0; v < noise.size(); ++v)
      noise[v] = std::sqrt(photonVariance[v] * photonScale + pointVariance[v] * pointScale + gatheredVariance[v] * gatheredScale);
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

NoiseParts BakeNoiseParts(const BakedMesh& baked) {
  const VertexNoise vertices(baked);
  return {vertices.Percentile(1, 0, 0), vertices.Percentile(0, 1, 0), vertices.Percentile(0, 0, 1)};
}

namespace {

// PredictedError's sums over a group of vertices: their H, their noise's and their bias's squares [(W/m^2)^2].
struct ErrorSums {
  double h = 0, noise2 = 0, bias2 = 0;
  size_t vertices = 0;
  BakeError Relative() const {
    if (!(h > 0)) return {};
    const double mean = h / double(vertices);
    return {std::sqrt(noise2 / double(vertices)) / mean, std::sqrt(bias2 / double(vertices)) / mean};
  }
};

// Adds vertex v's terms to `sums`, with PredictedError's scales.
void AddVertexError(const BakedMesh& baked, size_t v, double photonScale, double pointScale, double biasScale,
                    double gatheredScale, ErrorSums& sums) {
  const auto at = [](const std::vector<double>& values, size_t v) {
    return values.empty() ? 0.0 : values[v];  // a mesh estimated without its noise, or without its bias
  };
  const double h = Luminance(baked.irradiance[v]);
  // A vertex's error is taken at most as large as its H: an ill-conditioned local fit on a few photons can predict
  // a noise of thousands of times its estimate (a book's edge in the office: 1,499 H), which would be the RMS.
  const double noise = std::min(at(baked.irradianceNoise, v), 1.0) * h, bias = at(baked.irradianceBias, v) * h;
  const VarianceShares share = SharesOf(baked, v);
  const double scale = share.photons * photonScale + share.points * pointScale + share.gathered * gatheredScale;
  sums.h += h, sums.noise2 += noise * noise * scale, sums.bias2 += bias * bias * biasScale, ++sums.vertices;
}

}  // namespace

BakeError PredictedError(const BakedMesh& baked, double photonScale, double pointScale, double biasScale,
                         double gatheredScale) {
  ErrorSums sums;
  for (size_t v = 0; v < baked.irradiance.size(); ++v)
    AddVertexError(baked, v, photonScale, pointScale, biasScale, gatheredScale, sums);
  return sums.Relative();
}

std::vector<BakeError> PredictedErrorPerSurface(const BakedMesh& baked, size_t surfaces) {
  std::vector<ErrorSums> sums(surfaces);
  for (size_t v = 0; v < baked.irradiance.size(); ++v) AddVertexError(baked, v, 1, 1, 1, 1, sums[baked.mesh.surface[v]]);
  std::vector<BakeError> out(surfaces);
  for (size_t s = 0; s < surfaces; ++s) out[s] = sums[s].Relative();
  return out;
}

double BakeDirectionNoise(const BakedMesh& baked) {
  if (baked.directionNoise.empty()) return 0;
  return WeightedPercentile(baked.directionNoise, DisplayWeights(baked), 0.95);
}

namespace {

// The remedy for a statistic(photonScale, pointScale) of the bake that falls as either scale does: the points'
// own part first, to `share` of the target where it is more (by default 60%, which leaves 80% to the photons':
// raising the photons instead where the points hold most of the target costs them a square of what is left (at
// 90%, 5x)).
template <typename Statistic>
NoiseRemedy RemedyFor(Statistic statistic, double target, uint64_t photons, uint32_t pointSamples, bool raisePoints,
                      double share) {
  NoiseRemedy remedy{photons, pointSamples};
  if (raisePoints && pointSamples > 0 && statistic(0, 1) > share * target) {
    const double s = LargestScaleWithin(share * target, [&](double k) { return statistic(0, k); });
    if (s > 0) remedy.pointSamples = uint32_t(std::min(std::ceil(pointSamples / s), 1e6));
  }
  const double pointScale = double(pointSamples) / double(std::max(remedy.pointSamples, 1u));
  const double s = LargestScaleWithin(target, [&](double k) { return statistic(k, pointScale); });
  if (s > 0) remedy.photons = uint64_t(std::ceil(double(photons) / s));
  return remedy;
}

}  // namespace

NoiseRemedy RemedyForNoise(const BakedMesh& baked, double target, uint64_t photons, uint32_t pointSamples,
                           bool raisePoints, double gatheredScale, double pointShare) {
  const VertexNoise vertices(baked);
  // The points' part alone (k = 0) is their samples', without the gathered paths', which their samples cannot lower.
  return RemedyFor([&](double k, double s) { return vertices.Percentile(k, s, k == 0 ? 0 : gatheredScale); }, target,
                   photons, pointSamples, raisePoints, pointShare);
}

NoiseRemedy RemedyForError(const BakedMesh& baked, double target, uint64_t photons, uint32_t pointSamples,
                           bool raisePoints, bool bandwidthFollows, double gatheredScale, double pointShare) {
  // The points' part alone leaves the bias and the gathered paths' noise out: their samples cannot lower either.
  // With h chosen again for n / k photons, h^6 ~ k: the photons' variance (~ k / h^2) and the bias's square (~ h^4)
  // both scale as k^(2/3).
  const double g = gatheredScale;
  const auto statistic = [&](double k, double s) {
    if (k == 0) return PredictedError(baked, 0, s, 0, 0).Total();
    return bandwidthFollows ? PredictedError(baked, std::cbrt(k * k), s, std::cbrt(k * k), g).Total()
                            : PredictedError(baked, k, s, 1, g).Total();
  };
  return RemedyFor(statistic, target, photons, pointSamples, raisePoints, pointShare);
}

TargetShares SharesByWork(const NoiseParts& alone, double bias, const RoundState& state, double target,
                          double mostPhotons) {
  if (state.raysPerPhoton <= 0) return {};
  const bool points = state.raiseShadowRays && state.shadowRays > 0, gathered = state.raiseGapPaths && state.gapPaths > 0;
  // The variance left to the sources the rounds raise, and each one's weight sqrt(A_i C_i).
  double budget = target * target - bias * bias;
  if (!points) budget -= alone.points * alone.points;
  if (!gathered) budget -= alone.gathered * alone.gathered;
  double photonsWeight = alone.photons * std::sqrt(state.raysPerPhoton * double(state.photons));
  const double pointsWeight = points ? alone.points * std::sqrt(state.pointWork) : 0.0;
  const double gatheredWeight = gathered ? alone.gathered * std::sqrt(state.gatheredWork) : 0.0;
  // Photons past their most (--max-photons, memory) are held there, and the others share what that leaves.
  const double photonsVariance = alone.photons * alone.photons;
  const double growth = mostPhotons / double(std::max<uint64_t>(state.photons, 1));
  if (budget > 0 && photonsWeight > 0 &&
      photonsVariance * (photonsWeight + pointsWeight + gatheredWeight) > growth * budget * photonsWeight) {
    budget -= photonsVariance / std::max(growth, 1.0);
    photonsWeight = 0;
  }
  const double weights = photonsWeight + pointsWeight + gatheredWeight;
  if (!(budget > 0) || !(weights > 0)) return {};
  const auto share = [&](double weight) { return std::sqrt(budget * weight / weights) / target; };
  return {points ? share(pointsWeight) : kPointShare, gathered ? share(gatheredWeight) : kGatheredShare};
}

namespace {

// The smallest square at least n, at most 1000^2: stratified shadow rays lie on a sqrt(n) x sqrt(n) grid.
uint32_t SquareAtLeast(double n) {
  const double side = std::min(std::ceil(std::sqrt(n)), 1000.0);
  return uint32_t(side * side);
}

// The predicted seconds of a round that takes the photons to n and the points' shadow rays by `rayGrowth`: the new
// photons at the rate traced so far, all n binned at the last round's rate, and the points' estimate again, grown
// with the rays or with the cube root of the photons, whichever grows more. The kernel's cost per point hardly
// grows with the photons where it reads them from a binned surface's lattice, but a surface too sparse to bin sums
// its photons one by one. Measured (estimate stage, one run each): the conference room 13.3 s at 10^6 photons and
// 13.1 s at 10^7, Lost Empire 7.2 s at 10^6 and 7.3 s at 8 10^6, the office with books (h = 0.1 m) 0.51 and 0.47 s,
// the box (h = 0.1 m) 0.06 and 0.12 s at 10^6 and 8 10^6: the cube root bounds them all.
double RoundSeconds(const RoundState& state, uint64_t n, double rayGrowth) {
  const double photons = double(std::max<uint64_t>(state.photons, 1)), growth = double(n) / photons;
  const double pointGrowth = std::max(std::cbrt(growth), rayGrowth);
  return state.traceSeconds / photons * double(n - state.photons) + state.binSeconds * growth +
         state.estimateSeconds * pointGrowth;
}

// The shadow rays of the next round where the points hold the noise, and how much their cost grows. From rays alike
// at every point: each takes its own count, to its share of the target (TargetShares), the one its direct light's noise (the
// points' noise over the direct light's share of H) predicts. From a count already per point: its target lowered as
// `variance` (the points' variance that the remedy asks for, as a fraction of today's) asks, and the most raised.
struct PointRays {
  uint32_t most = 0;
  double target = 0, growth = 1;
};
PointRays PointRaysFor(const BakedMesh& baked, const RoundState& state, uint32_t uniform, double target, double share) {
  const double variance = double(state.shadowRays) / double(uniform);
  if (state.directNoise > 0) {
    const double growth = std::pow(variance, -0.5 / LightSampler::kStratifiedOrder);
    return {SquareAtLeast(state.shadowRays * growth), state.directNoise * std::sqrt(variance), growth};
  }
  PointRays next{SquareAtLeast(4.0 * uniform), share * target, 1};
  double rays = 0;
  const size_t n = baked.irradianceNoise.size();
  for (size_t v = 0; v < n; ++v) {
    const double points = baked.irradianceNoise[v] * std::sqrt(SharesOf(baked, v).points);
    const double share = baked.sampledShare.empty() ? 1.0 : baked.sampledShare[v];
    // LightSampler::AdaptiveIrradiance's count, from the noise of the point's direct light at today's rays, and
    // its pilot
    const double direct = share > 0 ? points / share : 0.0;
    rays += LightSampler::AdaptiveCount(direct, state.shadowRays, next.target, next.most) + LightSampler::kPilotSamples;
  }
  next.growth = n > 0 ? rays / double(n) / state.shadowRays : 1.0;
  return next;
}

// The paths gathered in gaps, raised where their own noise alone passes half the target, to half of it: the
// factor by which their variance is to fall (1: as they are). Their noise falls as one over the root of the paths.
constexpr uint32_t kMostGapPaths = 1 << 16;
double GatheredScale(const BakedMesh& baked, const RoundState& state, const RoundLimits& limits, double share) {
  if (!state.raiseGapPaths || state.gapPaths == 0) return 1;
  const VertexNoise vertices(baked);
  const auto alone = [&](double g) {
    return limits.error ? PredictedError(baked, 0, 0, 0, g).Total() : vertices.Percentile(0, 0, g);
  };
  if (alone(1) <= share * limits.target) return 1;
  const double g = LargestScaleWithin(share * limits.target, alone);
  return std::max(g, double(state.gapPaths) / kMostGapPaths);
}

// The most photons the rounds may reach: --max-photons, and what the store's memory holds.
double MostPhotons(const RoundState& state, const RoundLimits& limits) {
  const double most = double(limits.maxPhotons);
  return state.bytesPerPhoton > 0 ? std::min(most, limits.maxStoreBytes / state.bytesPerPhoton) : most;
}

// The shares of the round's target (SharesByWork), from each source's part of the statistic the target bounds.
TargetShares PlannedShares(const BakedMesh& baked, const RoundState& state, const RoundLimits& limits) {
  if (state.raysPerPhoton <= 0) return {};
  const double most = MostPhotons(state, limits);
  if (!limits.error) return SharesByWork(BakeNoiseParts(baked), 0, state, limits.target, most);
  const NoiseParts alone{PredictedError(baked, 1, 0, 0, 0).noise, PredictedError(baked, 0, 1, 0, 0).noise,
                         PredictedError(baked, 0, 0, 0, 1).noise};
  return SharesByWork(alone, PredictedError(baked).bias, state, limits.target, most);
}

// Why no photon count helps, or what caps it.
std::string StopReason(const BakedMesh& baked, const NoiseRemedy& remedy, const RoundState& state, const RoundLimits& limits) {
  const BakeError error = limits.error ? PredictedError(baked) : BakeError{};
  if (remedy.photons <= state.photons && error.bias > 0 && error.bias >= PredictedError(baked, 0, 1).noise)
    return fmt::format("the smoothing bias ({:.2f}%), which more photons at this h cannot lower (give a smaller --h)",
                       100 * error.bias);
  if (remedy.photons <= state.photons)
    return state.raiseShadowRays || state.shadowRays == 0
               ? "the points' own noise (shadow rays or gathered paths), which more photons cannot lower"
               : "the points' own noise, which more photons cannot lower (raise --direct-samples)";
  if (state.photons >= limits.maxPhotons) return fmt::format("--max-photons {}", limits.maxPhotons);
  return fmt::format("memory (the photons and what they take would pass {:.1f} GB)", limits.maxStoreBytes / 1e9);
}

}  // namespace

NextRound PlanNextRound(const BakedMesh& baked, const RoundState& state, const RoundLimits& given) {
  RoundLimits limits = given;
  limits.target *= kPlanMargin;
  const TargetShares shares = PlannedShares(baked, state, limits);
  const double gatheredScale = GatheredScale(baked, state, limits, shares.gathered);
  const NoiseRemedy remedy =
      limits.error ? RemedyForError(baked, limits.target, state.photons, state.shadowRays, state.raiseShadowRays,
                                    state.bandwidthFollows, gatheredScale, shares.points)
                   : RemedyForNoise(baked, limits.target, state.photons, state.shadowRays, state.raiseShadowRays,
                                    gatheredScale, shares.points);
  NextRound next{state.photons, state.shadowRays, state.directNoise, ""};
  double rayGrowth = 1;
  if (gatheredScale < 1) {  // the gathering's cost grows with its paths, at most as the estimate's
    next.gapPaths = uint32_t(std::min(std::ceil(state.gapPaths / gatheredScale), double(kMostGapPaths)));
    rayGrowth = double(next.gapPaths) / double(state.gapPaths);
  }
  if (remedy.pointSamples > state.shadowRays) {
    const PointRays rays = PointRaysFor(baked, state, remedy.pointSamples, limits.target, shares.points);
    next.shadowRays = std::max(rays.most, state.shadowRays), next.directNoise = rays.target;
    rayGrowth = std::max(rayGrowth, rays.growth);
  }
  double photons = remedy.photons > state.photons ? std::max(1.25, 1.1 * remedy.photons / double(state.photons)) * double(state.photons)
                                                  : double(state.photons);
  photons = std::min(photons, MostPhotons(state, limits));
  next.photons = std::max(state.photons, uint64_t(std::ceil(photons)));  // ceil: 1.25 n stays a step of 1.25 n
  // A step worth a round: 1.25 times the photons or the gathered paths, or the points' target first set or lowered
  // by 10% or more.
  const bool lowered = next.directNoise > 0 && (state.directNoise == 0 || next.directNoise <= 0.9 * state.directNoise);
  const bool morePaths = double(next.gapPaths) >= 1.25 * double(state.gapPaths) && next.gapPaths > 0;
  const bool worthARound = double(next.photons) >= 1.25 * double(state.photons) || lowered || morePaths;
  if (worthARound && state.elapsed + RoundSeconds(state, next.photons, rayGrowth) <= limits.maxSeconds) return next;
  NextRound stay{state.photons, state.shadowRays, state.directNoise, "", 0};
  stay.stop = worthARound ? fmt::format("the time budget (--max-seconds {:g})", limits.maxSeconds)
                          : StopReason(baked, remedy, state, limits);
  return stay;
}

}  // namespace pb
