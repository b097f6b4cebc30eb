#include "baker/1_trace_photons.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>

#include "estimators/emission.h"
#include "estimators/scatter.h"
#include "estimators/surface_hit.h"
#include "estimators/rng.h"
#include "baker/runtime/interrupt.h"
#include "mesh/errors.h"

namespace pb {
namespace {

// A block being traced: its hits and its stats, in attenuation units.
struct Block {
  HitBlock hits;
  TraceStats stats;
};

// The photon loop. kInterreflect: diffuse surfaces scatter (else a photon ends at its first diffuse surface).
// kSpecular: materials of every class are sampled, with mirror and glass events (else every surface is
// treated as the diffuse class, which the plan guarantees it is).
template <bool kInterreflect, bool kSpecular>
class PhotonTracer {
 public:
  PhotonTracer(const Scene& scene, const RayScene& rays, const TransportPlan& plan, uint32_t maxBounces, bool storeDirect)
      : scene_(scene), rays_(rays), maxBounces_(maxBounces), storeDirect_(storeDirect), reflection_(plan.On(Effect::kReflection)),
        refraction_(plan.On(Effect::kRefraction)), caustics_(plan.On(Effect::kCaustics)) {}

  // Traces one photon from `light`, appending its hits to `block`. `attenuation` is the fraction of its flux it still
  // carries: at emission its weight, 1 but for a sky image's photons.
  void Trace(const Light& light, Rng& rng, Block& block) const {
    const EmissionSample e = SampleEmission(scene_, light, rng);
    Rgb attenuation = e.weight;
    block.stats.fluxEmitted.Add(attenuation);
    ++block.stats.emitted;
    if (!e.carriesLight) return Escape(attenuation, block.stats);
    Point3 origin = e.onSurface ? rays_.SpawnPoint(e.position, e.normal) : e.position;
    Vector3 direction = e.direction;
    bool afterSpecular = false;
    for (uint32_t bounce = 0; bounce <= maxBounces_; ++bounce) {
      const auto hit = rays_.Intersect(origin, direction);
      if (!hit) return Escape(attenuation, block.stats);
      const SurfaceHit at = SurfaceHit::Meet(scene_, *hit, direction);
      if (kSpecular && afterSpecular && !at.material->IsSpecular()) {
        if (!caustics_) return Forbid(attenuation, block.stats);
        ++block.stats.causticHits;
      }
      if (bounce > 0 || storeDirect_) block.hits.emplace_back(attenuation, -direction, hit->triangle, at.onFront, hit->b1, hit->b2);
      if constexpr (!kInterreflect && !kSpecular) return StopAtFirstSurface(at.albedo, attenuation, block.stats);
      const float uEvent = rng.Uniform();
      const Point2 uDirection = rng.Uniform2();
      const ScatterSample s = kSpecular ? SampleScatter(*at.material, at.albedo, -direction, at.front,
                                                        TransportMode::kImportance, uEvent, uDirection)
                                        : ScatterDiffuse(at.albedo, at.side, uEvent, uDirection);
      block.stats.fluxAbsorbed.Add(attenuation * s.expectedAbsorbed);
      if (s.Absorbed()) {
        ++block.stats.absorbed;
        return;
      }
      attenuation = attenuation * s.weight;
      if (attenuation.IsBlack()) {  // e.g. red light on a pure green surface: all it carried was absorbed here
        ++block.stats.absorbed;
        return;
      }
      if (attenuation.Max() > kMostPhotonAttenuation) break;  // truncated
      if (!Allowed(s.event)) return Forbid(attenuation, block.stats);
      Count(s.event, block.stats);
      origin = at.NextOrigin(rays_, s.transmitted);
      direction = s.wi;
      afterSpecular = s.Specular();
    }
    ++block.stats.truncated;
    block.stats.fluxForbidden.Add(attenuation);
  }

