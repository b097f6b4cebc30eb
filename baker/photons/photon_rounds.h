// Stages 1 and 2 as one noun: the photons of a bake, from an empty store or --resume's to the per-surface bins
// that stage 3 reads (baker/2_bin_photons.h, SurfaceBins). A round traces photons up to its count over all lights
// (baker/1_trace_photons.h), here or shared among processes (baker/distribution.h), and bins them, while they are
// traced where the plan allows (PlanBinning) and nothing needs the photons themselves afterwards. With
// --target-noise, rounds follow until the bake's noise meets it (baker/photons/progressive.h); Ctrl-C ends the
// tracing or the rounds; --save-photons writes the store at the end. The driver, and bake-mpi's worker, read as
// "trace a round, estimate, continue?".
//
// Its settings (RoundSettings) are its own, taken from the command line by the driver: the photon counts and
// budgets, the seed, the bounces, whether the points sample the direct light (else the photons store their first
// hit), and the sampled terms' counts as given. It holds no stage's settings: each round it hands out a RoundPlan
// (the shadow rays and gathered paths it chose, the h it holds), from which stage 3's settings are made.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "baker/0_prepare_scene.h"
#include "baker/2_bin_photons.h"
#include "baker/baked_mesh.h"
#include "baker/files/atomic_file.h"
#include "baker/files/photon_file.h"
#include "estimators/density_estimator.h"
#include "baker/photon_store.h"
#include "baker/photons/progressive.h"
#include "baker/runtime/progress.h"
#include "baker/runtime/stage_clock.h"

namespace pb {

class Distribution;

// What the rounds read, as the command line gives it (baker/options.h: the same names and units).
struct RoundSettings {
  std::string scenePath;  // for messages
  uint64_t photons = 0;   // the first round's, over all lights (none with referencePaths)
  uint64_t maxPhotons = 0;
  double maxSeconds = 60;
  uint32_t maxRounds = 0;
  std::optional<float> targetNoise, targetError;
  uint64_t seed = 1;
  uint32_t maxBounces = 0;
  std::string resumePath, savePhotonsPath;
  EstimatorSettings estimator;  // its bandwidth none: --h auto
  uint32_t referencePaths = 0;  // --reference: no photons; the points gather all of H
  bool sh = false;              // the photons keep their directions for --sh
  // The sampled terms as given, which the rounds raise, or cut to fit the time budget: whether the points sample
  // the direct light (else the photons store their first hit), its shadow rays a point and their noise target, and
  // whether they were given (then kept); the paths gathered in gaps, their noise target, and whether given.
  bool sampledDirect = true;
  uint32_t shadowRays = 0;
  double directNoise = 0;
  bool fixedShadowRays = false;
  uint32_t gapPaths = 0;
  double gapNoise = 0;
  bool fixedGapPaths = false;
  bool Rounds() const { return targetNoise || targetError; }  // traced in rounds to a target
};

// What a round's estimate takes from the rounds: the shadow rays a point and their noise target, the paths gathered
// a point in gaps, and --h auto's choice in the first round, held after it (empty: none held).
struct RoundPlan {
  uint32_t shadowRays = 0;
  double directNoise = 0;
  uint32_t gapPaths = 0;
  std::vector<float> heldBandwidths;
};

class PhotonRounds {
 public:
  // Opens the store: empty, or --resume's (every check of baker/files/photon_file.h passed). `distribution`, when
  // given, shares the tracing among processes; it and everything else must outlive the rounds.
  PhotonRounds(const PreparedScene& scene, RoundSettings settings, const Distribution* distribution,
               StageClock& clock, const Log& log);

