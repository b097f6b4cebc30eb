#include "baker/2_bin_photons.h"

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

SurfaceBins Bin(const SurfaceSet& surfaces, const PhotonStore& hits, Progress* progress) {
  const size_t surfaceCount = surfaces.surfaces.size();
  SurfaceBins bins;
  bins.start.assign(surfaceCount + 1, 0);
  bins.backHits.assign(surfaceCount, 0);
  {
    StepCounter counter(progress);
    hits.ForEach([&](const PhotonHit& hit, Rgb) {
      counter.Count();
      const uint32_t s = surfaces.surfaceOfTriangle[hit.Triangle()];
      if (hit.OnFront())
        ++bins.start[s + 1];
      else
        ++bins.backHits[s];
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

}  // namespace

SurfaceBins BinPhotons(const SurfaceSet& surfaces, const PhotonStore& hits) { return Bin(surfaces, hits, nullptr); }

SurfaceBins BinPhotons(const SurfaceSet& surfaces, const PhotonStore& hits, const Log& log) {
  Progress progress(log, "bin photons", 2 * hits.stats.hits);
  return Bin(surfaces, hits, &progress);
}

}  // namespace pb
