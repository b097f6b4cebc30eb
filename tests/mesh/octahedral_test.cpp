// The octahedral direction code must round-trip every unit vector within its stated 8e-5 rad, including the
// axes, the folded lower hemisphere and the fold's seams.
#include "mesh/octahedral.h"

#include <gtest/gtest.h>

#include "estimators/rng.h"
#include "estimators/warps.h"

namespace pb {
namespace {

double AngleBetween(Vector3 a, Vector3 b) { return std::atan2(double(Length(Cross(a, b))), double(Dot(a, b))); }

TEST(Octahedral, RoundTripsRandomDirectionsWithinTheStatedError) {
  double worst = 0;
  for (uint64_t i = 0; i < 200000; ++i) {
    Rng rng(3, i);
    const Point2 u = rng.Uniform2();
    const float z = 1 - 2 * u.u, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * u.v;
    const Vector3 d{r * std::cos(phi), r * std::sin(phi), z};
    worst = std::max(worst, AngleBetween(d, DecodeOctahedral(EncodeOctahedral(d))));
  }
  EXPECT_LT(worst, 8e-5);
  RecordProperty("worst_error_rad", std::to_string(worst));
}

TEST(Octahedral, AxesAndSeamsAreExactOrClose) {
  const Vector3 cases[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1},
                           Normalize({1, 1, -1e-7f}), Normalize({-1, 1, -1}), Normalize({1e-8f, -1, -1})};
  for (const Vector3& d : cases) EXPECT_LT(AngleBetween(d, DecodeOctahedral(EncodeOctahedral(d))), 8e-5);
}

}  // namespace
}  // namespace pb
