// Progressive bakes: the photon store of a bake (baker/1_trace_photons.h) started empty or from --resume, grown to
// --photons or in rounds to --target-noise, and saved by --save-photons (baker/files/photon_file.h); the rounds
// themselves are baker/photons/photon_rounds.h, and this is what they report and how they plan and measure. The paper ("How
// to trace a particle") stores photons by attenuation so that "the number of photons emitted by each light
// source" can grow; its warning that this "can lead to bias" is met by dividing each light's photons by that
// light's own count, which only ever grows (docs/bake.md, "Adding photons to a bake").
//
// The noise of a vertex is the relative standard deviation of its displayed radiance L = Le + R H / pi, in
// luminance: sigma_L / L = (R H / pi) / L x sigma_H / H, with sigma_H / H predicted by the surface's estimator
// from the photons it uses (DensityEstimator::RelativeNoise; smoothing bias not included). The bake's noise is
// the 95th percentile over vertices, each weighted by its luminance L times its area (a third of its faces'),
// so that dark corners and dense meshes do not decide it. Dimensionless.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "baker/baked_mesh.h"

namespace pb {

struct RoundReport {
  uint64_t requested = 0;  // the round's --photons: a bake with this many gives the same bytes
  uint64_t photons = 0;    // emitted by the end of the round, over all lights
  uint32_t shadowRays = 0; // the round's --direct-samples (0 with --direct photons)
  double directNoise = 0;  // the round's --direct-noise: the points' target, shadowRays their most; 0: all take them
  double noise = 0;        // the bake's noise after it
  double error = 0;        // and its predicted error (PredictedError's total)
  double seconds = 0;      // the bake's wall time at the round's end [s]
  uint32_t gapPaths = 0;   // the round's --gap-paths (0: no gathering)
};

// "256 shadow rays per point", or with a target per point "up to 1024 shadow rays per point, to 1.8%", and ", 4096
// paths in gaps" with gathering; "" without shadow rays.
std::string ShadowRays(const RoundReport& round);

struct ProgressiveReport {
  std::string resumedFrom;      // --resume's file, or ""
  uint64_t resumedPhotons = 0;  // photons it held
  std::string savedTo;          // --save-photons' file, or ""
  bool interrupted = false;     // Ctrl-C stopped tracing early
  bool estimateStopped = false; // a later round's estimate stopped (Ctrl-C or its deadline): the vertices are the
                                // last round's in `rounds`
  // Vertices of the first round's estimate that Ctrl-C or its deadline left to the fewest samples (0: none).
  uint64_t finishedVertices = 0;
  std::optional<float> target;  // --target-noise, or --target-error when targetIsError
  bool targetIsError = false;
  std::vector<RoundReport> rounds;  // --target-noise's rounds, in order
  std::string stoppedBy;            // why the rounds ended short of the target (NextRound::stop), or ""
  // Where the first round's estimate, foretold from a pilot, would have ended the bake past the time budget: the
  // factor its shadow rays and gathered paths were cut by (1: not cut), and its foretold seconds at the full count.
  double firstRoundCut = 1, firstRoundForetold = 0;
  // The surfaces smaller than their kernel that the defaults' share left to the photons, and those of them the time
  // the rounds left gathered at their points (baker/photons/trace_and_estimate.h), with their vertices and seconds.
  struct SmallSurfaces {
    uint32_t leftOut = 0, gathered = 0;
    uint64_t vertices = 0;
    double seconds = 0;
    bool interrupted = false;  // Ctrl-C ended it (else, where not all were gathered, the time budget)
  } small;
  double Measured(const RoundReport& r) const { return targetIsError ? r.error : r.noise; }  // what the target bounds
  bool TargetMet() const { return target && !rounds.empty() && Measured(rounds.back()) <= *target; }
};


// The smallest of `value` such that the values at or below it carry at least `fraction` of the total weight (0 when
// the weights sum to none).
double WeightedPercentile(const std::vector<double>& value, const std::vector<double>& weight, double fraction);

// The bake's noise: the weighted 95th percentile above, from each vertex's sigma_H / H (BakedMesh::irradianceNoise,
// which EstimateIrradiance gives with withNoise); 0 for a mesh with no lit vertex. With the scales, the noise it
// would have if the photons' variance were multiplied by photonScale and the points' samples' by pointScale
// (n / n' for n' photons, S / S' for S' samples per point); the variance of paths gathered in gaps stays.
double BakeNoise(const BakedMesh& baked, double photonScale = 1, double pointScale = 1);
// The bake's noise from each source alone, by the same percentile: the photons', the points' own samples' (shadow
// rays, or --reference's paths) and the paths gathered in gaps'. Each is at most BakeNoise; the one nearest it holds
// the noise (the sports car at the defaults: 61% in all, its gathered paths' alone 60%).
struct NoiseParts {
  double photons = 0, points = 0, gathered = 0;
};
NoiseParts BakeNoiseParts(const BakedMesh& baked);

// The bake's predicted error of H, in the accuracy tool's measure (tools/accuracy.cpp): the RMS over vertices of
// H's luminance error, relative to the vertices' mean H, split into the noise (sigma_H, BakedMesh::irradianceNoise)
// and the photons' smoothing bias (BakedMesh::irradianceBias), which add in quadrature; a vertex's noise is taken at
// most as large as its H. With the scales, the error
// it would have if the photons' variance were multiplied by photonScale, the points' samples' by pointScale and the
// bias's square by biasScale, and the paths gathered in gaps by gatheredScale. Dimensionless; 0 for a mesh with no
// lit vertex.
struct BakeError {
  double noise = 0, bias = 0;
  double Total() const { return std::hypot(noise, bias); }
};
BakeError PredictedError(const BakedMesh& baked, double photonScale = 1, double pointScale = 1, double biasScale = 1,
                         double gatheredScale = 1);
// The same per surface (`surfaces` of them), over its own vertices and relative to their own mean H: where the error
// is, which the bake's figure, dominated by the lit parts, does not say (a room lit through a door left ajar reads
// 1.4% over the whole bake and tens of percent on its own surfaces).
std::vector<BakeError> PredictedErrorPerSurface(const BakedMesh& baked, size_t surfaces);

// With --sh, the 95th percentile of the vertices' direction noise [rad] (BakedMesh::directionNoise), by the same
// weights as BakeNoise's; 0 without.
double BakeDirectionNoise(const BakedMesh& baked);

// The shares of a round's target that the points' own noise and the gathered paths' take when the work of each is
// not known (SharesByWork).
constexpr double kPointShare = 0.6, kGatheredShare = 0.5;

// What would bring the bake's noise to `target`: the photon count, and the samples per point (shadow rays or
// --reference paths) when the points' own noise alone passes pointShare of it and `raisePoints` (to that share; else
// the current count). photons is the current count when no photon count reaches the target (the points' noise holds it).
struct NoiseRemedy {
  uint64_t photons = 0;
  uint32_t pointSamples = 0;
};
NoiseRemedy RemedyForNoise(const BakedMesh& baked, double target, uint64_t photons, uint32_t pointSamples,
                           bool raisePoints = true, double gatheredScale = 1, double pointShare = kPointShare);
// The same for the predicted error (PredictedError): the photons' variance falls with their count, the points'
// with their samples, and the smoothing bias with neither (h is held); photons is the current count where the
// bias, or the points' noise, holds the error above the target.
// With bandwidthFollows (--h auto chosen again each round), the photons' variance and the bias both fall with the
// photons, as (n / n')^(2/3).
NoiseRemedy RemedyForError(const BakedMesh& baked, double target, uint64_t photons, uint32_t pointSamples,
                           bool raisePoints = true, bool bandwidthFollows = false, double gatheredScale = 1,
                           double pointShare = kPointShare);

// Where a bake with --target-noise stands after a round, and what bounds the next.
struct RoundState {
  uint64_t photons = 0;        // requested so far over all lights
  uint32_t shadowRays = 0;     // per point (--direct sampled), else 0; with directNoise, the most a point takes
  double directNoise = 0;      // each point's target for its direct light's relative noise; 0: none
  bool raiseShadowRays = false;  // the rounds may raise them (--direct-samples and --direct-noise not given)
  bool bandwidthFollows = false; // --h auto chooses h again each round (--target-error), rather than holding it
  uint32_t gapPaths = 0;         // paths gathered per point in a gap (--gap-paths); 0: none
  bool raiseGapPaths = false;    // the rounds may raise them (--gap-paths and --gap-noise not given)
  double elapsed = 0;          // the bake's wall time so far [s]
  double traceSeconds = 0;     // spent tracing all photons so far [s]
  double binSeconds = 0;       // the last round's binning [s]
  double estimateSeconds = 0;  // the last round's estimate, everything after binning [s]
  double bytesPerPhoton = 0;   // the bake's memory per emitted photon: its peak beyond what it held before tracing, at least the store's
  // The work each source took (SharesByWork); all 0: not counted, and the plan gives the sources fixed shares.
  double raysPerPhoton = 0;    // rays a photon cast on average (its segments)
  double pointWork = 0;        // the last round's samples at the points (shadow rays, or --reference's paths)
  double gatheredWork = 0;     // the rays of the last round's gathered paths (segments and light samples)
};

// The share of the target that each source's noise is planned to take, as a fraction of the target (the photons
// take what the others leave). With the sources' work counted, the least work that meets the target: a source
// whose variance A_i cost C_i (rays) costs C_i A_i / V_i to bring to V_i, so the least total over the V_i that sum
// to the target's variance (less the bias's square, less the noise of the sources the rounds may not raise) gives
// each V_i in proportion to sqrt(A_i C_i) (Lagrange). The work is counted in rays, a shadow ray, a path's segment
// and a photon's alike, not timed, so that the plan, and the bytes, are the same on any machine and thread count;
// the least total is flat about its optimum (two sources alike, one's cost misjudged by 2x: 3% more work; by 4x:
// 12%). Without counts, the points' noise takes kPointShare of the target and the gathered paths' kGatheredShare.
struct TargetShares {
  double points = kPointShare, gathered = kGatheredShare;
};
// `alone`: each source's noise (or error) alone at today's samples, the statistic's; `bias`: the error's smoothing
// bias (0 for a noise target); `mostPhotons`: what --max-photons and the memory let the photons reach. Photons that
// the least work would raise past it are held there (a bound met, the others share what they leave: Kuhn-Tucker);
// where even that leaves no variance to share, the fixed shares, and the remedies then say what holds the rounds.
TargetShares SharesByWork(const NoiseParts& alone, double bias, const RoundState& state, double target,
                          double mostPhotons);
struct RoundLimits {
  float target = 0;           // --target-noise, or --target-error with `error`
  uint64_t maxPhotons = 0;    // --max-photons
  double maxSeconds = 0;      // --max-seconds: no round starts that is expected to end the bake's rounds later
  double maxStoreBytes = 0;   // what the rounds may add to the memory the bake held before tracing
  bool error = false;         // the target bounds PredictedError's total, not BakeNoise
};
// The next round: photons n (noise / target)^2 with 10% to spare and at least 1.25 n, from the photons' share of
// the noise (RemedyForNoise); within --max-photons and the store's memory. Where the points' own noise holds the
// bake's, each point takes the shadow rays its own noise needs (--direct-noise, LightSampler::AdaptiveIrradiance),
// to 60% of the target, at most 4 times the count that every point would need alike: the rays go where the shadows
// are (Lost Empire: 3.6% at 8 10^6 photons in 17 s, where 2,209 rays at every point took 85 s to 2.9%). A later
// round lowers that target, and raises the most, as the points' noise still asks. stop names what ends the rounds
// instead ("" when a round follows): nothing to gain, or a round whose time, predicted from this one's, would pass
// --max-seconds.
struct NextRound {
  uint64_t photons = 0;
  uint32_t shadowRays = 0;
  double directNoise = 0;
  std::string stop;
  uint32_t gapPaths = 0;  // the next round's --gap-paths; 0: as it was
};
// Every remedy above is asked for kPlanMargin times the target: the plan's prediction of the round it plans is an
// extrapolation, and a round that lands just short (1.02% for 1%) pays for a whole further round. Measured on the
// box at --quality production --target-error 0.01: three rounds in 10.9 s at 1, two in 6.3 s at 0.95 (0.95% net
// against the 16,384-path truth, 0.97% before); the office at 1.5%, 23.6 s -> 15.4 s (docs/bake.md, "Target error").
constexpr double kPlanMargin = 0.95;
NextRound PlanNextRound(const BakedMesh& baked, const RoundState& state, const RoundLimits& limits);

}  // namespace pb