  // Traces the next round (all of it, or this process's share) and bins the store per surface. An interrupted
  // round whose photons were binned while traced cannot be cut short: InputError.
  void TraceRound();
  // After the round's estimate (its vertices, with their noise, and the bake's noise and predicted error): whether
  // another round follows. False without --target-noise or --target-error, and when the target is met, Ctrl-C
  // came, or a limit ends the rounds. `bandwidths` are the round's h per surface: with --h auto, the first round's
  // are held from then on (unless BandwidthFollows).
  bool Continue(const BakedMesh& baked, double noise, const BakeError& error, const std::vector<float>& bandwidths);
  // Ctrl-C (`interrupted`) or the deadline stopped a later round's estimate: the rounds end, the bake keeping the
  // round before's vertices (reported, and warned about).
  void EstimateInterrupted(bool interrupted);
  // The work of the round's estimate, over every process (IrradianceField::Work): the samples drawn at the points and
  // the gathered paths' rays, which the next round's plan weighs each source's noise against (SharesByWork).
  void CountEstimateWork(uint64_t pointSamples, uint64_t gatheredRays) { work_ = {pointSamples, gatheredRays}; }
  // The time [s since the bake began] after which a round's estimate takes no more vertices: kEstimateDeadlineShare
  // of --max-seconds with rounds, else none (infinity); Ctrl-C stops it too. The first round's pilot foretells its
  // estimate (FitFirstEstimate), and is off by 2-3x on some scenes: this bounds the bake whatever it foretold.
  double EstimateDeadline() const;
  static constexpr double kEstimateDeadlineShare = 0.9;
  // Ctrl-C (`interrupted`) or the deadline stopped the first round's estimate after `done` of `vertices` vertices,
  // the rest estimated at `shadowRays` and `gapPaths` a point (no more than kFinishSamples, given counts too: the
  // budget and Ctrl-C bound the bake): the rounds end there (reported, and warned about). The round's report keeps
  // its own counts, those of the vertices done.
  void FinishFirstEstimate(uint64_t done, uint64_t vertices, bool interrupted, uint32_t shadowRays, uint32_t gapPaths);
  static constexpr uint32_t kFinishSamples = 4;
  // Before the first round's estimate, which nothing cuts short once it runs (a later round's falls back on the
  // round before): with --target-noise or --target-error, where the estimate foretold to take `estimateSeconds` (a
  // pilot's) would end the bake past kFirstRoundShare of --max-seconds, cuts the round's shadow rays and gathered
  // paths (those not given) in proportion to what is left, to no fewer than kFewestCutSamples; reported. Whether it
  // cut them (the field must then be built again). With a distribution, `estimateSeconds` is each process's
  // foretelling of all the chunks, which the processes share, and rank 0 decides for all.
  bool FitFirstEstimate(double estimateSeconds);
  static constexpr double kFirstRoundShare = 0.8;
  static constexpr uint32_t kFewestCutSamples = 16;
  // When the rounds ended on their own (their target met, or a limit) before kFirstRoundShare of --max-seconds,
  // the time [s since the bake began] until which what is left may be spent on the estimate's vertices
  // (GatherSmallSurfacesLeft, baker/photons/trace_and_estimate.h); nullopt without rounds, after Ctrl-C or a stopped
  // estimate, and on processes that do not decide (a distribution's ranks but 0). A first round cut to fit the
  // budget may leave time too: its pilot reads the photons directly where gathered paths end, so it foretells more
  // than the estimate takes (the sports car: 56 s foretold, 34 s taken).
  std::optional<double> SpareTimeUntil() const;
  // What that time gathered, for the report.
  void SmallSurfacesGathered(const ProgressiveReport::SmallSurfaces& small) { report_.small = small; }
  // Writes --save-photons, when given.
  void Save(OutputFiles& outputs);

  // This round's shadow rays and gathered paths (the rounds may raise them, or cut the first round's) and the h held.
  RoundPlan Plan() const { return {shadowRays_, directNoise_, gapPaths_, heldBandwidths_}; }
  const RoundSettings& Settings() const { return settings_; }
  const PhotonStore& Store() const { return store_; }
  const SurfaceBins& Bins() const { return bins_; }
  const ProgressiveReport& Report() const { return report_; }
  // Whether the round traced last is the first, on every process.
  bool FirstRound() const { return traced_ == 1; }

 private:
  PhotonOrigin Origin() const;
  bool BinsWhileTracing(const BinningPlan& plan) const;
  // Whether this process decides what the rounds do and says it: the only one, or a distribution's rank 0.
  bool Decides() const;
  void ShareThePlan(bool& more);
  bool CutFirstEstimate(double estimateSeconds);
  void ShareTheCut(bool& cut);
  double MemoryForRounds() const;
  void HoldFirstRoundToMemory();
  static constexpr double kMostHitsPerPhoton = 64;
  bool Grow(const HitSink* sink);
  std::string Stopper(bool interrupted) const;
  RoundState StateAfterRound() const;
  // With --h auto, h is held at the first round's choice, so that the noise falls as 1 / sqrt(photons); with
  // --target-error, where the first round's predicted smoothing bias passes half the target, h is chosen again
  // from each round's photons instead, so that the bias falls with them (where it did not, chosen again it shrank
  // faster than the noise could follow: the office with books took 3 rounds and 17M photons for 3%).
  bool BandwidthFollows(const BakeError& error) const {
    return !settings_.estimator.bandwidth && settings_.targetError && error.bias > kFollowingBias * *settings_.targetError;
  }
  static constexpr double kFollowingBias = 0.5;
  bool LastRound(const BakedMesh& baked, double noise, const BakeError& error);

  const PreparedScene& scene_;
  const RoundSettings settings_;
  uint32_t shadowRays_;  // settings_'s, as the rounds chose them
  double directNoise_;
  uint32_t gapPaths_;
  const Distribution* distribution_;
  StageClock& clock_;
  const Log& log_;
  const double baseline_;  // the memory in use before the first photon [bytes] (MemoryInUseBytes)
  PhotonStore store_;
  SurfaceBins bins_;
  ProgressiveReport report_;
  uint64_t photons_ = 0;                // the round's count over all lights
  std::vector<float> heldBandwidths_;
  bool bandwidthFollows_ = false;  // BandwidthFollows, decided after the first round
  // The bake's wall, tracing and binning time [s], read together.
  struct ClockReading {
    double elapsed = 0, traced = 0, binned = 0;
  };
  ClockReading ReadClock() const { return {clock_.Elapsed(), clock_.Seconds("trace"), clock_.Seconds("bin")}; }
  ClockReading roundStart_;  // when the round began
  uint32_t traced_ = 0;      // rounds traced, on every process (report_.rounds is rank 0's alone)
  struct {
    uint64_t pointSamples = 0, gatheredRays = 0;
  } work_;  // CountEstimateWork's
};

}  // namespace pb
