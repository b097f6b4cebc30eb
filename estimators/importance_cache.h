// Importance maps built once and reused, as Jensen 1995 ("Importance Driven Path Tracing using the Photon Map",
// section 4) suggests: a map costs a nearest-neighbour query among all the photons and its own tables (about 20 us
// at a million photons), where a BRDF bounce costs one ray (about 0.2 us), so building one at every hit loses at
// equal time whatever it saves in variance.
//
// A map is the paper's (estimators/importance_map.h): photons that arrived near a point, on a surface facing the
// same way (normals within about 25 degrees), each add their power (luminance) to the region of their incoming
// direction, in the frame of the normal, and a floor fraction is spread over every region. (The BRDF, Lambertian,
// is the same for every direction and drops out when the map is normalised.)
//
// The cache bins the photons into a uniform grid of cubic cells [m], sized so that a cell a photon reached holds
// about N of them on average (N = MapSettings::neighbours, the paper's N nearest), and within a cell into groups
// by surface orientation: a photon joins the first group whose normal (that of its first photon) lies within 25
// degrees of its own. Each group's photons build one map, in the frame of the group's normal. Building costs one
// pass over the photons and no nearest-neighbour search: no kd-tree is needed. A hit takes the map of the group
// in its own cell that faces its way most nearly, and reads it in its own normal's frame; where none does, the
// caller draws from the cosine lobe. Either way the direction's pdf is that of the map (or lobe) it was drawn
// from, so the estimate stays unbiased whichever answers (the floor keeps every direction possible).
//
// A group of fewer than N photons describes its light less surely, so its floor grows toward the whole map: floor
// max(f, 1 - count / N). A group of one photon is then almost the cosine lobe, not a spike that sends most paths
// one way and weights the rest heavily.
#pragma once

#include <cstdint>
#include <vector>

#include "estimators/importance_map.h"
#include "estimators/photon_map.h"
#include "mesh/geometry.h"

namespace pb {

// A neighbour whose surface normal is more than about 25 degrees from the point's describes light arriving at a
// different surface (the floor beside a wall, the other side of a thin panel).
inline constexpr float kSameSurfaceCosine = 0.9f;

struct MapSettings {
  uint32_t neighbours = 50;  // N: nearest photons per map at a hit, photons per cell on average in the cache
  int rows = 4, cols = 8;    // regions, each the same measure of the domain
  float floorFraction = 0.3f;
  MapDomain domain = MapDomain::kCosineHemisphere;
};

// Fills `map` (Clear, Add, Finish) from the photons nearest to p (world [m]) on a surface of normal `side`;
// `indices` and `distance2` are working memory.
void BuildImportanceMap(ImportanceMap& map, const PhotonMap& photons, Point3 p, Normal3 side, const MapSettings& s,
                        std::vector<uint32_t>& indices, std::vector<float>& distance2);

// An open-addressing table of 64-bit cell keys to dense indices 0, 1, 2, ... in the order first inserted; it
// doubles when half full.
class CellTable {
 public:
  explicit CellTable(size_t expectedKeys = 0);
  uint32_t Insert(uint64_t key);        // the key's index, new or old
  uint32_t Find(uint64_t key) const;    // kAbsent when absent
  size_t Size() const { return count_; }
  static constexpr uint32_t kAbsent = UINT32_MAX;

 private:
  size_t SlotOf(uint64_t key) const;  // the key's slot, or the empty slot where it would go
  void Grow();
  std::vector<uint64_t> keys_;
  std::vector<uint32_t> values_;  // kAbsent where no key
  size_t count_ = 0;
};

class ImportanceCache {
 public:
  // Builds the maps from `photons` (positions [m], directions, flux, normals). N = settings.neighbours >= 1.
  ImportanceCache(const std::vector<MapPhoton>& photons, const MapSettings& settings);

  size_t Size() const { return groups_.size(); }  // maps
  float CellSide() const { return cell_; }          // [m]; 0 without photons
  // The map for a hit at p (world [m]) with normal `side`, or null where none in its cell faces its way.
  const ImportanceMap* At(Point3 p, Normal3 side) const;
  // The key of p's cell: (i, j, k) counted from the photons' lowest corner, 21 bits each, so no two cells share
  // one; kOutside beyond the photons' bounds.
  uint64_t CellOf(Point3 p) const;
  static constexpr uint64_t kOutside = UINT64_MAX;

 private:
  struct Group {
    Normal3 normal;
    uint32_t photons = 0;
    uint32_t next = UINT32_MAX;  // the next group of the same cell
  };
  void Bin(const std::vector<MapPhoton>& photons, const MapSettings& settings);

  Point3 origin_;  // the photons' lowest corner [m]
  float cell_ = 0;
  CellTable cells_;
  std::vector<uint32_t> firstGroup_;  // per cell
  std::vector<Group> groups_;
  std::vector<ImportanceMap> maps_;   // per group
};

}  // namespace pb
