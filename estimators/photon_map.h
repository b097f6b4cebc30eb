// A photon map in the sense of Jensen 1995/1996: photons stored at their world positions [m] with their incoming
// direction and flux [W], and a 3-D kd-tree (nanoflann) to find the N nearest to a point. The path tracer builds
// its importance maps from these neighbours (estimators/importance_map.h).
#pragma once

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "mesh/color.h"
#include "mesh/geometry.h"

namespace pb {

struct MapPhoton {
  Point3 position;  // [m]
  Vector3 wi;       // unit, toward where the photon came from
  Rgb flux;         // [W]
  Normal3 normal;   // unit normal of the side of the surface it arrived on
};

class PhotonMap {
 public:
  explicit PhotonMap(std::vector<MapPhoton> photons);
  ~PhotonMap();
  PhotonMap(PhotonMap&&) noexcept;

  size_t Size() const { return photons_.size(); }
  const MapPhoton& operator[](uint32_t i) const { return photons_[i]; }

  // The (up to) n photons nearest to p, nearest first, into `indices`; returns how many were found.
  size_t Nearest(Point3 p, size_t n, std::vector<uint32_t>& indices, std::vector<float>& distance2) const;
  // Every photon within `radius` [m] of p, as (index, squared distance [m^2]) in the tree's order (the same for the
  // same photons on any thread), into `found`; returns how many.
  size_t Within(Point3 p, float radius, std::vector<std::pair<uint32_t, float>>& found) const;

 private:
  struct Tree;
  std::vector<MapPhoton> photons_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace pb
