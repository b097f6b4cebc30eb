#include "estimators/importance_map.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "mesh/errors.h"

namespace pb {
namespace {

constexpr float kBelowOne = 0x1.fffffep-1f;  // the largest float < 1

float Unit(double x) { return std::clamp(float(x), 0.0f, kBelowOne); }

// A sampled point keeps this fraction of its region's side away from the region's edges, so that float rounding
// on the way to a direction and back (cos, sin, atan2) cannot move it into a neighbouring region, whose pdf may
// differ or be 0. It squeezes the uniform density within a region by 2e-4, far below any Monte Carlo noise.
constexpr float kEdge = 1e-4f;
float Inside(float local) { return std::clamp(local, kEdge, 1.0f - kEdge); }

bool IsPowerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }

// Rescales u in [0, 1) into the half of a split whose first half has probability q: returns which half.
bool Descend(float& u, double q) {
  if (u < q) {
    u = Unit(u / q);
    return false;
  }
  u = Unit((u - q) / (1.0 - q));
  return true;
}

}  // namespace

// A (rows + 1) x (cols + 1) summed-area table of a row-major grid: the sum over any rectangle in O(1).
struct ImportanceMap::SummedArea {
  int cols;
  std::vector<double> table;
  SummedArea(const std::vector<float>& values, int rows, int columns)
      : cols(columns), table(size_t(rows + 1) * size_t(columns + 1), 0.0) {
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c)
        At(r + 1, c + 1) = values[size_t(r * cols + c)] + At(r, c + 1) + At(r + 1, c) - At(r, c);
  }
  double& At(int r, int c) { return table[size_t(r) * size_t(cols + 1) + size_t(c)]; }
  double At(int r, int c) const { return table[size_t(r) * size_t(cols + 1) + size_t(c)]; }
  double Sum(int r0, int r1, int c0, int c1) const {  // rows [r0, r1), cols [c0, c1)
    return At(r1, c1) - At(r0, c1) - At(r1, c0) + At(r0, c0);
  }
};

ImportanceMap::ImportanceMap(int rows, int cols, MapDomain domain)
    : rows_(rows), cols_(cols), domain_(domain), importance_(size_t(rows) * size_t(cols), 0.0) {
  PB_CHECK_GE(rows, 1);  // an importance map has at least one region
  PB_CHECK_GE(cols, 1);
  Finish(1.0f);  // uniform until built
}

float ImportanceMap::RegionMeasure() const {
  const double whole = domain_ == MapDomain::kSphere ? 4 * kPi : domain_ == MapDomain::kHemisphere ? 2 * kPi : kPi;
  return float(whole / Regions());
}

float ImportanceMap::PdfIn(uint32_t region, float cosTheta) const {
  const float density = probability_[region] / RegionMeasure();
  return domain_ == MapDomain::kCosineHemisphere ? density * std::max(cosTheta, 0.0f) : density;
}

void ImportanceMap::Clear() { std::fill(importance_.begin(), importance_.end(), 0.0); }

Point2 ImportanceMap::ToSquare(Vector3 d) const {
  const float s = domain_ == MapDomain::kSphere       ? 0.5f * (1.0f - d.z)
                  : domain_ == MapDomain::kHemisphere ? 1.0f - d.z
                                                      : 1.0f - d.z * d.z;
  float phi = std::atan2(d.y, d.x);
  if (phi < 0) phi += float(2 * kPi);
  return {Unit(s), Unit(phi / (2 * kPi))};
}

