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

SurfaceBins Bin(const SurfaceSet& surfaces, const PhotonStore& hits, Progress* progress, double fluxUnit) {
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
  std::vector<uint32_t> cursor(bins.start.begin(), bins.start.end() - 1);
  StepCounter counter(progress);
  hits.ForEach([&](const PhotonHit& hit, Rgb flux) {
    counter.Count();
    if (!hit.OnFront()) return;
    const uint32_t slot = cursor[surfaces.surfaceOfTriangle[hit.Triangle()]]++;
    bins.uv[slot] = surfaces.UvAt(hit.Triangle(), hit.b1, hit.b2);
    bins.flux[slot] = flux;
  });
  return bins;
}

uint64_t StoredHits(const PhotonStore& store) {
  uint64_t count = 0;
  for (const HitBlock& block : store.blocks) count += block.size();
  return count;
}

double StoreFluxUnit(const PhotonStore& store) { return FluxUnit(store.lightPower, store.emitted); }

// Bytes per node while photons are binned (four 64-bit sums), and of a stored hit (the store's record).
constexpr double kBytesPerNode = 32, kBytesPerHit = sizeof(PhotonHit);

}  // namespace

double FluxUnit(const std::vector<Rgb>& lightPower, const std::vector<uint64_t>& photonsPerLight) {
  double unit = 0;
  for (size_t l = 0; l < lightPower.size(); ++l)
    if (photonsPerLight[l] > 0) unit = std::max(unit, double((lightPower[l] / float(photonsPerLight[l])).Max()));
  return unit > 0 ? unit : 1.0;
}

BinningPlan PlanBinning(const PreparedScene& scene, const EstimatorSettings& settings, bool automaticBandwidth,
                        uint64_t photons) {
  BinningPlan plan;
  std::vector<Rgb> power;
  for (const Light& light : scene.lights) power.push_back(light.Power());
  plan.photonsPerLight = AllocatePhotons(scene.lights, photons, scene.plan.lightReaches);
  plan.fluxUnit = FluxUnit(power, plan.photonsPerLight);
  if (settings.kind != EstimatorKind::kKernel || !settings.edgeCorrection || automaticBandwidth) return plan;
  plan.lattices.resize(scene.regions.size());
  double nodes = 0;
  for (size_t s = 0; s < scene.regions.size(); ++s) {
    plan.lattices[s][0] = KernelEstimator::WideLattice(settings.kernel, *scene.regions[s], settings.bandwidth);
    if (scene.coveredRegions[s])
      plan.lattices[s][1] = KernelEstimator::WideLattice(settings.kernel, *scene.coveredRegions[s], settings.bandwidth);
    for (const auto& lattice : plan.lattices[s])
      if (lattice) nodes += double(lattice->Count());
  }
  plan.wide = nodes * kBytesPerNode <= double(photons) * kBytesPerHit;
  if (!plan.wide) plan.lattices.clear();
  return plan;
}

PhotonBinner::PhotonBinner(const PreparedScene& scene, const BinningPlan& plan)
    : scene_(scene), fluxUnit_(plan.fluxUnit), sums_(plan.lattices.size()), tallies_(plan.lattices.size()) {
  PB_CHECK(plan.wide, "photons are binned while traced only where every wide surface is binned");
  for (size_t l = 0; l < scene.lights.size(); ++l)  // as PhotonStore::PhotonFlux once the lights have emitted them
    photonFlux_.push_back(plan.photonsPerLight[l] ? scene.lights[l].Power() / float(plan.photonsPerLight[l]) : Rgb{});
  for (size_t s = 0; s < sums_.size(); ++s)
    for (int d = 0; d < 2; ++d)
      if (plan.lattices[s][d]) sums_[s][d] = std::make_unique<BinnedPhotons>(*plan.lattices[s][d], fluxUnit_);
}

void PhotonBinner::Take(uint32_t light, HitBlock& hits, size_t from) const {
  const SurfaceSet& surfaces = scene_.surfaces;
  const Rgb photon = photonFlux_[light];
  size_t kept = from;
  for (size_t i = from; i < hits.size(); ++i) {
    const PhotonHit& hit = hits[i];
    const uint32_t s = surfaces.surfaceOfTriangle[hit.Triangle()];
    const Point2 uv = surfaces.UvAt(hit.Triangle(), hit.b1, hit.b2);
    const int domain = scene_.covers[s].Empty() || !scene_.covers[s].Covered(uv) ? 0 : 1;
    SurfaceTally& tally = tallies_[s];
    if (!hit.OnFront() && Binned(s)) {
      std::atomic_ref<uint64_t>(tally.backHits).fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    if (!hit.OnFront() || !sums_[s][domain]) {
      hits[kept++] = hit;
      continue;
    }
    const Rgb flux = hit.attenuation * photon;
    sums_[s][domain]->Add(uv, flux);
    std::atomic_ref<uint64_t>(tally.frontHits).fetch_add(1, std::memory_order_relaxed);
    FluxTally one;
    one.Add(flux, fluxUnit_);
    for (int c = 0; c < 3; ++c) std::atomic_ref<int64_t>(tally.frontFlux.units[c]).fetch_add(one.units[c], std::memory_order_relaxed);
  }
  hits.resize(kept);
}

SurfaceBins BinPhotons(const SurfaceSet& surfaces, const PhotonStore& hits) {
  return Bin(surfaces, hits, nullptr, StoreFluxUnit(hits));
}

SurfaceBins BinPhotons(const SurfaceSet& surfaces, const PhotonStore& hits, const Log& log, const BinningPlan& plan,
                       PhotonBinner* binner) {
  Progress progress(log, "bin photons", 2 * StoredHits(hits));
  SurfaceBins bins = Bin(surfaces, hits, &progress, plan.wide ? plan.fluxUnit : StoreFluxUnit(hits));
  bins.wide = plan.wide;
  if (binner == nullptr) return bins;
  bins.traced = binner->TakeSums();
  const std::vector<SurfaceTally> taken = binner->TakeTallies();
  for (size_t s = 0; s < taken.size(); ++s) {
    bins.tally[s].frontHits += taken[s].frontHits;
    bins.tally[s].backHits += taken[s].backHits;
    bins.tally[s].frontFlux.Add(taken[s].frontFlux);
  }
  return bins;
}

}  // namespace pb
