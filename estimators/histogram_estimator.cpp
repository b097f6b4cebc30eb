#include "estimators/histogram_estimator.h"

#include <algorithm>
#include <cmath>

#include "mesh/errors.h"

namespace pb {
namespace {
// A grid of many more buckets than photons is mostly empty: h is then far below the photon spacing and the
// estimate is noise. The grid is capped (buckets grow) rather than exhausting memory, as in KernelEstimator.
constexpr double kMaxBucketsPerPhoton = 4.0;
constexpr double kMinBucketBudget = 1 << 12, kMaxBucketBudget = 1 << 22;
}  // namespace

HistogramEstimator::HistogramEstimator(std::span<const Point2> uv, std::span<const Rgb> flux, float h,
                                       const SurfaceRegion& region, bool edgeCorrection)
    : h_(h), lo_(region.Bounds().lo) {
  PB_CHECK(h > 0 && std::isfinite(h), "bucket side is positive and finite");
  PB_CHECK_EQ(uv.size(), flux.size());  // one flux per photon
  const Bounds2& b = region.Bounds();
  if (region.Triangles().empty()) return;
  const double su = double(b.hi.u) - b.lo.u, sv = double(b.hi.v) - b.lo.v;
  const double budget = std::clamp(kMaxBucketsPerPhoton * double(uv.size()), kMinBucketBudget, kMaxBucketBudget);
  while ((su / h_ + 1) * (sv / h_ + 1) > budget) h_ *= 2;
  nu_ = int(su / h_) + 1;
  nv_ = int(sv / h_) + 1;
  std::vector<RgbSum> sums(size_t(nu_) * nv_);
  luminanceSquares_.assign(sums.size(), 0.0);
  for (size_t i = 0; i < uv.size(); ++i) {
    const int iu = std::clamp(int(std::floor((uv[i].u - lo_.u) / h_)), 0, nu_ - 1);
    const int iv = std::clamp(int(std::floor((uv[i].v - lo_.v) / h_)), 0, nv_ - 1);
    sums[Bucket(iu, iv)].Add(flux[i], 1.0f);
    luminanceSquares_[Bucket(iu, iv)] += double(Luminance(flux[i])) * Luminance(flux[i]);
  }
  flux_.resize(sums.size());
  for (size_t i = 0; i < sums.size(); ++i) flux_[i] = sums[i].ToRgb();

  area_ = edgeCorrection ? region.GridOverlapAreas(lo_, h_, nu_, nv_) : std::vector<double>(sums.size(), double(h_) * h_);
}

int HistogramEstimator::BucketAt(Point2 x) const {
  if (flux_.empty()) return -1;
  const double fu = (x.u - lo_.u) / h_, fv = (x.v - lo_.v) / h_;
  int best = -1;
  for (double du : {-1e-6, 1e-6})
    for (double dv : {-1e-6, 1e-6}) {  // the up to four buckets whose closure holds x
      const int iu = std::clamp(int(std::floor(fu + du)), 0, nu_ - 1), iv = std::clamp(int(std::floor(fv + dv)), 0, nv_ - 1);
      if (best < 0 || area_[Bucket(iu, iv)] > area_[best]) best = Bucket(iu, iv);
    }
  return area_[best] > 0 ? best : -1;
}

Rgb HistogramEstimator::Estimate(Point2 x) const {
  const int b = BucketAt(x);
  return b < 0 ? Rgb{} : flux_[b] * float(1.0 / area_[b]);
}

double HistogramEstimator::RelativeNoise(Point2 x) const {
  const int b = BucketAt(x);
  const double sum = b < 0 ? 0.0 : Luminance(flux_[b]);
  return sum > 0 ? std::sqrt(luminanceSquares_[b]) / sum : 0.0;
}

}  // namespace pb
