#include "estimators/nearest_estimator.h"

#include <nanoflann.hpp>

#include <cmath>

#include "mesh/errors.h"

namespace pb {

// nanoflann's dataset interface over the photons' chart positions.
struct NearestEstimator::Tree {
  struct Points {
    const std::vector<Point2>* uv;
    size_t kdtree_get_point_count() const { return uv->size(); }
    float kdtree_get_pt(size_t i, size_t dim) const { return dim == 0 ? (*uv)[i].u : (*uv)[i].v; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const { return false; }
  };
  using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Points>, Points, 2, uint32_t>;
  Points points;
  Index index;
  explicit Tree(const std::vector<Point2>& uv) : points{&uv}, index(2, points, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
};

NearestEstimator::NearestEstimator(std::span<const Point2> uv, std::span<const Rgb> flux, uint32_t k,
                                   const SurfaceRegion& region, bool edgeCorrection)
    : k_(k), region_(region), edgeCorrection_(edgeCorrection), uv_(uv.begin(), uv.end()), photonFlux_(flux.begin(), flux.end()) {
  PB_CHECK_GE(k, 2u);
  PB_CHECK_EQ(uv.size(), flux.size());  // one flux per photon
  if (uv_.size() >= k_) {
    tree_ = std::make_unique<Tree>(uv_);
    return;
  }
  RgbSum total;
  for (const Rgb& p : photonFlux_) total.Add(p);
  if (region.Area() > 0) surfaceMean_ = total.ToRgb() * float(1.0 / region.Area());
}

NearestEstimator::~NearestEstimator() = default;

size_t NearestEstimator::Search(Point2 x, std::vector<uint32_t>& index, std::vector<float>& distance2) const {
  index.resize(k_);
  distance2.resize(k_);
  const float query[2] = {x.u, x.v};
  return tree_->index.knnSearch(query, k_, index.data(), distance2.data());
}

double NearestEstimator::RelativeNoise(Point2 x) const {
  std::vector<uint32_t> index;
  std::vector<float> distance2;
  const size_t found = tree_ ? Search(x, index, distance2) : photonFlux_.size();
  double sum = 0, squares = 0;
  for (size_t i = 0; i < found; ++i) {
    const double w = Luminance(photonFlux_[tree_ ? index[i] : i]);
    sum += w;
    squares += w * w;
  }
  if (!(sum > 0)) return 0.0;
  return std::sqrt(squares) / sum * (found > 2 ? std::sqrt(double(found) / double(found - 2)) : 1.0);
}

Rgb NearestEstimator::Estimate(Point2 x) const {
  if (!tree_) return surfaceMean_;
  std::vector<uint32_t> index;
  std::vector<float> distance2;
  const size_t found = Search(x, index, distance2);
  RgbSum flux;
  for (size_t i = 0; i < found; ++i) flux.Add(photonFlux_[index[i]]);
  const double r = std::sqrt(double(distance2[found - 1]));
  const double fraction =
      edgeCorrection_ ? std::max(region_.KernelMass(x, Kernel::kUniform, r),
                                 MinimumKernelMass(region_.Area(), Kernel::kUniform, float(r)))
                      : 1.0;
  const double area = M_PI * r * r * fraction;
  if (!(area > 0)) return {};  // k photons at exactly x: no area to divide by
  return flux.ToRgb() * float(double(k_ - 1) / double(k_) / area);
}

}  // namespace pb
