#include "baker/photons/trace_and_estimate.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <functional>
#include <span>
#include <type_traits>

#include "baker/distribution.h"
#include "baker/runtime/interrupt.h"

namespace pb {
namespace {

// Stage 3's own settings, with the shadow rays, gathered paths and held h the rounds planned.
FieldSettings FieldSettingsOf(FieldSettings field, const PhotonRounds& rounds) {
  RoundPlan plan = rounds.Plan();
  field.direct.samples = plan.shadowRays, field.direct.noise = plan.directNoise;
  field.gaps.paths = plan.gapPaths;
  field.heldBandwidths = std::move(plan.heldBandwidths);
  return field;
}

// Rank 0 takes every process's vertices (baker/distribution.h).
void GatherVertices(BakedMesh& baked, const Distribution& d) {
  const auto gather = [&](auto& values) {
    d.GatherChunks(std::as_writable_bytes(std::span(values)), sizeof(values[0]), kVertexChunk);
  };
  gather(baked.irradiance), gather(baked.albedo), gather(baked.emitted);
  gather(baked.irradianceNoise), gather(baked.photonVarianceShare), gather(baked.sampledShare);
  gather(baked.irradianceBias), gather(baked.gatheredVarianceShare), gather(baked.gapPairs);
}

// The first round's estimate of every vertex foretold from a pilot over one vertex in kPilotStride, spread over
// the whole mesh [s]: what its field costs on this scene, at this round's settings, on this machine. Its gathered
// paths read the photons where they end directly (IrradianceField::ReadPathEndsDirectly): the tables that spare
// the whole estimate most of that cost would be filled at nearly every end of so few points' paths (the
// staircase's pilot foretold 44 s of an estimate that took 23 s). So the foretold time is an upper bound.
constexpr size_t kPilotStride = 64;
double ForetoldEstimateSeconds(IrradianceField& field, const SplitMesh& base, StageClock& clock) {
  const double before = clock.Seconds("estimate");
  const size_t piloted = (base.VertexCount() + kPilotStride - 1) / kPilotStride;
  field.ReadPathEndsDirectly(true);
  clock.Time("estimate", [&] {
    tbb::parallel_for(size_t(0), piloted, [&](size_t k) { field.LightWithNoise(base.Point(k * kPilotStride)); });
  });
  field.ReadPathEndsDirectly(false);
  return piloted > 0 ? (clock.Seconds("estimate") - before) * double(base.VertexCount()) / double(piloted) : 0.0;
}

// Copies into `into` the vertices of every chunk (kVertexChunk vertices) that `taken` leaves 0, from `from`.
void TakeUntakenChunks(BakedMesh& into, const BakedMesh& from, const std::vector<char>& taken) {
  const auto take = [&](auto& to, const auto& source) {
    for (size_t c = 0; c < taken.size(); ++c) {
      if (taken[c] != 0) continue;
      const size_t begin = c * kVertexChunk, end = std::min(to.size(), begin + kVertexChunk);
      std::copy(source.begin() + ptrdiff_t(begin), source.begin() + ptrdiff_t(end), to.begin() + ptrdiff_t(begin));
    }
  };
  take(into.irradiance, from.irradiance), take(into.albedo, from.albedo), take(into.emitted, from.emitted);
  take(into.irradianceNoise, from.irradianceNoise), take(into.photonVarianceShare, from.photonVarianceShare);
  take(into.sampledShare, from.sampledShare), take(into.irradianceBias, from.irradianceBias);
  take(into.gatheredVarianceShare, from.gatheredVarianceShare), take(into.gapPairs, from.gapPairs);
}

// The first round's chunks that a stopped estimate did not take (`taken` 0), estimated into `baked` at no more than
// PhotonRounds::kFinishSamples shadow rays and gathered paths a point, from the round's photon estimators with
// those terms built anew; lit's field becomes that field, and the rounds report it.
void FinishAtTheFewestSamples(BakedMesh& baked, Lit& lit, const PreparedScene& scene, const SplitMesh& base,
                              const FieldSettings& field, PhotonRounds& rounds, const std::vector<char>& taken,
                              bool interrupted, StageClock& clock, const Log& log) {
  uint64_t done = 0;
  for (size_t c = 0; c < taken.size(); ++c)
    if (taken[c] != 0) done += std::min<uint64_t>(kVertexChunk, base.VertexCount() - c * kVertexChunk);
  FieldSettings fewest = FieldSettingsOf(field, rounds);
  if (fewest.direct.mode == DirectLight::kSampled)
    fewest.direct.samples = std::min(fewest.direct.samples, PhotonRounds::kFinishSamples), fewest.direct.noise = 0;
  fewest.gaps.paths = std::min(fewest.gaps.paths, PhotonRounds::kFinishSamples);
  rounds.FinishFirstEstimate(done, base.VertexCount(), interrupted, fewest.direct.samples, fewest.gaps.paths);
  lit.field.emplace(WithSampledTerms(*std::move(lit.field), scene, fewest, clock));
  const BakedMesh rest = clock.Time("estimate", [&] {
    return EstimateIrradiance(*lit.field, base, log, /*withNoise=*/true, [&](size_t c) { return taken[c] == 0; });
  });
  TakeUntakenChunks(baked, rest, taken);
}

// The work of a round's estimate (`work`: this process's), over every process, to the rounds.
void CountTheWork(const FieldWork& work, PhotonRounds& rounds, const Distribution* d) {
  std::array<int64_t, 2> counts{int64_t(work.pointSamples), int64_t(work.gatheredRays)};
  if (d != nullptr) d->SumOnAll(counts);
  rounds.CountEstimateWork(uint64_t(counts[0]), uint64_t(counts[1]));
}

// The bake's noise, predicted error and the noise's parts, from its vertices'.
void JudgeTheVertices(Lit& lit, StageClock& clock) {
  clock.Time("noise", [&] {
    lit.noise = BakeNoise(lit.baked), lit.error = PredictedError(lit.baked), lit.noiseParts = BakeNoiseParts(lit.baked);
  });
}

// The round's estimate at the vertices of `base`, each with its noise; with a distribution, this process's chunks
// of them. It takes no more chunks once Ctrl-C comes (on one process) or the rounds' deadline passes
// (PhotonRounds::EstimateDeadline): a later round then ends there (nullopt; lit keeps the round before's vertices,
// with the new round's field), and the first round estimates the chunks left at the fewest samples, with a field
// built for them (PhotonRounds::FinishFirstEstimate), so that the bake ends within its budget with valid outputs.
// With a distribution, each process stops claiming chunks at its own clock's deadline, and the chunks that none
// claimed, which every process learns from the claims, are the ones left.
std::optional<BakedMesh> EstimateUntilStopped(Lit& lit, const PreparedScene& scene, const SplitMesh& base,
                                              const FieldSettings& field, PhotonRounds& rounds, const Distribution* d,
                                              StageClock& clock, const Log& log) {
  const bool mayStop = base.VertexCount() > 0;
  const double deadline = rounds.EstimateDeadline();
  std::vector<char> taken((base.VertexCount() + kVertexChunk - 1) / kVertexChunk, 0);
  std::atomic<bool> stopped{false};
  const FieldWork before = lit.field->Work();
  const auto owns = [&](size_t chunk) {
    if (mayStop && (stopped || (d == nullptr && InterruptRequested()) || clock.Elapsed() > deadline)) {
      stopped = true;
      return false;
    }
    if (d != nullptr) return d->ClaimChunk(chunk);
    taken[chunk] = 1;
    return true;
  };
  BakedMesh baked = clock.Time("estimate", [&] {
    if (d != nullptr) d->OpenChunks(taken.size());
    BakedMesh estimated = EstimateIrradiance(*lit.field, base, log, /*withNoise=*/true, owns);
    if (d != nullptr) d->CloseChunks();
    return estimated;
  });
  if (d != nullptr) {
    for (size_t c = 0; c < taken.size(); ++c) taken[c] = d->ChunkHolder(c) != Distribution::kNobody;
    stopped = std::find(taken.begin(), taken.end(), 0) != taken.end();
  }
  CountTheWork(lit.field->Work() - before, rounds, d);
  if (!stopped) return baked;
  const bool interrupted = d == nullptr && InterruptRequested();
  if (lit.baked.mesh.VertexCount() > 0) {
    rounds.EstimateInterrupted(interrupted);
    return std::nullopt;
  }
  FinishAtTheFewestSamples(baked, lit, scene, base, field, rounds, taken, interrupted, clock, log);
  return baked;
}

// Stage 3 from the round's photons at the vertices of `base`, with each vertex's noise and the bake's; with a
// distribution, each process estimates its share of the vertices for rank 0. False where a later round's estimate
// stopped (EstimateUntilStopped): lit then keeps the round before's vertices.
bool EstimateLight(Lit& lit, const PreparedScene& scene, const SplitMesh& base, const FieldSettings& field,
                   PhotonRounds& rounds, const Distribution* d, StageClock& clock, const Log& log) {
  lit.field.emplace(BuildIrradianceField(scene, rounds.Bins(), FieldSettingsOf(field, rounds), clock, &log));
  const bool first = rounds.FirstRound() && rounds.Settings().Rounds();
  const bool root = d == nullptr || d->Root();  // which foretells for all
  if (first && rounds.FitFirstEstimate(root ? ForetoldEstimateSeconds(*lit.field, base, clock) : 0.0))
    lit.field.emplace(WithSampledTerms(*std::move(lit.field), scene, FieldSettingsOf(field, rounds), clock));
  std::optional<BakedMesh> baked = EstimateUntilStopped(lit, scene, base, field, rounds, d, clock, log);
  if (!baked) return false;
  lit.baked = std::move(*baked);
  if (d != nullptr) clock.Time("estimate", [&] { GatherVertices(lit.baked, *d); });
  if (!root) return true;  // the others hold their own vertices only
  clock.Time("estimate", [&] { WeighGatheredPaths(*lit.field, lit.baked); });
  JudgeTheVertices(lit, clock);
  return true;
}

// The vertices of `mesh` on each of `surfaces`, in their order.
std::vector<std::vector<uint32_t>> VerticesOn(const SplitMesh& mesh, std::span<const uint32_t> surfaces) {
  std::vector<uint32_t> rank(*std::max_element(surfaces.begin(), surfaces.end()) + 1, UINT32_MAX);
  for (size_t k = 0; k < surfaces.size(); ++k) rank[surfaces[k]] = uint32_t(k);
  std::vector<std::vector<uint32_t>> on(surfaces.size());
  for (size_t v = 0; v < mesh.VertexCount(); ++v) {
    const uint32_t s = mesh.surface[v];
    if (s < rank.size() && rank[s] != UINT32_MAX) on[rank[s]].push_back(uint32_t(v));
  }
  return on;
}

// Learns the weights of the surfaces whose points `lights` gathered at (surfaces the first estimate gathered nowhere)
// and mixes their light by them, as the first estimate's vertices were (WeighGatheredPaths).
void WeighTheirPaths(IrradianceField& field, std::vector<SurfaceLight>& lights) {
  std::vector<GapPair> pairs(lights.size());
  std::transform(lights.begin(), lights.end(), pairs.begin(), [](const SurfaceLight& l) { return l.gap; });
  field.WeighGaps(pairs);
  for (SurfaceLight& light : lights) field.Remix(light);
}

// The lights of a batch's vertices shared among the processes of `d`: chunks of kSharedChunk vertices, each
// estimated by the process that claims it first while it is not `late`, gathered on rank 0. Whole when every chunk
// was claimed, which every process then knows (ChunkHolder), so that all keep or drop the batch together.
constexpr size_t kSharedChunk = 32;
bool ShareTheBatch(const Lit& lit, const std::vector<uint32_t>& batch, std::vector<SurfaceLight>& lights,
                   const std::function<bool()>& late, const Distribution& d) {
  static_assert(std::is_trivially_copyable_v<SurfaceLight>, "lights travel as bytes");
  const size_t chunks = (batch.size() + kSharedChunk - 1) / kSharedChunk;
  d.OpenChunks(chunks);
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    if (late() || !d.ClaimChunk(c)) return;
    for (size_t i = c * kSharedChunk; i < std::min(batch.size(), (c + 1) * kSharedChunk); ++i)
      lights[i] = lit.field->LightWithNoise(lit.baked.mesh.Point(batch[i]));
  });
  d.CloseChunks();
  for (size_t c = 0; c < chunks; ++c)
    if (d.ChunkHolder(c) == Distribution::kNobody) return false;
  d.GatherChunks(std::as_writable_bytes(std::span(lights)), sizeof(SurfaceLight), kSharedChunk);
  return true;
}