 private:
  static void Escape(Rgb attenuation, TraceStats& stats) {
    ++stats.escaped;
    stats.fluxEscaped.Add(attenuation);
  }
  static void Forbid(Rgb attenuation, TraceStats& stats) {
    ++stats.forbidden;
    stats.fluxForbidden.Add(attenuation);
  }
  // Without interreflection: the absorbed and the forbidden (reflected) parts are tallied in expectation.
  static void StopAtFirstSurface(Rgb albedo, Rgb attenuation, TraceStats& stats) {
    stats.fluxAbsorbed.Add(attenuation * (Rgb{1, 1, 1} - albedo));
    stats.fluxForbidden.Add(attenuation * albedo);
    ++(albedo.IsBlack() ? stats.absorbed : stats.forbidden);
  }
  bool Allowed(ScatterEvent event) const {
    switch (event) {
      case ScatterEvent::kDiffuse: return kInterreflect;
      case ScatterEvent::kMirror:
      case ScatterEvent::kFresnelReflection: return reflection_;
      case ScatterEvent::kRefraction: return refraction_;
      case ScatterEvent::kAbsorbed: break;
    }
    return false;
  }
  static void Count(ScatterEvent event, TraceStats& stats) {
    if constexpr (!kSpecular) {
      ++stats.diffuseBounces;
      return;
    }
    switch (event) {
      case ScatterEvent::kDiffuse: ++stats.diffuseBounces; break;
      case ScatterEvent::kMirror: ++stats.mirrorReflections; break;
      case ScatterEvent::kFresnelReflection: ++stats.fresnelReflections; break;
      case ScatterEvent::kRefraction: ++stats.refractions; break;
      case ScatterEvent::kAbsorbed: break;
    }
  }

