#include "baker/2_bin_photons.h"

namespace pb {

SurfaceBins BinPhotons(const Scene& scene, const PhotonHits& hits, size_t surfaceCount) {
  SurfaceBins bins;
  bins.start.assign(surfaceCount + 1, 0);
  bins.backHits.assign(surfaceCount, 0);
  std::vector<uint8_t> front;
  front.reserve(hits.stats.hits);
  hits.ForEach([&](const PhotonHit& hit) {
    front.push_back(hit.OnFront(scene));
    if (front.back())
      ++bins.start[hit.surface + 1];
    else
      ++bins.backHits[hit.surface];
  });
  for (size_t s = 1; s <= surfaceCount; ++s) bins.start[s] += bins.start[s - 1];
  bins.uv.resize(bins.start.back());
  bins.power.resize(bins.start.back());
  std::vector<uint32_t> cursor(bins.start.begin(), bins.start.end() - 1);
  size_t i = 0;
  hits.ForEach([&](const PhotonHit& hit) {
    if (!front[i++]) return;
    const uint32_t slot = cursor[hit.surface]++;
    bins.uv[slot] = hit.uv;
    bins.power[slot] = hit.power;
  });
  return bins;
}

}  // namespace pb