// Gathers at the vertices of `surfaces` into `baked`, unless `until` [s on the clock] or Ctrl-C comes first, when
// nothing changes: false. With `d`, every process takes its part (ShareTheBatch) and rank 0 keeps the lights; the
// others mark the surfaces gathered, as rank 0 does, and learn its weights with the maps (LateState).
bool GatherWhole(Lit& lit, std::span<const uint32_t> surfaces, std::span<const std::vector<uint32_t>> vertices,
                 double until, const Distribution* d, StageClock& clock) {
  std::vector<uint32_t> batch;
  for (const auto& on : vertices) batch.insert(batch.end(), on.begin(), on.end());
  for (uint32_t s : surfaces) lit.field->GatherAtPoints(s, true);
  std::vector<SurfaceLight> lights(batch.size());
  std::atomic<bool> stopped{false};
  const std::function<bool()> late = [&] {
    if (!stopped && (clock.Elapsed() > until || InterruptRequested())) stopped = true;
    return bool(stopped);
  };
  bool whole = true;
  if (d != nullptr) {
    whole = ShareTheBatch(lit, batch, lights, late, *d);
  } else {
    tbb::parallel_for(size_t(0), batch.size(), [&](size_t i) {
      if (!late()) lights[i] = lit.field->LightWithNoise(lit.baked.mesh.Point(batch[i]));
    });
    whole = !stopped;
  }
  if (!whole) {
    for (uint32_t s : surfaces) lit.field->GatherAtPoints(s, false);
    return false;
  }
  if (d != nullptr && !d->Root()) return true;
  WeighTheirPaths(*lit.field, lights);
  for (size_t i = 0; i < batch.size(); ++i) SetVertexLight(lit.baked, batch[i], lights[i]);
  return true;
}

