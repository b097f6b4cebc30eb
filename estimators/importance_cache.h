// Importance maps built once and reused, as Jensen 1995 ("Importance Driven Path Tracing using the Photon Map",
// section 4) suggests: a map costs a nearest-neighbour query among all the photons and its own tables (about 20 us
// at a million photons), where a BRDF bounce costs one ray (about 0.2 us), so building one at every hit loses at
// equal time whatever it saves in variance.
//
// A map is the paper's (estimators/importance_map.h): the N nearest photons that arrived on a surface facing the
// same way (normals within about 25 degrees) each add their power (luminance) to the region of their incoming
// direction, in the frame of the normal, and a floor fraction is spread over every region. (The BRDF, Lambertian,
// is the same for every direction and drops out when the map is normalised.)
//
// The cache's sites are every `stride`-th photon of the photon map, in its order, each with the map its own N
// nearest photons build. A hit takes the map of the nearest site in its cell of a uniform grid (cells of the
// median distance from a site to its kCandidates-th nearest, so that a cell holds a few sites) whose normal is
// within 25 degrees of its own, or, where its cell holds none, of the nearest of its kCandidates nearest sites; it
// reads the map in its own normal's frame. Where no site qualifies, the caller builds a map at the hit. Either way the direction's pdf is that of the map it was drawn from, so the estimate stays unbiased
// whichever map answers (the floor keeps every direction possible); a neighbour's map only fits the hit's light a
// little less well.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "estimators/importance_map.h"
#include "estimators/photon_map.h"
#include "mesh/geometry.h"

namespace pb {

// A neighbour whose surface normal is more than about 25 degrees from the point's describes light arriving at a
// different surface (the floor beside a wall, the other side of a thin panel).
inline constexpr float kSameSurfaceCosine = 0.9f;

struct MapSettings {
  uint32_t neighbours = 50;  // N
  int rows = 4, cols = 8;    // regions, each the same measure of the domain
  float floorFraction = 0.3f;
  MapDomain domain = MapDomain::kCosineHemisphere;
};

// Fills `map` (Clear, Add, Finish) from the photons nearest to p (world [m]) on a surface of normal `side`;
// `indices` and `distance2` are working memory.
void BuildImportanceMap(ImportanceMap& map, const PhotonMap& photons, Point3 p, Normal3 side, const MapSettings& s,
                        std::vector<uint32_t>& indices, std::vector<float>& distance2);

class ImportanceCache {
 public:
  static constexpr size_t kCandidates = 4;
  // Builds the sites' maps in parallel. stride >= 1.
  ImportanceCache(const PhotonMap& photons, const MapSettings& settings, uint32_t stride);

  size_t Size() const { return maps_.size(); }
  // The map for a hit at p with normal `side`, or null where no site nearby faces its way.
  const ImportanceMap* At(Point3 p, Normal3 side, std::vector<uint32_t>& indices, std::vector<float>& distance2) const;

 private:
  void BuildGrid(std::vector<float> spacing);
  uint64_t CellOf(Point3 p) const;
  const ImportanceMap* FromCell(Point3 p, Normal3 side) const;

  PhotonMap sites_;                  // the sites' positions and normals
  std::vector<ImportanceMap> maps_;  // per site
  float cell_ = 0;                   // the grid's cell side [m]; 0: no grid
  std::vector<uint32_t> bySite_;     // site indices, cell by cell
  std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> cells_;  // cell -> its range of bySite_
};

}  // namespace pb
