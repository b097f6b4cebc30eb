#include "mesh/intensity_profile.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "mesh/errors.h"

namespace pb {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi, kHalfPi = std::numbers::pi / 2;
constexpr double kSameAngle = 1e-9;  // [rad]: angles closer than this are one

// The lateral symmetries of LM-63's horizontal angles, and where each maps an angle of the full circle to.
enum class Symmetry { kAxial, kQuadrant, kAbout0To180, kAbout90To270, kNone };

Symmetry SymmetryOf(const std::vector<double>& c) {
  if (c.size() == 1) return Symmetry::kAxial;
  if (std::fabs(c.front() - kHalfPi) < kSameAngle) return Symmetry::kAbout90To270;
  if (std::fabs(c.back() - kHalfPi) < kSameAngle) return Symmetry::kQuadrant;
  if (std::fabs(c.back() - std::numbers::pi) < kSameAngle) return Symmetry::kAbout0To180;
  return Symmetry::kNone;
}

// The angle within the measured range whose intensity the angle c in [0, 2 pi] has.
double Fold(Symmetry symmetry, double c) {
  switch (symmetry) {
    case Symmetry::kAxial: return 0;
    case Symmetry::kQuadrant:
      if (c > 3 * kHalfPi) return kTwoPi - c;
      if (c > std::numbers::pi) return c - std::numbers::pi;
      return c > kHalfPi ? std::numbers::pi - c : c;
    case Symmetry::kAbout0To180: return c > std::numbers::pi ? kTwoPi - c : c;
    case Symmetry::kAbout90To270:
      if (c < kHalfPi) return std::numbers::pi - c;
      return c > 3 * kHalfPi ? 3 * std::numbers::pi - c : c;
    case Symmetry::kNone: return c;
  }
  return c;
}

// The images over the full circle of each measured angle under the symmetry's mirrors, with 0 and 2 pi.
std::vector<double> ExpandedAngles(Symmetry symmetry, const std::vector<double>& measured) {
  constexpr double pi = std::numbers::pi;
  std::vector<double> all{0, kTwoPi};
  for (double a : measured) {
    switch (symmetry) {
      case Symmetry::kAxial: break;
      case Symmetry::kQuadrant: all.insert(all.end(), {a, pi - a, pi + a, kTwoPi - a}); break;
      case Symmetry::kAbout0To180: all.insert(all.end(), {a, kTwoPi - a}); break;
      case Symmetry::kAbout90To270: all.insert(all.end(), {a, pi - a, 3 * pi - a}); break;
      case Symmetry::kNone: all.push_back(a); break;
    }
  }
  std::erase_if(all, [](double c) { return c < 0 || c > kTwoPi; });  // a mirror's image of the other half
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end(), [](double x, double y) { return y - x < kSameAngle; }), all.end());
  all.back() = kTwoPi;
  return all;
}

// Index i with angles[i] <= x < angles[i + 1], and the fraction of the way; angles has at least 2 entries and x
// lies within them.
std::pair<size_t, double> Bracket(const std::vector<double>& angles, double x) {
  const size_t i = std::min<size_t>(angles.size() - 2,
                                    size_t(std::upper_bound(angles.begin(), angles.end(), x) - angles.begin()) - 1);
  return {i, std::clamp((x - angles[i]) / (angles[i + 1] - angles[i]), 0.0, 1.0)};
}

}  // namespace