// Rank 0's spare time into every process of `d` (none without one): whether the pass runs, and until when.
std::optional<double> RankZerosSpareTime(std::optional<double> until, const Distribution* d) {
  if (d == nullptr) return until;
  struct Shared {
    double until;
    uint8_t runs;
  } shared{until.value_or(0.0), uint8_t(until ? 1 : 0)};
  d->Broadcast(std::as_writable_bytes(std::span(&shared, 1)));
  return shared.runs != 0 ? std::optional<double>(shared.until) : std::nullopt;
}

// At least this many vertices are gathered together (whole surfaces, in parallel).
constexpr size_t kGatheredTogether = 256;

// With the time the rounds left (PhotonRounds::SpareTimeUntil), the surfaces smaller than their kernel that the
// defaults' share of the triangles (kDefaultSmallShare: a scene of tiny faces must not gather everywhere) left to
// the photons are gathered at their vertices, the smallest first, whole surfaces at a time, until that time or
// Ctrl-C. The pooled photons read such parts from their surroundings (the staircase's brass fittings 25-30%
// bright); gathered paths read their own light. The paths gathered elsewhere read their photons as before, so no
// other vertex changes, and the bake's noise is judged again. It depends on the machine's speed where the time ends
// before the last surface (the report says how many were gathered); --gap-small-area, given, gathers on every small
// surface from the start.
//
// In a distributed bake the processes share each batch's vertices (GatherWhole); rank 0 decides whether the pass runs
// and until when (its rounds hold the time), and alone reports it and judges the vertices again. A progress line
// counts the vertices of every surface left (at 1,024 paths a point the staircase's pass ran for minutes without
// a word), within the time the rounds left; one that ends below 100% is that time running out.
void GatherSmallSurfacesLeft(Lit& lit, PhotonRounds& rounds, const Distribution* d, StageClock& clock, const Log& log) {
  std::optional<double> until = rounds.SpareTimeUntil();
  const std::span<const uint32_t> left = lit.field->SmallLeftOut();
  if (left.empty() || lit.baked.irradianceNoise.empty()) until.reset();
  until = RankZerosSpareTime(until, d);
  if (!until) return;
  ProgressiveReport::SmallSurfaces small{uint32_t(left.size())};
  const double start = clock.Elapsed();
  const std::vector<std::vector<uint32_t>> vertices = VerticesOn(lit.baked.mesh, left);
  size_t all = 0;
  for (const auto& on : vertices) all += on.size();
  clock.Time("small surfaces", [&] {  // apart from "estimate", whose seconds per vertex foretell maps and refinement
    Progress progress(log, "gather small surfaces", all);
    progress.EndsWithin(*until - clock.Elapsed());
    for (size_t k = 0, next = 0; k < left.size(); k = next) {
      size_t count = 0;
      for (next = k; next < left.size() && count < kGatheredTogether; ++next) count += vertices[next].size();
      if (!GatherWhole(lit, left.subspan(k, next - k), std::span(vertices).subspan(k, next - k), *until, d, clock)) break;
      small.gathered += uint32_t(next - k), small.vertices += count;
      progress.Advance(count);
    }
  });
  small.seconds = clock.Elapsed() - start, small.interrupted = InterruptRequested();
  if (d != nullptr && !d->Root()) return;
  rounds.SmallSurfacesGathered(small);
  if (small.gathered > 0) JudgeTheVertices(lit, clock);
}

}  // namespace