  const Scene& scene_;
  const RayScene& rays_;
  uint32_t maxBounces_;  // scattering events after the first hit
  bool storeDirect_;     // TraceSettings::storeDirect
  bool reflection_, refraction_, caustics_;
};

// The work that brings a store to `target` photons per light: each light's partial last block continued in place,
// then new blocks. `block` indexes the store's blocks; new blocks are appended past its end. The items are in the
// order they are claimed: the lights' blocks interleaved by how far into its target each starts, so that a Ctrl-C
// part-way leaves every light with photons in proportion to its share, not the first lights complete and the last
// with none. (The store keeps its own order, by light then photon, so the bytes do not depend on this one.)
struct WorkItem {
  size_t block;
  BlockRange range;     // the block's whole range once traced
  uint64_t from = 0;    // photons [from, range.end) are traced now
};

std::vector<WorkItem> PlanWork(const PhotonStore& store, const std::vector<uint64_t>& target) {
  std::vector<WorkItem> work;
  size_t next = store.blocks.size();
  for (size_t b = 0; b < store.blocks.size(); ++b) {
    const BlockRange& r = store.ranges[b];
    if (!r.Full() && r.end == store.emitted[r.light] && target[r.light] > r.end)
      work.push_back({b, {r.light, r.first, std::min(target[r.light], r.first + kBlockPhotons)}, r.end});
  }
  for (uint32_t l = 0; l < target.size(); ++l) {
    const uint64_t start = (store.emitted[l] + kBlockPhotons - 1) / kBlockPhotons * kBlockPhotons;
    for (uint64_t first = start; first < target[l]; first += kBlockPhotons)
      work.push_back({next++, {l, first, std::min(target[l], first + kBlockPhotons)}, first});
  }
  const auto progress = [&](const WorkItem& w) { return double(w.from) / double(target[w.range.light]); };
  std::stable_sort(work.begin(), work.end(), [&](const WorkItem& a, const WorkItem& b) { return progress(a) < progress(b); });
  return work;
}

// Photons [w.from, w.range.end) of w's light, appended to `block`; a sink takes what it bins. An item of few photons
// (one of 100,000 LEDs) is traced into `scratch`, a worker's array reused from item to item, and its hits are then
// copied into an array of exactly their size: reserving ahead in each block's own array touched 3 hits' memory per
// photon, in 4 KiB pages each a page fault. A large item, reserved in huge pages, is traced in place.
template <typename Tracer>
void TraceItem(const Tracer& tracer, const Light& light, const WorkItem& w, uint64_t seed, const HitSink* sink,
               Block& block, HitBlock& scratch) {
  const uint64_t photons = w.range.end - w.from;
  const bool small = !HugePageAllocator<PhotonHit>::Huge(photons * kReservedHitsPerPhoton);
  Block traced{small ? std::move(scratch) : std::move(block.hits), block.stats};
  if (small) traced.hits.clear();  // the scratch holds the last small item's hits
  const size_t before = traced.hits.size();
  traced.hits.reserve(before + photons * kReservedHitsPerPhoton);
  for (uint64_t j = w.from; j < w.range.end; ++j) {
    Rng rng(seed, PhotonStream(w.range.light, j));
    tracer.Trace(light, rng, traced);
  }
  traced.stats.hits += traced.hits.size() - before;  // every hit, those a sink takes too
  if (sink != nullptr) sink->Take(w.range.light, traced.hits, before);
  block.stats = traced.stats;
  if (!small) {
    block.hits = std::move(traced.hits);
    if (sink != nullptr) block.hits.shrink_to_fit();
    return;
  }
  block.hits.reserve(block.hits.size() + traced.hits.size());
  block.hits.insert(block.hits.end(), traced.hits.begin(), traced.hits.end());
  scratch = std::move(traced.hits);
}

// Traces the work items in parallel, each into its block (moved out of the store, or new); claims them in order,
// so that an interruption leaves each light's traced photons close to a prefix of its stream. done[i] says
// whether item i was traced.
template <typename Tracer>
std::vector<bool> TraceWork(const Tracer& tracer, const std::vector<Light>& lights, const std::vector<WorkItem>& work,
                            std::vector<Block>& blocks, uint64_t seed, const HitSink* sink, const TraceShare* share,
                            const Log& log) {
  std::vector<bool> mine(work.size(), true);
  if (share != nullptr) {
    std::vector<uint32_t> itemLights(work.size());
    for (size_t i = 0; i < work.size(); ++i) itemLights[i] = work[i].range.light;
    mine = share->Takes(itemLights);
  }
  const auto takes = [&](size_t i) { return bool(mine[i]); };
  uint64_t total = 0;
  for (size_t i = 0; i < work.size(); ++i)
    if (takes(i)) total += work[i].range.end - work[i].from;
  Progress progress(log, "trace photons", total);
  std::atomic<size_t> next{0};
  std::vector<char> done(work.size(), 0);
  const size_t workers = std::min<size_t>(work.size(), size_t(tbb::this_task_arena::max_concurrency()));
  tbb::parallel_for(size_t(0), workers, [&](size_t) {
    HitBlock scratch;  // this worker's, reused by its small items
    for (size_t i; !InterruptRequested() && (i = next++) < work.size();) {
      if (!takes(i)) continue;
      const WorkItem& w = work[i];
      TraceItem(tracer, lights[w.range.light], w, seed, sink, blocks[w.block], scratch);
      done[i] = 1;
      progress.Advance(w.range.end - w.from);
    }
  });
  return {done.begin(), done.end()};
}

// With a shared trace: hands this process's traced blocks to the share, and takes back every process's, so that
// `done` and `blocks` describe the whole trace.
void GatherShares(const TraceShare& share, const std::vector<WorkItem>& work, std::vector<Block>& blocks,
                  std::vector<bool>& done) {
  std::vector<TracedBlock> mine;
  for (size_t i = 0; i < work.size(); ++i) {
    if (!done[i]) continue;
    Block& b = blocks[work[i].block];
    mine.push_back({i, work[i].range, b.stats, std::move(b.hits)});
  }
  std::fill(done.begin(), done.end(), false);
  for (TracedBlock& t : share.Gather(std::move(mine))) {
    PB_CHECK_LT(t.item, work.size());
    blocks[work[t.item].block] = {std::move(t.hits), t.stats};
    done[t.item] = true;
  }
}

// Moves the store's blocks out, for tracing to continue in them.
std::vector<Block> TakeBlocks(PhotonStore& store, size_t total) {
  std::vector<Block> blocks(total);
  for (size_t b = 0; b < store.blocks.size(); ++b) {
    blocks[b].hits = std::move(store.blocks[b]);
    blocks[b].stats = std::move(store.blockStats[b]);
  }
  return blocks;
}

// Puts the blocks back, ordered by light, then photon, keeping for each light only the traced prefix of its stream
// (after an interruption, a block traced beyond an untraced one is dropped).
void StoreBlocks(PhotonStore& store, std::vector<Block>& blocks, const std::vector<WorkItem>& work,
                 const std::vector<bool>& done) {
  std::vector<BlockRange> ranges(store.ranges);
  ranges.resize(blocks.size());
  std::vector<bool> traced(blocks.size(), true);
  for (size_t i = 0; i < work.size(); ++i) {
    if (done[i]) ranges[work[i].block] = work[i].range;
    else traced[work[i].block] = work[i].block < store.blocks.size();  // an unfinished old block keeps what it had
  }
  std::vector<size_t> order;
  for (size_t b = 0; b < blocks.size(); ++b)
    if (traced[b]) order.push_back(b);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return ranges[a].light != ranges[b].light ? ranges[a].light < ranges[b].light : ranges[a].first < ranges[b].first;
  });
  store.blocks.clear();
  store.blockStats.clear();
  store.ranges.clear();
  std::fill(store.emitted.begin(), store.emitted.end(), 0);
  for (size_t b : order) {
    const BlockRange& r = ranges[b];
    if (r.first != store.emitted[r.light]) continue;  // after a gap in this light's stream
    store.blocks.push_back(std::move(blocks[b].hits));
    store.blockStats.push_back(std::move(blocks[b].stats));
    store.ranges.push_back(r);
    store.emitted[r.light] = r.end;
  }
}

}  // namespace

