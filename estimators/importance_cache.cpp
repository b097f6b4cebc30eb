#include "estimators/importance_cache.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

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
  maps_.assign(sites_.Size(), ImportanceMap(settings.rows, settings.cols, settings.domain));
  std::vector<float> spacing(sites_.Size());  // each site's distance to its kCandidates-th nearest [m]
  tbb::parallel_for(tbb::blocked_range<size_t>(0, maps_.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<uint32_t> indices;
    std::vector<float> distance2;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const MapPhoton& site = sites_[uint32_t(i)];
      BuildImportanceMap(maps_[i], photons, site.position, site.normal, settings, indices, distance2);
      sites_.Nearest(site.position, kCandidates, indices, distance2);
      spacing[i] = distance2.empty() ? 0.0f : std::sqrt(distance2.back());
    }
  });
  BuildGrid(std::move(spacing));
}

void ImportanceCache::BuildGrid(std::vector<float> spacing) {
  if (spacing.empty()) return;
  std::nth_element(spacing.begin(), spacing.begin() + spacing.size() / 2, spacing.end());
  cell_ = spacing[spacing.size() / 2];
  if (!(cell_ > 0) || !std::isfinite(cell_)) return void(cell_ = 0);
  std::vector<std::pair<uint64_t, uint32_t>> keyed(sites_.Size());
  for (uint32_t i = 0; i < sites_.Size(); ++i) keyed[i] = {CellOf(sites_[i].position), i};
  std::sort(keyed.begin(), keyed.end());
  bySite_.resize(keyed.size());
  for (size_t i = 0; i < keyed.size(); ++i) {
    bySite_[i] = keyed[i].second;
    auto& range = cells_.try_emplace(keyed[i].first, uint32_t(i), uint32_t(i)).first->second;
    range.second = uint32_t(i + 1);
  }
}

uint64_t ImportanceCache::CellOf(Point3 p) const {
  // 21 bits a coordinate, wrapping: cells far apart may share a key, which only costs a scan of their sites.
  const auto bits = [&](float x) { return uint64_t(int64_t(std::floor(x / cell_))) & 0x1fffff; };
  return bits(p.x) | bits(p.y) << 21 | bits(p.z) << 42;
}

const ImportanceMap* ImportanceCache::FromCell(Point3 p, Normal3 side) const {
  if (cell_ == 0) return nullptr;
  const auto it = cells_.find(CellOf(p));
  if (it == cells_.end()) return nullptr;
  const ImportanceMap* best = nullptr;
  float nearest = INFINITY;
  for (uint32_t k = it->second.first; k < it->second.second; ++k) {
    const MapPhoton& site = sites_[bySite_[k]];
    const Vector3 d = site.position - p;
    const float d2 = Dot(d, d);
    if (d2 < nearest && Dot(site.normal, side) >= kSameSurfaceCosine) nearest = d2, best = &maps_[bySite_[k]];
  }
  return best;
}

const ImportanceMap* ImportanceCache::At(Point3 p, Normal3 side, std::vector<uint32_t>& indices,
                                         std::vector<float>& distance2) const {
  if (const ImportanceMap* map = FromCell(p, side)) return map;
  const size_t found = sites_.Nearest(p, kCandidates, indices, distance2);
  for (size_t i = 0; i < found; ++i)
    if (Dot(sites_[indices[i]].normal, side) >= kSameSurfaceCosine) return &maps_[indices[i]];
  return nullptr;
}

}  // namespace pb
