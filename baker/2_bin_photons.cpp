#include "baker/2_bin_photons.h"

namespace pb {

SurfaceBins BinPhotons(const Scene& scene, const std::vector<PhotonHit>& hits, size_t surfaceCount) {
  SurfaceBins bins;
  bins.start.assign(surfaceCount + 1, 0);
  bins.backHits.assign(surfaceCount, 0);
  std::vector<uint8_t> front(hits.size());
  for (size_t i = 0; i < hits.size(); ++i) {
    front[i] = hits[i].OnFront(scene);
    if (front[i])
      ++bins.start[hits[i].surface + 1];
    else
      ++bins.backHits[hits[i].surface];
  }
  for (size_t s = 1; s <= surfaceCount; ++s) bins.start[s] += bins.start[s - 1];
  bins.uv.resize(bins.start.back());
  bins.power.resize(bins.start.back());
  std::vector<uint32_t> cursor(bins.start.begin(), bins.start.end() - 1);
  for (size_t i = 0; i < hits.size(); ++i) {
    if (!front[i]) continue;
    const uint32_t slot = cursor[hits[i].surface]++;
    bins.uv[slot] = hits[i].uv;
    bins.power[slot] = hits[i].power;
  }
  return bins;
}

}  // namespace pb