// The time the estimate took per vertex, over every round [s]: what a texel or a refined vertex costs.
double SecondsPerPoint(const Lit& lit, const PhotonRounds& rounds, const StageClock& clock) {
  const double points = double(lit.baked.mesh.VertexCount()) * double(std::max<size_t>(rounds.Report().rounds.size(), 1));
  return points > 0 ? clock.Seconds("estimate") / points : 0.0;
}

// Stages 1 to 3 once with --photons, or in rounds until --target-noise (baker/photons/photon_rounds.h); then
// --save-photons. Ctrl-C ends the rounds: in the first round's tracing, the bake goes on with the photons it has;
// in the first round's estimate, the vertices left read the fewest samples; in a later round, that round's estimate
// stops (at once, when the Ctrl-C came while it traced) and the bake keeps the vertices of the round before. The
// rounds' deadline stops an estimate alike.
Lit TraceAndEstimate(PhotonRounds& rounds, const PreparedScene& scene, const FieldSettings& field,
                     const std::vector<bool>& estimated, OutputFiles& outputs, const Distribution* distribution,
                     StageClock& clock, const Log& log) {
  const InterruptScope interrupt;
  const SplitMesh base = SplitBySurface(scene.scene, scene.surfaces, estimated);
  Lit lit;
  do {
    rounds.TraceRound();
    if (!EstimateLight(lit, scene, base, field, rounds, distribution, clock, log)) break;
  } while (rounds.Continue(lit.baked, lit.noise, lit.error, lit.field->Photons().Bandwidths()));
  GatherSmallSurfacesLeft(lit, rounds, distribution, clock, log);
  rounds.Save(outputs);
  return lit;
}

}  // namespace pb