IntensityProfile::IntensityProfile(std::string source, std::vector<double> gamma, std::vector<double> c,
                                   std::vector<double> candela)
    : source_(std::move(source)), gamma_(std::move(gamma)), c_(std::move(c)), candela_(std::move(candela)) {
  PB_CHECK(gamma_.size() >= 2 && !c_.empty(), "a profile has two vertical angles and a horizontal one");
  PB_CHECK_EQ(candela_.size(), gamma_.size() * c_.size());
  PB_CHECK(gamma_.front() >= 0 && gamma_.back() <= std::numbers::pi, "vertical angles lie in [0, pi]");
  PB_CHECK(std::adjacent_find(gamma_.begin(), gamma_.end(), std::greater_equal<>()) == gamma_.end(),
           "vertical angles increase");
  PB_CHECK(std::adjacent_find(c_.begin(), c_.end(), std::greater_equal<>()) == c_.end(), "horizontal angles increase");
  PB_CHECK(std::all_of(candela_.begin(), candela_.end(), [](double v) { return v >= 0 && std::isfinite(v); }),
           "intensities are finite and not negative");
  ExpandSymmetry();
  std::vector<double> flux;
  for (size_t h = 0; h + 1 < c_.size(); ++h)
    for (size_t v = 0; v + 1 < gamma_.size(); ++v) flux.push_back(flux_ += CellFlux(h, v));
  if (!(flux_ > 0)) return;
  for (double& f : flux) f /= flux_;
  flux.back() = 1;
  cellCdf_ = std::move(flux);
}

// Replaces the measured columns by columns at every angle of the full circle that a measured one maps to, each
// the measured table's interpolation at its folded angle: bilinear interpolation in the expanded table then
// equals that of the folded one, since each mirror is linear in C between consecutive expanded angles.
void IntensityProfile::ExpandSymmetry() {
  const Symmetry symmetry = SymmetryOf(c_);
  std::vector<double> measured = c_, columns = candela_;
  if (symmetry == Symmetry::kNone && kTwoPi - measured.back() >= kSameAngle) {
    measured.push_back(kTwoPi);  // the last measured plane's neighbour is C = 0's
    columns.insert(columns.end(), candela_.begin(), candela_.begin() + std::ptrdiff_t(gamma_.size()));
  }
  std::vector<double> expanded = ExpandedAngles(symmetry, measured);
  std::vector<double> values;
  values.reserve(expanded.size() * gamma_.size());
  for (double c : expanded) {
    const double folded = Fold(symmetry, c);
    const auto [h, t] = measured.size() == 1 ? std::pair<size_t, double>{0, 0.0} : Bracket(measured, folded);
    const size_t next = std::min(h + 1, measured.size() - 1);
    for (size_t v = 0; v < gamma_.size(); ++v)
      values.push_back((1 - t) * columns[h * gamma_.size() + v] + t * columns[next * gamma_.size() + v]);
  }
  c_ = std::move(expanded);
  candela_ = std::move(values);
}

double IntensityProfile::Intensity(double gamma, double c) const {
  if (!(gamma >= gamma_.front() && gamma <= gamma_.back())) return 0;
  const auto [v, s] = Bracket(gamma_, gamma);
  const auto [h, t] = Bracket(c_, std::clamp(c, 0.0, kTwoPi));
  const double near = (1 - s) * At(h, v) + s * At(h, v + 1), far = (1 - s) * At(h + 1, v) + s * At(h + 1, v + 1);
  return (1 - t) * near + t * far;
}

// The integral of the bilinear interpolant times sin(gamma) over the cell: with s the fraction of the way from
// gamma0 to gamma1, integral s sin(gamma) dgamma = (sin g1 - sin g0) / (g1 - g0) - cos g1, and the average over C
// of a linear function is its mean at the ends.
double IntensityProfile::CellFlux(size_t h, size_t v) const {
  const double g0 = gamma_[v], g1 = gamma_[v + 1];
  const double toFar = (std::sin(g1) - std::sin(g0)) / (g1 - g0) - std::cos(g1);
  const double toNear = (std::cos(g0) - std::cos(g1)) - toFar;
  const double nearRow = 0.5 * (At(h, v) + At(h + 1, v)), farRow = 0.5 * (At(h, v + 1) + At(h + 1, v + 1));
  return (c_[h + 1] - c_[h]) * std::max(0.0, nearRow * toNear + farRow * toFar);
}

IntensityProfile::Cell IntensityProfile::CellAt(size_t index) const {
  const size_t h = index / (gamma_.size() - 1), v = index % (gamma_.size() - 1);
  const double most = std::max({At(h, v), At(h, v + 1), At(h + 1, v), At(h + 1, v + 1)});
  return {gamma_[v], gamma_[v + 1], c_[h], c_[h + 1], most};
}

}  // namespace pb
