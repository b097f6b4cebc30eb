#include "estimators/photon_map.h"

#include <nanoflann.hpp>

namespace pb {

// nanoflann's dataset interface over the photons' positions.
struct PhotonMap::Tree {
  struct Points {
    const std::vector<MapPhoton>* photons;
    size_t kdtree_get_point_count() const { return photons->size(); }
    float kdtree_get_pt(size_t i, size_t dim) const {
      const Point3& p = (*photons)[i].position;
      return dim == 0 ? p.x : dim == 1 ? p.y : p.z;
    }
    template <class Box>
    bool kdtree_get_bbox(Box&) const { return false; }
  };
  using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Points>, Points, 3, uint32_t>;
  Points points;
  Index index;
  explicit Tree(const std::vector<MapPhoton>& photons)
      : points{&photons}, index(3, points, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
};

PhotonMap::PhotonMap(std::vector<MapPhoton> photons)
    : photons_(std::move(photons)), tree_(std::make_unique<Tree>(photons_)) {}
PhotonMap::~PhotonMap() = default;
PhotonMap::PhotonMap(PhotonMap&& other) noexcept
    : photons_(std::move(other.photons_)), tree_(std::move(other.tree_)) {
  if (tree_) tree_->points.photons = &photons_;  // the vector's buffer moved with it; re-point the adaptor
}

size_t PhotonMap::Nearest(Point3 p, size_t n, std::vector<uint32_t>& indices, std::vector<float>& distance2) const {
  n = std::min(n, photons_.size());
  indices.resize(n);
  distance2.resize(n);
  if (n == 0) return 0;
  const float query[3] = {p.x, p.y, p.z};
  const size_t found = tree_->index.knnSearch(query, n, indices.data(), distance2.data());
  indices.resize(found);
  distance2.resize(found);
  return found;
}

size_t PhotonMap::Within(Point3 p, float radius, std::vector<std::pair<uint32_t, float>>& found) const {
  found.clear();
  if (photons_.empty() || !(radius > 0)) return 0;
  const float query[3] = {p.x, p.y, p.z};
  // L2_Simple_Adaptor measures squared distances, so the radius goes in squared; unsorted: the tree's own order.
  return tree_->index.radiusSearch(query, radius * radius, found, nanoflann::SearchParams(32, 0, false));
}

}  // namespace pb
