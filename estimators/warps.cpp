#include "estimators/warps.h"

#include <algorithm>

namespace pb {

Point2 SampleUniformDiskConcentric(Point2 u) {
  const float a = 2.0f * u.u - 1.0f, b = 2.0f * u.v - 1.0f;
  if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
  float r, phi;
  if (std::fabs(a) > std::fabs(b)) {
    r = a;
    phi = (kPi / 4.0f) * (b / a);
  } else {
    r = b;
    phi = (kPi / 2.0f) - (kPi / 4.0f) * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

Point2 InvertUniformDiskConcentric(Point2 p) {
  const float r = std::sqrt(p.u * p.u + p.v * p.v);
  if (r == 0.0f) return {0.5f, 0.5f};
  float phi = std::atan2(p.v, p.u);  // (-pi, pi]
  if (phi < -kPi / 4.0f) phi += 2.0f * kPi;  // [-pi/4, 7pi/4)
  float a, b;
  if (phi < kPi / 4.0f) {  // right wedge: r = a
    a = r;
    b = phi * a / (kPi / 4.0f);
  } else if (phi < 3.0f * kPi / 4.0f) {  // top wedge: r = b
    b = r;
    a = -(phi - kPi / 2.0f) * b / (kPi / 4.0f);
  } else if (phi < 5.0f * kPi / 4.0f) {  // left wedge: r = -a
    a = -r;
    b = (phi - kPi) * a / (kPi / 4.0f);
  } else {  // bottom wedge: r = -b
    b = -r;
    a = -(phi - 3.0f * kPi / 2.0f) * b / (kPi / 4.0f);
  }
  return {std::clamp((a + 1.0f) * 0.5f, 0.0f, 1.0f), std::clamp((b + 1.0f) * 0.5f, 0.0f, 1.0f)};
}

DirectionSample SampleCosineHemisphere(Point2 u) {
  const Point2 d = SampleUniformDiskConcentric(u);
  const float z = std::sqrt(std::max(0.0f, 1.0f - d.u * d.u - d.v * d.v));
  return {{d.u, d.v, z}, CosineHemispherePdf(z)};
}

Point2 InvertCosineHemisphere(Vector3 w) { return InvertUniformDiskConcentric({w.x, w.y}); }

namespace {
// The direction at height z and azimuth 2 pi v.
Vector3 AtHeight(float z, float v) {
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * float(kPi) * v;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace

DirectionSample SampleUniformSphere(Point2 u) { return {AtHeight(1.0f - 2.0f * u.u, u.v), float(0.25 * kInvPi)}; }

DirectionSample SampleUniformHemisphere(Point2 u) { return {AtHeight(1.0f - u.u, u.v), float(0.5 * kInvPi)}; }

DirectionSample SampleSpotCone(Point2 u, float cosInner, float cosOuter) {
  const double ci = cosInner, co = cosOuter;
  const double cap = 1 - ci, ramp = (ci - co) / 3, total = cap + ramp;
  const double pick = double(u.u) * total;
  float z;
  if (pick < cap || ramp <= 0) {
    z = float(1 - (cap > 0 ? pick : 0));  // uniform on [ci, 1]
  } else {
    z = float(co + (ci - co) * std::cbrt((pick - cap) / ramp));
  }
  const double t = ci > co ? std::clamp((double(z) - co) / (ci - co), 0.0, 1.0) : 1.0;
  const double falloff = z >= cosInner ? 1.0 : t * t;
  return {AtHeight(z, u.v), float(falloff / (2 * kPi * total))};
}

Barycentrics SampleUniformTriangle(Point2 u) {
  const float s = std::sqrt(u.u);
  return {s * (1.0f - u.v), s * u.v};
}

Point2 InvertUniformTriangle(Barycentrics b) {
  const float s = b.b1 + b.b2;
  return {s * s, s > 0 ? b.b2 / s : 0.0f};
}

namespace {

using D3 = std::array<double, 3>;
D3 Of(Vector3 v) { return {v.x, v.y, v.z}; }
D3 Minus(D3 a, D3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
D3 Plus(D3 a, D3 b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
D3 Times(D3 a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double DotD(D3 a, D3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
D3 CrossD(D3 a, D3 b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double NormD(D3 a) { return std::sqrt(DotD(a, a)); }
D3 UnitD(D3 a) {
  const double n = NormD(a);
  return n > 0 ? Times(a, 1 / n) : D3{0, 0, 0};
}
// The unit component of `to` orthogonal to the unit `from`: the direction in which the arc from `from` leaves it.
D3 Tangent(D3 from, D3 to) { return UnitD(Minus(to, Times(from, DotD(to, from)))); }

}  // namespace

std::optional<SphericalTriangle> SphericalTriangle::From(Point3 p, Point3 v0, Point3 v1, Point3 v2) {
  const D3 a = UnitD(Of(v0 - p)), b = UnitD(Of(v1 - p)), c = UnitD(Of(v2 - p));
  const double triple = std::fabs(DotD(a, CrossD(b, c)));
  const double area = 2 * std::atan2(triple, 1 + DotD(a, b) + DotD(b, c) + DotD(c, a));
  if (!(area > 1e-9)) return std::nullopt;
  SphericalTriangle t;
  t.a_ = a, t.b_ = b, t.towardC_ = Tangent(a, c);
  t.area_ = area;
  t.alpha_ = std::acos(std::clamp(DotD(Tangent(a, b), t.towardC_), -1.0, 1.0));  // between the arcs to b and to c
  t.cosAlpha_ = std::cos(t.alpha_), t.sinAlpha_ = std::sin(t.alpha_), t.cosC_ = DotD(a, b);
  if (!(t.sinAlpha_ > 0)) return std::nullopt;
  return t;
}

Vector3 SphericalTriangle::Sample(Point2 u) const {
  const D3& a = a_;
  const D3& b = b_;
  // The sub-triangle (a, b, c') of area u.u * Omega: c' on the arc from a to c, by Arvo's closed form.
  const double s = std::sin(double(u.u) * area_ - alpha_), t = std::cos(double(u.u) * area_ - alpha_);
  const double du = t - cosAlpha_, dv = s + sinAlpha_ * cosC_;
  const double q = std::clamp(((dv * t - du * s) * cosAlpha_ - dv) / ((dv * s + du * t) * sinAlpha_), -1.0, 1.0);
  const D3 cPrime = Plus(Times(a, q), Times(towardC_, std::sqrt(std::max(0.0, 1 - q * q))));
  // Then a point on the arc from b to c', uniform in the area it sweeps: its cosine to b is linear in u.v.
  const double z = 1 - double(u.v) * (1 - DotD(cPrime, b));
  const D3 w = UnitD(Plus(Times(b, z), Times(Tangent(b, cPrime), std::sqrt(std::max(0.0, 1 - z * z)))));
  return {float(w[0]), float(w[1]), float(w[2])};
}

std::optional<DiscreteSample> SampleDiscreteCdf(std::span<const double> cdf, float u) {
  if (cdf.empty()) return std::nullopt;
  // The first entry above u (std::upper_bound's answer), by a binary search without branches: the light and
  // triangle choices of every shadow ray run through here, and the branches' mispredictions were a tenth of a
  // sampled bake's time.
  const double x = double(u);
  size_t first = 0;
  for (size_t n = cdf.size(); n > 1;) {
    const size_t half = n / 2;
    first = cdf[first + half - 1] <= x ? first + half : first;
    n -= half;
  }
  first += cdf[first] <= x ? 1 : 0;
  const auto index = uint32_t(std::min(first, cdf.size() - 1));
  const double lo = index == 0 ? 0.0 : cdf[index - 1];
  const double pmf = cdf[index] - lo;
  const float remapped = pmf > 0 ? float((double(u) - lo) / pmf) : 0.0f;
  return DiscreteSample{index, pmf, std::clamp(remapped, 0.0f, 0x1.fffffep-1f)};  // the float below 1
}

Vector3 CosineSpiralDirection(int k, int n) {
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  const double u = (k + 0.5) / n, r = std::sqrt(u), phi = k * golden;
  return {float(r * std::cos(phi)), float(r * std::sin(phi)), float(std::sqrt(1.0 - u))};
}

}  // namespace pb
