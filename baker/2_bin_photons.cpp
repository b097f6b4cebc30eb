#include "baker/2_bin_photons.h"

namespace pb {

SurfaceBins BinPhotons(const SurfaceSet& surfaces, const PhotonStore& hits) {
  const size_t surfaceCount = surfaces.surfaces.size();
  SurfaceBins bins;
  bins.start.assign(surfaceCount + 1, 0);
  bins.backHits.assign(surfaceCount, 0);
  hits.ForEach([&](const PhotonHit& hit, Rgb) {
    const uint32_t s = surfaces.surfaceOfTriangle[hit.Triangle()];
    if (hit.OnFront())
      ++bins.start[s + 1];
    else
      ++bins.backHits[s];
  });
  for (size_t s = 1; s <= surfaceCount; ++s) bins.start[s] += bins.start[s - 1];
  bins.uv.resize(bins.start.back());
  bins.flux.resize(bins.start.back());
  std::vector<uint32_t> cursor(bins.start.begin(), bins.start.end() - 1);
  hits.ForEach([&](const PhotonHit& hit, Rgb flux) {
    if (!hit.OnFront()) return;
    const uint32_t slot = cursor[surfaces.surfaceOfTriangle[hit.Triangle()]]++;
    bins.uv[slot] = surfaces.UvAt(hit.Triangle(), hit.b1, hit.b2);
    bins.flux[slot] = flux;
  });
  return bins;
}

}  // namespace pb