bool ExtendPhotons(PhotonStore& store, const Scene& scene, const std::vector<Light>& lights, const RayScene& rays,
                   const TransportPlan& plan, const TraceSettings& settings, const Log& log) {
  std::vector<uint64_t> target = AllocatePhotons(lights, settings.photons, plan.lightReaches);
  for (size_t l = 0; l < lights.size(); ++l) target[l] = std::max(target[l], store.emitted[l]);
  const std::vector<WorkItem> work = PlanWork(store, target);
  size_t total = store.blocks.size();
  for (const WorkItem& w : work) total = std::max(total, w.block + 1);
  std::vector<Block> blocks = TakeBlocks(store, total);
  const auto run = [&]<bool kInterreflect, bool kSpecular>() {
    const PhotonTracer<kInterreflect, kSpecular> tracer(scene, rays, plan, settings.maxBounces, settings.storeDirect);
    return TraceWork(tracer, lights, work, blocks, settings.seed, settings.sink, settings.share, log);
  };
  const bool bounce = plan.On(Effect::kInterreflection), specular = plan.NeedsSpecularKernel();
  std::vector<bool> done = specular ? (bounce ? run.template operator()<true, true>()
                                                    : run.template operator()<false, true>())
                                          : (bounce ? run.template operator()<true, false>()
                                                    : run.template operator()<false, false>());
  if (settings.share != nullptr) GatherShares(*settings.share, work, blocks, done);
  StoreBlocks(store, blocks, work, done);
  store.Summarise();
  return std::find(done.begin(), done.end(), false) == done.end();
}

PhotonStore EmptyPhotonStore(const std::vector<Light>& lights) {
  PhotonStore store;
  store.emitted.assign(lights.size(), 0);
  for (const Light& light : lights) store.lightPower.push_back(light.Power());
  store.Summarise();
  return store;
}

PhotonStore TracePhotons(const Scene& scene, const std::vector<Light>& lights, const RayScene& rays,
                        const TransportPlan& plan, const TraceSettings& settings, const Log& log) {
  PhotonStore store = EmptyPhotonStore(lights);
  ExtendPhotons(store, scene, lights, rays, plan, settings, log);
  return store;
}

PhotonStore TracePhotons(const PreparedScene& scene, const TraceSettings& settings, const Log& log) {
  return TracePhotons(scene.scene, scene.lights, *scene.rays, scene.plan, settings, log);
}

bool ExtendPhotons(PhotonStore& store, const PreparedScene& scene, const TraceSettings& settings, const Log& log) {
  return ExtendPhotons(store, scene.scene, scene.lights, *scene.rays, scene.plan, settings, log);
}

std::vector<MapPhoton> MapPhotonsOf(const Scene& scene, const PhotonStore& hits) {
  std::vector<MapPhoton> photons;
  photons.reserve(hits.stats.hits);
  hits.ForEach([&](const PhotonHit& h, Rgb flux) {
    const Normal3 front = scene.FrontNormal(h.Triangle());
    photons.push_back({scene.PointAt(h.Triangle(), h.b1, h.b2), h.Wi(), flux, h.OnFront() ? front : -front});
  });
  return photons;
}

}  // namespace pb
