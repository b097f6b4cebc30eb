#include "estimators/importance_cache.h"

#include <tbb/parallel_for.h>

#include "estimators/warps.h"

namespace pb {
namespace {

std::vector<MapPhoton> SitesOf(const PhotonMap& photons, uint32_t stride) {
  std::vector<MapPhoton> sites;
  sites.reserve(photons.Size() / stride + 1);
  for (size_t i = 0; i < photons.Size(); i += stride) sites.push_back(photons[uint32_t(i)]);
  return sites;
}

}  // namespace

void BuildImportanceMap(ImportanceMap& map, const PhotonMap& photons, Point3 p, Normal3 side, const MapSettings& s,
                        std::vector<uint32_t>& indices, std::vector<float>& distance2) {
  const Frame frame = Frame::FromNormal(side);
  map.Clear();
  const size_t found = photons.Nearest(p, s.neighbours, indices, distance2);
  for (size_t i = 0; i < found; ++i) {
    const MapPhoton& photon = photons[indices[i]];
    if (Dot(photon.normal, side) < kSameSurfaceCosine) continue;  // light that reached another surface
    map.Add(frame.ToLocal(photon.wi), Luminance(photon.flux));    // ignored unless in the hemisphere
  }
  map.Finish(s.floorFraction);
}

ImportanceCache::ImportanceCache(const PhotonMap& photons, const MapSettings& settings, uint32_t stride)
    : sites_(SitesOf(photons, std::max(stride, 1u))) {
  maps_.assign(sites_.Size(), ImportanceMap(settings.rows, settings.cols));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, maps_.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<uint32_t> indices;
    std::vector<float> distance2;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const MapPhoton& site = sites_[uint32_t(i)];
      BuildImportanceMap(maps_[i], photons, site.position, site.normal, settings, indices, distance2);
    }
  });
}

const ImportanceMap* ImportanceCache::At(Point3 p, Normal3 side, std::vector<uint32_t>& indices,
                                         std::vector<float>& distance2) const {
  const size_t found = sites_.Nearest(p, kCandidates, indices, distance2);
  for (size_t i = 0; i < found; ++i)
    if (Dot(sites_[indices[i]].normal, side) >= kSameSurfaceCosine) return &maps_[indices[i]];
  return nullptr;
}

}  // namespace pb
