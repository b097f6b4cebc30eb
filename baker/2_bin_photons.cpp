#include "baker/2_bin_photons.h"

#include <algorithm>
#include <atomic>

#include "estimators/emission.h"
#include "estimators/kernel_estimator.h"
#include "mesh/errors.h"

namespace pb {

namespace {

// Counts hits into `progress` in steps, so that the per-hit loop pays no atomic add.
class StepCounter {
 public:
  explicit StepCounter(Progress* progress) : progress_(progress) {}
  ~StepCounter() {
    if (progress_) progress_->Advance(pending_);
  }
  void Count() {
    if (progress_ && ++pending_ == kStep) progress_->Advance(pending_), pending_ = 0;
  }

 private:
  static constexpr uint64_t kStep = 1 << 16;
  Progress* progress_;
  uint64_t pending_ = 0;
};

SurfaceBins Bin(const SurfaceSet& surfaces, const PhotonStore& hits, Progress* progress, double fluxUnit,
                const Scene* directionsIn) {
  const size_t surfaceCount = surfaces.surfaces.size();
  SurfaceBins bins;
  bins.fluxUnit = fluxUnit;
  bins.start.assign(surfaceCount + 1, 0);
  bins.tally.assign(surfaceCount, {});
  {
    StepCounter counter(progress);
    hits.ForEach([&](const PhotonHit& hit, Rgb flux) {
      counter.Count();
      const uint32_t s = surfaces.surfaceOfTriangle[hit.Triangle()];
      if (!hit.OnFront()) return void(++bins.tally[s].backHits);
      ++bins.start[s + 1];
      ++bins.tally[s].frontHits;
      bins.tally[s].frontFlux.Add(flux, fluxUnit);
    });
  }
  for (size_t s = 1; s <= surfaceCount; ++s) bins.start[s] += bins.start[s - 1];
  bins.uv.resize(bins.start.back());
  bins.flux.resize(bins.start.back());
  bins.directions = directionsIn != nullptr;
  if (bins.directions) bins.from.resize(bins.start.back()), bins.cosine.resize(bins.start.back());
  std::vector<uint32_t> cursor(bins.start.begin(), bins.start.end() - 1);
  StepCounter counter(progress);
  hits.ForEach([&](const PhotonHit& hit, Rgb flux) {
    counter.Count();
    if (!hit.OnFront()) return;
    const uint32_t slot = cursor[surfaces.surfaceOfTriangle[hit.Triangle()]]++;
    bins.uv[slot] = surfaces.UvAt(hit.Triangle(), hit.b1, hit.b2);
    bins.flux[slot] = flux;
    if (directionsIn == nullptr) return;
    bins.from[slot] = hit.Wi();
    bins.cosine[slot] = Dot(bins.from[slot], directionsIn->FrontNormal(hit.Triangle()));
  });
  return bins;
}

double StoreFluxUnit(const PhotonStore& store) { return FluxUnit(store.lightPower, store.emitted); }

// Bytes per node while photons are binned (four 64-bit sums), and of a stored hit (the store's record).
constexpr double kBytesPerNode = 32, kBytesPerHit = sizeof(PhotonHit);
// Every wide surface is binned when its lattices take at most this share of a store of one hit per photon. Binning
// while tracing misses the cache on every hit once the lattices outgrow it: in a 10 x 3 x 10 m room (213 MB of
// lattices at h = 0.05 m) the trace took 1.6x as long as storing the hits, which at 10M photons (lattices about the
// store's size) saved only 25% of the memory; at 100M the whole bake took 0.55x the stored one's time and 0.1x its
// memory (docs/performance.md, "Scale").
constexpr double kLatticeShareOfStore = 0.25;

}  // namespace

double FluxUnit(const std::vector<Rgb>& lightPower, const std::vector<uint64_t>& photonsPerLight) {
  double unit = 0;
  for (size_t l = 0; l < lightPower.size(); ++l)
    if (photonsPerLight[l] > 0) unit = std::max(unit, double((lightPower[l] / float(photonsPerLight[l])).Max()));
  return unit > 0 ? unit : 1.0;
}

BinningPlan PlanBinning(const PreparedScene& scene, const EstimatorSettings& settings,
                        uint64_t photons) {
  BinningPlan plan;
  std::vector<Rgb> power;
  for (const Light& light : scene.lights) power.push_back(light.Power());
  plan.photonsPerLight = AllocatePhotons(scene.lights, photons, scene.plan.lightReaches);
  plan.fluxUnit = FluxUnit(power, plan.photonsPerLight);
  if (settings.kind != EstimatorKind::kKernel || !settings.edgeCorrection || !settings.bandwidth) return plan;
  plan.lattices.resize(scene.regions.size());
  double nodes = 0;
  for (size_t s = 0; s < scene.regions.size(); ++s) {
    plan.lattices[s][0] = KernelEstimator::WideLattice(settings.kernel, *scene.regions[s], *settings.bandwidth);
    if (scene.coveredRegions[s])
      plan.lattices[s][1] = KernelEstimator::WideLattice(settings.kernel, *scene.coveredRegions[s], *settings.bandwidth);
    for (const auto& lattice : plan.lattices[s])
      if (lattice) nodes += double(lattice->Count());
  }
  plan.wide = nodes * kBytesPerNode <= kLatticeShareOfStore * double(photons) * kBytesPerHit;
  if (!plan.wide) plan.lattices.clear();
  return plan;
}

namespace {
// Node sums on the plan's lattices, one per binned domain.
std::vector<DomainSums> SumsOn(const BinningPlan& plan) {
  std::vector<DomainSums> sums(plan.lattices.size());
  for (size_t s = 0; s < sums.size(); ++s)
    for (int d = 0; d < 2; ++d)
      if (plan.lattices[s][d]) sums[s][d] = std::make_unique<BinnedPhotons>(*plan.lattices[s][d], plan.fluxUnit);
  return sums;
}
}  // namespace

PhotonBinner::PhotonBinner(const PreparedScene& scene, const BinningPlan& plan, bool directions)
    : scene_(scene), fluxUnit_(plan.fluxUnit), sums_(SumsOn(plan)), tallies_(plan.lattices.size()) {
  PB_CHECK(plan.wide, "photons are binned while traced only where every wide surface is binned");
  for (size_t l = 0; l < scene.lights.size(); ++l)  // as PhotonStore::PhotonFlux once the lights have emitted them
    photonFlux_.push_back(plan.photonsPerLight[l] ? scene.lights[l].Power() / float(plan.photonsPerLight[l]) : Rgb{});
  if (directions)
    for (auto& m : momentSums_) m = SumsOn(plan);
}

namespace {
// A front hit bound for a lattice, waiting while its nodes are fetched.
struct PendingAdd {
  BinnedPhotons* sums;
  SurfaceTally* tally;
  Point2 uv;
  Rgb flux;
};
// Photons ahead whose nodes are prefetched: enough to overlap a few misses, few enough to stay in L1.
constexpr size_t kPrefetchAhead = 8;

void Apply(const PendingAdd& a, double fluxUnit) {
  a.sums->Add(a.uv, a.flux);
  std::atomic_ref<uint64_t>(a.tally->frontHits).fetch_add(1, std::memory_order_relaxed);
  FluxTally one;
  one.Add(a.flux, fluxUnit);
  for (int c = 0; c < 3; ++c)
    std::atomic_ref<int64_t>(a.tally->frontFlux.units[c]).fetch_add(one.units[c], std::memory_order_relaxed);
}
}  // namespace

void PhotonBinner::Take(uint32_t light, HitBlock& hits, size_t from) const {
  const SurfaceSet& surfaces = scene_.surfaces;
  const Rgb photon = photonFlux_[light];
  std::array<PendingAdd, kPrefetchAhead> pending;
  size_t kept = from, queued = 0;
  for (size_t i = from; i < hits.size(); ++i) {
    const PhotonHit& hit = hits[i];
    const uint32_t s = surfaces.surfaceOfTriangle[hit.Triangle()];
    SurfaceTally& tally = tallies_[s];
    if (!hit.OnFront()) {
      if (Binned(s)) std::atomic_ref<uint64_t>(tally.backHits).fetch_add(1, std::memory_order_relaxed);
      else hits[kept++] = hit;
      continue;
    }
    const Point2 uv = surfaces.UvAt(hit.Triangle(), hit.b1, hit.b2);
    const int domain = scene_.covers[s].Empty() || !scene_.covers[s].Covered(uv) ? 0 : 1;
    BinnedPhotons* sums = sums_[s][domain].get();
    if (sums == nullptr) {
      hits[kept++] = hit;
      continue;
    }
    sums->Prefetch(uv);
    PendingAdd& slot = pending[queued++ % kPrefetchAhead];
    if (queued > kPrefetchAhead) Apply(slot, fluxUnit_);
    slot = {sums, &tally, uv, hit.attenuation * photon};
    if (!momentSums_[0].empty()) AddMoments(hit, s, domain, uv, slot.flux);
  }
  for (size_t q = queued > kPrefetchAhead ? queued - kPrefetchAhead : 0; q < queued; ++q) Apply(pending[q % kPrefetchAhead], fluxUnit_);
  hits.resize(kept);
}

void PhotonBinner::AddMoments(const PhotonHit& hit, uint32_t s, int domain, Point2 uv, Rgb flux) const {
  const Vector3 from = hit.Wi();
  const std::array<Rgb, kMomentFluxes> weighted = MomentFluxes(flux, from, Dot(from, scene_.scene.FrontNormal(hit.Triangle())));
  for (size_t m = 0; m < kMomentFluxes; ++m) momentSums_[m][s][domain]->Add(uv, weighted[m]);
}

namespace {
// Calls f on every node sum: the fluxes', then each weighted flux's.
template <typename F>
void ForEachSum(std::vector<DomainSums>& sums, std::array<std::vector<DomainSums>, kMomentFluxes>& moments, F f) {
  const auto each = [&](std::vector<DomainSums>& list) {
    for (DomainSums& domains : list)
      for (auto& one : domains)
        if (one) f(*one);
  };
  each(sums);
  for (auto& m : moments) each(m);
}
}  // namespace

void PhotonBinner::SumWith(const std::function<void(std::span<int64_t>)>& sum) {
  std::vector<int64_t> counts;  // per lattice its photons, then per surface its tally
  ForEachSum(sums_, momentSums_, [&](BinnedPhotons& one) { sum(one.Units()), counts.push_back(int64_t(one.Photons())); });
  for (const SurfaceTally& t : tallies_) {
    counts.insert(counts.end(), {int64_t(t.frontHits), int64_t(t.backHits)});
    counts.insert(counts.end(), t.frontFlux.units.begin(), t.frontFlux.units.end());
  }
  sum(counts);
  auto next = counts.begin();
  ForEachSum(sums_, momentSums_, [&](BinnedPhotons& one) { one.SetPhotons(uint64_t(*next++)); });
  for (SurfaceTally& t : tallies_) {
    t.frontHits = uint64_t(*next++), t.backHits = uint64_t(*next++);
    for (int64_t& u : t.frontFlux.units) u = *next++;
  }
}

SurfaceBins BinPhotons(const SurfaceSet& surfaces, const PhotonStore& hits, const Scene* directionsIn) {
  return Bin(surfaces, hits, nullptr, StoreFluxUnit(hits), directionsIn);
}

SurfaceBins BinPhotons(const SurfaceSet& surfaces, const PhotonStore& hits, const Log& log, const BinningPlan& plan,
                       PhotonBinner* binner, const Scene* directionsIn) {
  Progress progress(log, "bin photons", 2 * hits.StoredHits());
  SurfaceBins bins = Bin(surfaces, hits, &progress, plan.wide ? plan.fluxUnit : StoreFluxUnit(hits), directionsIn);
  bins.wide = plan.wide;
  if (binner == nullptr) return bins;
  bins.traced = binner->TakeSums();
  bins.tracedMoments = binner->TakeMomentSums();
  const std::vector<SurfaceTally> taken = binner->TakeTallies();
  for (size_t s = 0; s < taken.size(); ++s) {
    bins.tally[s].frontHits += taken[s].frontHits;
    bins.tally[s].backHits += taken[s].backHits;
    bins.tally[s].frontFlux.Add(taken[s].frontFlux);
  }
  return bins;
}

void PoolSparseHits(const Scene& scene, const SurfaceSet& surfaces, const PhotonStore& store, SurfaceBins& bins) {
  bins.pooled.clear(), bins.pooledTriangles.clear();
  store.ForEach([&](const PhotonHit& hit, Rgb flux) {
    if (!hit.OnFront() || !bins.Sparse(surfaces.surfaceOfTriangle[hit.Triangle()])) return;
    bins.pooled.push_back({scene.PointAt(hit.Triangle(), hit.b1, hit.b2), hit.Wi(), flux, scene.FrontNormal(hit.Triangle())});
    bins.pooledTriangles.push_back(hit.Triangle());
  });
}

}  // namespace pb
