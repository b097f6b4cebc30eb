#include "estimators/importance_cache.h"

#include <algorithm>
#include <cmath>

#include "estimators/warps.h"

namespace pb {
namespace {

constexpr int kCellBits = 21;
constexpr float kCellsPerAxis = float(1 << kCellBits);

uint64_t Mix(uint64_t key) {  // SplitMix64's finaliser: neighbouring cells land far apart in the table
  key = (key ^ (key >> 30)) * 0xbf58476d1ce4e5b9ull;
  key = (key ^ (key >> 27)) * 0x94d049bb133111ebull;
  return key ^ (key >> 31);
}

struct Bounds {
  Point3 low{INFINITY, INFINITY, INFINITY}, high{-INFINITY, -INFINITY, -INFINITY};
  float Extent() const { return std::max({high.x - low.x, high.y - low.y, high.z - low.z}); }
};

Bounds BoundsOf(const std::vector<MapPhoton>& photons) {
  Bounds b;
  for (const MapPhoton& p : photons) {
    b.low = {std::min(b.low.x, p.position.x), std::min(b.low.y, p.position.y), std::min(b.low.z, p.position.z)};
    b.high = {std::max(b.high.x, p.position.x), std::max(b.high.y, p.position.y), std::max(b.high.z, p.position.z)};
  }
  return b;
}

uint64_t KeyOf(Point3 p, Point3 origin, float cell) {
  // Compared in floating point before any conversion, so that a point far outside (or NaN) is never cast.
  const auto index = [&](float x, float o) { return std::floor((x - o) / cell); };
  const float i = index(p.x, origin.x), j = index(p.y, origin.y), k = index(p.z, origin.z);
  const auto inside = [](float c) { return c >= 0 && c < kCellsPerAxis; };
  if (!inside(i) || !inside(j) || !inside(k)) return ImportanceCache::kOutside;
  return uint64_t(i) | uint64_t(j) << kCellBits | uint64_t(k) << (2 * kCellBits);
}

// The cell side [m] at which a cell that photons reached holds about `perCell` of them on average. Photons lie on
// surfaces, so that count grows as the side squared: two rounds of counting the occupied cells at a trial side
// correct the side by the square root of the ratio. At least extent / 2^21, so that every cell has its own key.
float CellSideFor(const std::vector<MapPhoton>& photons, const Bounds& bounds, uint32_t perCell) {
  const float extent = bounds.Extent(), smallest = extent / (kCellsPerAxis - 2);
  if (!(extent > 0) || !std::isfinite(extent)) return 1.0f;
  float side = extent / 256;
  for (int round = 0; round < 2; ++round) {
    CellTable occupied(photons.size() / 4);
    for (const MapPhoton& p : photons) occupied.Insert(KeyOf(p.position, bounds.low, side));
    const double mean = double(photons.size()) / double(occupied.Size());
    side = std::max(smallest, float(side * std::sqrt(double(perCell) / mean)));
  }
  return side;
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

CellTable::CellTable(size_t expectedKeys) {
  size_t slots = 16;
  while (slots < 2 * expectedKeys) slots *= 2;
  keys_.assign(slots, 0);
  values_.assign(slots, kAbsent);
}

size_t CellTable::SlotOf(uint64_t key) const {
  const size_t mask = keys_.size() - 1;
  size_t slot = size_t(Mix(key)) & mask;
  while (values_[slot] != kAbsent && keys_[slot] != key) slot = (slot + 1) & mask;
  return slot;
}

void CellTable::Grow() {
  std::vector<uint64_t> keys(keys_.size() * 2, 0);
  std::vector<uint32_t> values(values_.size() * 2, kAbsent);
  keys_.swap(keys);
  values_.swap(values);
  for (size_t i = 0; i < keys.size(); ++i)
    if (values[i] != kAbsent) {
      const size_t slot = SlotOf(keys[i]);
      keys_[slot] = keys[i];
      values_[slot] = values[i];
    }
}

uint32_t CellTable::Insert(uint64_t key) {
  if (2 * (count_ + 1) > keys_.size()) Grow();
  const size_t slot = SlotOf(key);
  if (values_[slot] == kAbsent) {
    keys_[slot] = key;
    values_[slot] = uint32_t(count_++);
  }
  return values_[slot];
}

uint32_t CellTable::Find(uint64_t key) const { return values_[SlotOf(key)]; }

ImportanceCache::ImportanceCache(const std::vector<MapPhoton>& photons, const MapSettings& settings) {
  if (photons.empty()) return;
  const Bounds bounds = BoundsOf(photons);
  origin_ = bounds.low;
  cell_ = CellSideFor(photons, bounds, std::max(settings.neighbours, 1u));
  Bin(photons, settings);
}

uint64_t ImportanceCache::CellOf(Point3 p) const { return cell_ > 0 ? KeyOf(p, origin_, cell_) : kOutside; }

void ImportanceCache::Bin(const std::vector<MapPhoton>& photons, const MapSettings& settings) {
  std::vector<Frame> frames;  // per group
  for (const MapPhoton& photon : photons) {
    const uint32_t cell = cells_.Insert(CellOf(photon.position));
    if (cell == firstGroup_.size()) firstGroup_.push_back(UINT32_MAX);
    uint32_t* link = &firstGroup_[cell];
    while (*link != UINT32_MAX && Dot(groups_[*link].normal, photon.normal) < kSameSurfaceCosine)
      link = &groups_[*link].next;
    uint32_t group = *link;
    if (group == UINT32_MAX) {  // the first photon of its cell facing its way (link is read before groups_ grows)
      group = *link = uint32_t(groups_.size());
      groups_.push_back({photon.normal});
      frames.push_back(Frame::FromNormal(photon.normal));
      maps_.emplace_back(settings.rows, settings.cols, settings.domain);
    }
    ++groups_[group].photons;
    maps_[group].Add(frames[group].ToLocal(photon.wi), Luminance(photon.flux));  // ignored unless in the hemisphere
  }
  const double n = std::max(settings.neighbours, 1u);
  for (size_t g = 0; g < maps_.size(); ++g)
    maps_[g].Finish(std::max(settings.floorFraction, float(1.0 - groups_[g].photons / n)));
}

const ImportanceMap* ImportanceCache::At(Point3 p, Normal3 side) const {
  const uint64_t key = CellOf(p);
  if (key == kOutside) return nullptr;
  const uint32_t cell = cells_.Find(key);
  if (cell == CellTable::kAbsent) return nullptr;
  const ImportanceMap* best = nullptr;
  float closest = kSameSurfaceCosine;
  for (uint32_t g = firstGroup_[cell]; g != UINT32_MAX; g = groups_[g].next)
    if (const float c = Dot(groups_[g].normal, side); c >= closest) closest = c, best = &maps_[g];
  return best;
}

}  // namespace pb
