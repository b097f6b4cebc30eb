// Irradiance on one surface by the histogram method (the paper's "Histogram methods"): the surface's (u,v)
// chart is cut into square buckets of side h [m], aligned with the corner of its bounding box; each bucket
// holds the flux [W] of the photons that fell in it. H(x) [W/m^2] is that flux divided by the area of x's bucket
// that lies on the surface (edge-corrected) or by h^2 (uncorrected). Piecewise constant by design.
#pragma once

#include <span>
#include <vector>

#include "estimators/density_estimator.h"
#include "estimators/surface_region.h"

namespace pb {

class HistogramEstimator final : public DensityEstimator {
 public:
  HistogramEstimator(std::span<const Point2> uv, std::span<const Rgb> flux, float h, const SurfaceRegion& region,
                     bool edgeCorrection);

  // For x on a line between buckets, the bucket with the most surface area among those touching x.
  Rgb Estimate(Point2 x) const override;
  double RelativeNoise(Point2 x) const override;

 private:
  int Bucket(int iu, int iv) const { return iv * nu_ + iu; }
  int BucketAt(Point2 x) const;  // the bucket x reads from; -1 when none has area on the surface

  float h_;
  Point2 lo_;
  int nu_ = 1, nv_ = 1;
  std::vector<Rgb> flux_;     // per bucket [W]
  std::vector<double> luminanceSquares_;  // per bucket: sum of the photons' squared flux luminance [W^2]
  std::vector<double> area_;  // per bucket: area on the surface [m^2], or h^2 without edge correction
};

}  // namespace pb
