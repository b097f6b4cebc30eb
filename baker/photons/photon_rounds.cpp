#include "baker/photons/photon_rounds.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "baker/distribution.h"
#include "baker/files/photon_file.h"
#include "baker/runtime/interrupt.h"
#include "mesh/memory_budget.h"
#include "mesh/errors.h"

namespace pb {
namespace {

// Every process is ready, or this one stops (rank 0 names those that are not).
void RequireAllReady(const Distribution& d) {
  const std::vector<bool> ready = d.Agree(true);
  std::string missing;
  for (size_t r = 0; r < ready.size(); ++r)
    if (!ready[r]) missing += (missing.empty() ? "" : ", ") + std::to_string(r);
  if (!missing.empty()) throw InputError("bake-mpi", 0, "rank " + missing + " could not start the bake (its message is above)");
}

}  // namespace

PhotonRounds::PhotonRounds(const PreparedScene& scene, RoundSettings settings, const Distribution* distribution,
                           StageClock& clock, const Log& log)
    : scene_(scene),
      settings_(std::move(settings)),
      shadowRays_(settings_.shadowRays),
      directNoise_(settings_.directNoise),
      gapPaths_(settings_.gapPaths),
      distribution_(distribution),
      clock_(clock),
      log_(log),
      baseline_(MemoryInUseBytes()),
      // --reference traces none: the field gathers all of H at the points.
      photons_(settings_.referencePaths > 0 ? 0 : settings_.photons) {
  report_.target = settings_.targetError ? settings_.targetError : settings_.targetNoise;
  report_.targetIsError = settings_.targetError.has_value();
  store_ = clock_.Time("trace", [&] {
    PhotonStore empty = EmptyPhotonStore(scene.lights);
    if (settings_.resumePath.empty()) return empty;
    PhotonStore store = ReadPhotonFile(settings_.resumePath, Origin(), empty.lightPower, scene.scene.triangles.size());
    report_.resumedFrom = settings_.resumePath;
    report_.resumedPhotons = store.stats.emitted;
    return store;
  });
  if (settings_.referencePaths == 0) photons_ = std::max(photons_, report_.resumedPhotons);
  if (settings_.Rounds() && settings_.resumePath.empty()) HoldFirstRoundToMemory();
}

// What a round may add to the memory the bake held before its first photon [bytes].
double PhotonRounds::MemoryForRounds() const {
  return std::max(kUsableMemoryShare * MemoryLimitBytes() - baseline_, 0.0);
}

// The first round is sized before any photon is traced (--target-error's from the target, up to 32M photons), so
// it is held to the memory for rounds at the most a photon may need: a hit a scattering, whose mean number Russian
// roulette by the largest albedo bounds by 1 / (1 - Kd) (at most kMostHitsPerPhoton; the blocks reserve
// kReservedHitsPerPhoton at least), and as much again for the estimate. The later rounds are held by what a photon
// took (StateAfterRound).
void PhotonRounds::HoldFirstRoundToMemory() {
  const double albedo = std::clamp(double(scene_.plan.largestAlbedo), 0.0, 1.0);
  const double hits = albedo < 1 ? std::min(kMostHitsPerPhoton, 1 / (1 - albedo)) : kMostHitsPerPhoton;
  const double perPhoton = 2 * std::max(hits, double(kReservedHitsPerPhoton)) * sizeof(PhotonHit);
  const double most = MemoryForRounds() / perPhoton;
  if (MemoryLimitBytes() <= 0 || double(photons_) <= most) return;
  photons_ = std::max<uint64_t>(uint64_t(most), 1);
  log_.Warning(fmt::format("the first round is held to {} photons: at up to {:.0f} bytes a photon (largest Kd {:.2f}) "
                           "more would pass {:.0f}% of {} {:.1f} GB of memory", photons_, perPhoton, albedo,
                           100 * kUsableMemoryShare, MemoryLimitName(), MemoryLimitBytes() / 1e9));
}

// What a photon file must have been traced with to continue: the scene, the seed, the bounces and the effects the
// photons carry (the direct light not, when the points sample it).
PhotonOrigin PhotonRounds::Origin() const {
  uint32_t effects = SimulatedEffects(scene_.plan);
  if (settings_.sampledDirect) effects &= ~(1u << uint32_t(Effect::kDirect));
  return {SceneHash(scene_.scene), settings_.seed, settings_.maxBounces, effects};
}

// Whether the photons are binned as they are traced (baker/2_bin_photons.h): where the plan bins every wide surface
// and nothing needs the photons themselves afterwards (a photon file written or extended, rounds).
bool PhotonRounds::BinsWhileTracing(const BinningPlan& plan) const {
  return plan.wide && settings_.savePhotonsPath.empty() && settings_.resumePath.empty() && !settings_.Rounds();
}

// Grows the store to photons_ over all lights (counts never shrink). Hits go to `sink` when given; the work is
// shared when the bake is. Returns whether tracing completed; without a sink an interruption is noted and warned
// about, with one the caller refuses it.
bool PhotonRounds::Grow(const HitSink* sink) {
  const TraceSettings settings{photons_, settings_.seed, settings_.maxBounces, !settings_.sampledDirect, sink, distribution_};
  if (ExtendPhotons(store_, scene_, settings, log_)) return true;
  if (sink != nullptr) return false;
  report_.interrupted = true;
  if (report_.rounds.empty())  // in a later round, the estimate stops too (EstimateInterrupted says so)
    log_.Warning(fmt::format("interrupted: tracing stopped after {} photons; the bake goes on with them and writes "
                             "valid outputs (Ctrl-C again to quit at once)", store_.stats.emitted));
  return false;
}

void PhotonRounds::TraceRound() {
  roundStart_ = ReadClock();
  ++traced_;
  const BinningPlan plan = PlanBinning(scene_, settings_.estimator, photons_);
  if (distribution_ != nullptr && !distribution_->Agreed()) RequireAllReady(*distribution_);  // once, before any photon
  std::optional<PhotonBinner> binner;
  if (BinsWhileTracing(plan)) binner.emplace(scene_, plan, settings_.sh);
  const PhotonBinner* sink = binner ? &*binner : nullptr;
  bool complete = true;
  clock_.Time("trace", [&] { complete = Grow(sink); });
  if (distribution_ != nullptr && binner)  // else every process took every process's blocks (baker/distribution.h)
    clock_.Time("trace", [&] { binner->SumWith([&](std::span<int64_t> v) { distribution_->SumOnAll(v); }); });
  if (binner && !complete)  // the photons' flux Phi_l / N_l was binned for the N_l planned
    throw InputError(settings_.scenePath, 0, fmt::format("interrupted after {} photons: nothing was written, since photons "
                                                        "binned while they are traced cannot be cut short (with "
                                                        "--save-photons they are stored, and an interrupted bake writes "
                                                        "what it has)", store_.stats.emitted));
  const Scene* directionsIn = settings_.sh ? &scene_.scene : nullptr;
  bins_ = clock_.Time("bin", [&] {
    SurfaceBins bins = BinPhotons(scene_.surfaces, store_, log_, plan, binner ? &*binner : nullptr, directionsIn);
    if (!settings_.estimator.bandwidth) PoolSparseHits(scene_.scene, scene_.surfaces, store_, bins);
    return bins;
  });
}

namespace {

// The rays a photon cast on average: one to each surface it met and one for its end where it left the scene.
double RaysPerPhoton(const TraceStats& s) {
  const double rays = double(s.diffuseBounces + s.SpecularEvents() + s.absorbed + s.escaped + s.forbidden + s.truncated);
  return s.emitted > 0 ? rays / double(s.emitted) : 0.0;
}

}  // namespace

// Where the rounds of --target-noise stand after one (baker/photons/progressive.h).
RoundState PhotonRounds::StateAfterRound() const {
  const bool sampled = settings_.sampledDirect;
  const double emitted = double(std::max<uint64_t>(store_.stats.emitted, 1));
  const ClockReading now = ReadClock(), start = roundStart_;
  return {.photons = photons_,
          .shadowRays = sampled ? shadowRays_ : 0,
          .directNoise = sampled ? directNoise_ : 0,
          .raiseShadowRays = sampled && !settings_.fixedShadowRays,
          .bandwidthFollows = bandwidthFollows_,
          .gapPaths = sampled && settings_.referencePaths == 0 ? gapPaths_ : 0,
          .raiseGapPaths = sampled && gapPaths_ > 0 && settings_.gapNoise == 0 && !settings_.fixedGapPaths,
          .elapsed = now.elapsed,
          .traceSeconds = now.traced,
          .binSeconds = now.binned - start.binned,
          .estimateSeconds = now.elapsed - start.elapsed - (now.traced - start.traced) - (now.binned - start.binned),
          .bytesPerPhoton = std::max(double(store_.StoredHits() * sizeof(PhotonHit)), PeakMemoryBytes() - baseline_) / emitted,
          .raysPerPhoton = RaysPerPhoton(store_.stats),
          .pointWork = double(work_.pointSamples),
          .gatheredWork = double(work_.gatheredRays)};
}

// Ends the rounds (true) when the target is met, Ctrl-C came or the next round cannot help or fit; else sets the
// next round's photons and shadow rays.
bool PhotonRounds::LastRound(const BakedMesh& baked, double noise, const BakeError& error) {
  const float target = *report_.target;
  if (report_.rounds.empty()) bandwidthFollows_ = BandwidthFollows(error);
  const RoundState state = StateAfterRound();
  report_.rounds.push_back({photons_, store_.stats.emitted, state.shadowRays, state.directNoise, noise, error.Total(),
                            state.elapsed, state.gapPaths});
  const std::string rays = ShadowRays(report_.rounds.back());
  const std::string measured = report_.targetIsError
                                   ? fmt::format("error {:.4f} (noise {:.4f}, bias {:.4f}; target {:.4f})", error.Total(),
                                                 error.noise, error.bias, target)
                                   : fmt::format("noise {:.4f} (target {:.4f})", noise, target);
  log_.Info(fmt::format("round {}: {} photons{}, {}, {:.1f} s", report_.rounds.size(), store_.stats.emitted,
                        rays.empty() ? "" : ", " + rays, measured, state.elapsed));
  if (report_.Measured(report_.rounds.back()) <= target || report_.interrupted || report_.finishedVertices > 0)
    return true;
  if (settings_.maxRounds > 0 && report_.rounds.size() >= settings_.maxRounds) {
    report_.stoppedBy = fmt::format("--max-rounds {}", settings_.maxRounds);
    return true;
  }
  if (InterruptRequested()) {  // Ctrl-C came after this round's tracing: no further round
    report_.interrupted = true;
    log_.Warning("interrupted: no further rounds; the bake goes on with the photons it has");
    return true;
  }
  const NextRound next = PlanNextRound(baked, state, {target, settings_.maxPhotons, settings_.maxSeconds,
                                                      MemoryForRounds(), report_.targetIsError});
  report_.stoppedBy = next.stop;
  if (!next.stop.empty()) return true;
  photons_ = next.photons, shadowRays_ = std::max(next.shadowRays, 1u), directNoise_ = next.directNoise;
  if (next.gapPaths > 0) gapPaths_ = next.gapPaths;
  return false;
}

bool PhotonRounds::Continue(const BakedMesh& baked, double noise, const BakeError& error,
                            const std::vector<float>& bandwidths) {
  if (!settings_.Rounds()) return false;
  bool more = Decides() && !LastRound(baked, noise, error);  // the others hold their own vertices only
  if (distribution_ != nullptr) ShareThePlan(more);
  if (!more) return false;
  if (!settings_.estimator.bandwidth && heldBandwidths_.empty() && !bandwidthFollows_) heldBandwidths_ = bandwidths;
  return true;
}

bool PhotonRounds::Decides() const { return distribution_ == nullptr || distribution_->Root(); }

// Rank 0's decision after a round, and the next round's plan, into every process's (baker/distribution.h). The
// bandwidths to hold are every process's own: the same field, from the same photons.
void PhotonRounds::ShareThePlan(bool& more) {
  struct Plan {
    uint64_t photons;
    double directNoise;
    uint32_t shadowRays, gapPaths;
    uint8_t more, bandwidthFollows;
  } plan{photons_, directNoise_, shadowRays_, gapPaths_, more, bandwidthFollows_};
  distribution_->Broadcast(std::as_writable_bytes(std::span(&plan, 1)));
  photons_ = plan.photons, shadowRays_ = plan.shadowRays, gapPaths_ = plan.gapPaths;
  directNoise_ = plan.directNoise, more = plan.more != 0, bandwidthFollows_ = plan.bandwidthFollows != 0;
}

bool PhotonRounds::FitFirstEstimate(double estimateSeconds) {
  if (!settings_.Rounds() || !FirstRound()) return false;
  bool cut = Decides() && CutFirstEstimate(distribution_ ? estimateSeconds / distribution_->Size() : estimateSeconds);
  if (distribution_ != nullptr) ShareTheCut(cut);
  return cut;
}

// Whether the first round's estimate, foretold to take `estimateSeconds` on this process's share of the chunks,
// is cut to fit the budget (FitFirstEstimate); if so, its counts are cut.
bool PhotonRounds::CutFirstEstimate(double estimateSeconds) {
  const double left = kFirstRoundShare * settings_.maxSeconds - clock_.Elapsed();
  if (estimateSeconds <= left) return false;
  const double cut = std::max(left, 0.0) / estimateSeconds;
  const auto fewer = [&](uint32_t n) { return std::max(std::min(n, kFewestCutSamples), uint32_t(std::floor(n * cut))); };
  const bool rays = settings_.sampledDirect && !settings_.fixedShadowRays && settings_.referencePaths == 0;
  const bool paths = gapPaths_ > 0 && !settings_.fixedGapPaths;
  if (!rays && !paths) return false;
  if (rays) shadowRays_ = fewer(shadowRays_);
  if (paths) gapPaths_ = fewer(gapPaths_);
  report_.firstRoundCut = cut, report_.firstRoundForetold = estimateSeconds;
  log_.Warning(fmt::format("the first round's estimate would take about {:.0f} s, past the time budget (--max-seconds "
                           "{:g}): its shadow rays and gathered paths are cut to {} and {} a point",
                           estimateSeconds, settings_.maxSeconds, shadowRays_, gapPaths_));
  return true;
}

// Rank 0's cut of the first round (each process's clock and pilot differ), into every process's.
void PhotonRounds::ShareTheCut(bool& cut) {
  struct Cut {
    double cut, foretold;
    uint32_t shadowRays, gapPaths;
    uint8_t fitted;
  } shared{report_.firstRoundCut, report_.firstRoundForetold, shadowRays_, gapPaths_, cut};
  distribution_->Broadcast(std::as_writable_bytes(std::span(&shared, 1)));
  report_.firstRoundCut = shared.cut, report_.firstRoundForetold = shared.foretold;
  shadowRays_ = shared.shadowRays, gapPaths_ = shared.gapPaths, cut = shared.fitted != 0;
}

std::optional<double> PhotonRounds::SpareTimeUntil() const {
  const double until = kFirstRoundShare * settings_.maxSeconds;
  if (!settings_.Rounds() || !Decides() || report_.interrupted || report_.estimateStopped ||
      report_.finishedVertices > 0 || clock_.Elapsed() >= until)
    return std::nullopt;
  return until;
}

double PhotonRounds::EstimateDeadline() const {
  return settings_.Rounds() ? kEstimateDeadlineShare * settings_.maxSeconds : INFINITY;
}

// What stopped an estimate, for the report: "Ctrl-C" or the deadline.
std::string PhotonRounds::Stopper(bool interrupted) const {
  return interrupted ? std::string("Ctrl-C")
                     : fmt::format("the estimate's deadline ({:.0f}% of --max-seconds {:g})",
                                   100 * kEstimateDeadlineShare, settings_.maxSeconds);
}

void PhotonRounds::EstimateInterrupted(bool interrupted) {
  report_.interrupted |= interrupted;
  report_.estimateStopped = true;
  if (!Decides()) return;  // every process stopped; rank 0, which holds the rounds' report, says so
  const RoundReport& kept = report_.rounds.back();
  report_.stoppedBy = fmt::format("{} during round {}, whose estimate stopped: the vertices are round {}'s",
                                  Stopper(interrupted), report_.rounds.size() + 1, report_.rounds.size());
  log_.Warning(fmt::format("{}: round {}'s estimate stopped; the vertices are round {}'s ({} photons, noise "
                           "{:.4f}); maps and refinement read all {} photons", interrupted ? "interrupted" : "time budget",
                           report_.rounds.size() + 1, report_.rounds.size(), kept.photons, kept.noise,
                           store_.stats.emitted));
}

void PhotonRounds::FinishFirstEstimate(uint64_t done, uint64_t vertices, bool interrupted, uint32_t shadowRays,
                                       uint32_t gapPaths) {
  report_.interrupted |= interrupted;
  report_.finishedVertices = vertices - done;
  report_.stoppedBy = fmt::format("{} during round 1's estimate, {} of {} vertices in: the rest read {} shadow rays "
                                  "and {} gathered paths a point", Stopper(interrupted), done, vertices,
                                  shadowRays, gapPaths);
  if (!Decides()) return;
  log_.Warning(fmt::format("{}: stopped by {}; the vertices left are estimated at the fewest samples, and the "
                           "predicted noise says what that costs", interrupted ? "interrupted" : "time budget",
                           report_.stoppedBy));
}

void PhotonRounds::Save(OutputFiles& outputs) {
  clock_.Time("save photons", [&] {
    if (settings_.savePhotonsPath.empty() || (distribution_ != nullptr && !distribution_->Root())) return;
    WritePhotonFile(outputs, settings_.savePhotonsPath, store_, Origin());
    report_.savedTo = settings_.savePhotonsPath;
  });
}

}  // namespace pb