Vector3 ImportanceMap::FromSquare(Point2 st) const {
  const float z = domain_ == MapDomain::kSphere       ? 1.0f - 2.0f * st.u
                  : domain_ == MapDomain::kHemisphere ? 1.0f - st.u
                                                      : std::sqrt(1.0f - st.u);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = float(2 * kPi) * st.v;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

std::optional<uint32_t> ImportanceMap::RegionOf(Vector3 d) const {
  if (domain_ != MapDomain::kSphere && d.z < 0) return std::nullopt;
  const Point2 st = ToSquare(d);
  const int row = std::min(rows_ - 1, int(st.u * float(rows_))), col = std::min(cols_ - 1, int(st.v * float(cols_)));
  return uint32_t(row * cols_ + col);
}

void ImportanceMap::Add(Vector3 d, float importance) {
  if (const auto region = RegionOf(d); region && importance > 0 && std::isfinite(importance))
    importance_[*region] += importance;
}

void ImportanceMap::Finish(float floorFraction) {
  const double total = std::accumulate(importance_.begin(), importance_.end(), 0.0);
  const double n = Regions(), floor = total > 0 ? std::clamp(double(floorFraction), 0.0, 1.0) : 1.0;
  probability_.resize(importance_.size());
  cdf_.resize(importance_.size());
  double running = 0;
  for (size_t k = 0; k < importance_.size(); ++k) {
    probability_[k] = float((total > 0 ? (1 - floor) * importance_[k] / total : 0.0) + floor / n);
    cdf_[k] = running += probability_[k];
  }
  for (double& c : cdf_) c /= running;  // exactly 1 at the end despite float rounding of the probabilities
  for (float& p : probability_) p = float(p / running);
  splits_.clear();
  if (IsPowerOfTwo(rows_) && IsPowerOfTwo(cols_)) {  // the mip-map warp's table; inversion reads cdf_ alone
    splits_.resize(size_t(Regions() - 1));
    TabulateSplits({0, rows_, 0, cols_}, 0, SummedArea(probability_, rows_, cols_));
  }
}

ImportanceMap::Split ImportanceMap::Halving(const Node& n) {
  const bool rows = n.r1 - n.r0 >= n.c1 - n.c0;  // halve the longer side
  return {rows, rows ? (n.r0 + n.r1) / 2 : (n.c0 + n.c1) / 2, 0.0};
}

void ImportanceMap::TabulateSplits(const Node& n, size_t index, const SummedArea& sums) {
  if (n.IsCell()) return;
  const Split s = Halving(n);
  const double first = s.rows ? sums.Sum(n.r0, s.mid, n.c0, n.c1) : sums.Sum(n.r0, n.r1, n.c0, s.mid);
  splits_[index] = first / sums.Sum(n.r0, n.r1, n.c0, n.c1);
  for (const bool second : {false, true}) {
    Node child = n;
    child.Keep(s, second);
    TabulateSplits(child, 2 * index + 1 + size_t(second), sums);
  }
}

ImportanceMap::Split ImportanceMap::TabulatedSplit(const Node& n, size_t index) const {
  Split s = Halving(n);
  s.first = splits_[index];
  return s;
}

Point2 ImportanceMap::SampleInversionSquare(Point2 u, uint32_t& region) const {
  region = uint32_t(std::min<ptrdiff_t>(std::upper_bound(cdf_.begin(), cdf_.end(), double(u.u)) - cdf_.begin(),
                                        ptrdiff_t(cdf_.size()) - 1));
  const double start = region ? cdf_[region - 1] : 0.0, width = cdf_[region] - start;
  const float a = width > 0 ? Unit((u.u - start) / width) : 0.5f;
  const int row = int(region) / cols_, col = int(region) % cols_;
  return {(float(row) + Inside(a)) / float(rows_), (float(col) + Inside(u.v)) / float(cols_)};
}

void ImportanceMap::Node::Keep(const Split& s, bool second) {
  int& lo = s.rows ? r0 : c0;
  int& hi = s.rows ? r1 : c1;
  (second ? lo : hi) = s.mid;
}

Point2 ImportanceMap::SampleMipmapSquare(Point2 u, uint32_t& region) const {
  Node n{0, rows_, 0, cols_};
  for (size_t index = 0; !n.IsCell();) {
    const Split s = TabulatedSplit(n, index);
    const bool second = Descend(s.rows ? u.u : u.v, s.first);
    n.Keep(s, second);
    index = 2 * index + 1 + size_t(second);
  }
  region = uint32_t(n.r0 * cols_ + n.c0);
  return {(float(n.r0) + Inside(u.u)) / float(rows_), (float(n.c0) + Inside(u.v)) / float(cols_)};
}

ImportanceSample ImportanceMap::Sample(Point2 u, ImportanceWarp warp) const {
  PB_CHECK(warp != ImportanceWarp::kMipmap || (IsPowerOfTwo(rows_) && IsPowerOfTwo(cols_)),
           "mip-map warping needs power-of-two rows and cols");
  uint32_t region = 0;
  const Point2 st = warp == ImportanceWarp::kMipmap ? SampleMipmapSquare(u, region) : SampleInversionSquare(u, region);
  const Vector3 d = FromSquare(st);
  return {d, PdfIn(region, d.z), region};
}

float ImportanceMap::Pdf(Vector3 d) const {
  const auto region = RegionOf(d);
  return region ? PdfIn(*region, d.z) : 0.0f;
}

Point2 ImportanceMap::InvertInversionSquare(uint32_t region, Point2 local) const {
  const double start = region ? cdf_[region - 1] : 0.0;
  return {Unit(start + local.u * (cdf_[region] - start)), local.v};
}

Point2 ImportanceMap::InvertMipmapSquare(int row, int col, Point2 local) const {
  Node n{0, rows_, 0, cols_};
  double ox = 0, sx = 1, oy = 0, sy = 1;  // u = o + s * (the coordinate inside the current node)
  for (size_t index = 0; !n.IsCell();) {
    const Split split = TabulatedSplit(n, index);
    const bool second = (split.rows ? row : col) >= split.mid;
    index = 2 * index + 1 + size_t(second);
    double& o = split.rows ? ox : oy;
    double& s = split.rows ? sx : sy;
    if (second) o += s * split.first;
    s *= second ? 1 - split.first : split.first;
    n.Keep(split, second);
  }
  return {Unit(ox + sx * local.u), Unit(oy + sy * local.v)};
}

std::optional<Point2> ImportanceMap::Invert(Vector3 d, ImportanceWarp warp) const {
  const auto region = RegionOf(d);
  if (!region || probability_[*region] <= 0) return std::nullopt;
  const Point2 st = ToSquare(d);
  const int row = int(*region) / cols_, col = int(*region) % cols_;
  const Point2 local{Unit(st.u * float(rows_) - float(row)), Unit(st.v * float(cols_) - float(col))};
  return warp == ImportanceWarp::kMipmap ? InvertMipmapSquare(row, col, local) : InvertInversionSquare(*region, local);
}

}  // namespace pb
