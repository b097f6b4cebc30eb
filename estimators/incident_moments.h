// Where the light at a surface point comes from: the first two moments of the radiance L(w) arriving there, per
// colour channel, over the sphere of directions w (unit vectors pointing back toward where the light came from):
//   F = integral L(w) dw     the scalar irradiance [W/m^2]
//   D = integral L(w) w dw   the irradiance vector [W/m^2] (Arvo 1995, "Applications of irradiance tensors to the
//                            simulation of non-Lambertian phenomena", SIGGRAPH; Gershun's light vector)
// A surface of normal n whose hemisphere holds all the light receives E(n) = D . n; so does the point's own
// surface, whose back the light cannot reach. Their real spherical harmonics of bands 0 and 1 (basis Y_00 =
// 1 / (2 sqrt(pi)), Y_1m = sqrt(3 / (4 pi)) w_m, m = x, y, z) are the radiance's L1 SH:
//   L_00 = F / (2 sqrt(pi)),   L_1m = sqrt(3 / (4 pi)) D_m   [W/(m^2 sr)],
// and E(n) = sqrt(4 pi / 3) (L_1x n_x + L_1y n_y + L_1z n_z) (ShIrradiance). The Ramamoorthi-Hanrahan evaluation of
// the same coefficients, pi L_00 Y_00 + 2 pi / 3 L_1 . Y_1(n) = F / 4 + D . n / 2, is exact only for light spread
// evenly over the hemisphere and reads light from one direction 3/4 of its irradiance; engines that use it get that.
//
// Estimated from samples of irradiance e = L cos / pdf arriving along w, cos = w . n: e / cos is a sample of F and
// e w / cos of D. Near grazing 1 / cos grows without bound, and with it the variance of estimates whose samples
// come cosine-distributed (photons, gathered paths: log-divergent), so cos is floored at kGrazingCosine: light
// within 1.1 degrees of the surface's plane counts as if at that angle, which reads an evenly lit hemisphere's F 1%
// low. D's normal component is exact in expectation either way; the bake sets it to the point's irradiance H, so
// that E at the vertex normal is H itself (ShProjection).
//
// The noise of D's direction (all that the SH add to H) is predicted as H's is. Each sample (a photon, a shadow
// ray, a gathered path) adds a vector x v to D's luminance, x its luminance (lum(phi) or lum(e), times its weight
// in the estimate) and v = w / c (c floored as above), whose part along the normal is 1: D's normal part is H's own
// sum, as ShProjection sets it. D's covariance M is then predicted as H's variance is, and the direction's variance
// is what M puts across D: (tr M - d^T M d) / |D|^2, d = D / |D| (DirectionNoise, radians); photons whose
// directions agree move |D|, not its direction. For photons (a Poisson process), M = sum x^2 v v^T, from the
// estimator's own noise of the photons weighted phi |a . v| along six axes a (MomentFluxes' last six):
// (noise x estimate)^2 = sum x^2 (a . v)^2 = a^T M a. For stratified shadow rays, from the differences of paired
// strata, as for H (StratifiedMean; the plain sum of squares predicted 13x the error of 64 of them on the closed
// form); for independent paths, their sample covariance (SampleMean).
#pragma once

#include <array>
#include <cmath>

#include "mesh/color.h"
#include "mesh/geometry.h"

namespace pb {

// The floor of cos in e / cos (see the top): cos(88.9 degrees).
inline constexpr float kGrazingCosine = 0.02f;

// A symmetric 3 x 3 matrix: xx, yy, zz, xy, yz, xz.
struct Symmetric3 {
  std::array<double, 6> m{};
  void AddOuter(Vector3 v, double scale) {
    const double x = v.x, y = v.y, z = v.z;
    m[0] += scale * x * x, m[1] += scale * y * y, m[2] += scale * z * z;
    m[3] += scale * x * y, m[4] += scale * y * z, m[5] += scale * x * z;
  }
  void Add(const Symmetric3& o, double scale) {
    for (size_t k = 0; k < 6; ++k) m[k] += scale * o.m[k];
  }
  double Trace() const { return m[0] + m[1] + m[2]; }
  double Quadratic(const std::array<double, 3>& d) const {  // d^T M d
    return m[0] * d[0] * d[0] + m[1] * d[1] * d[1] + m[2] * d[2] * d[2] +
           2 * (m[3] * d[0] * d[1] + m[4] * d[1] * d[2] + m[5] * d[0] * d[2]);
  }
};

// The six axes a whose quadratic forms a^T M a give M (MomentFluxes, PhotonCovariance): x, y, z, then (x + y),
// (y + z) and (x + z) over sqrt 2.
inline const std::array<Vector3, 6>& CovarianceAxes() {
  static const float r = 0.70710678f;
  static const std::array<Vector3, 6> axes = {
      {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {r, r, 0}, {0, r, r}, {r, 0, r}}};
  return axes;
}

// M from its quadratic forms q_k = a_k^T M a_k along CovarianceAxes: q_xy = (M_xx + M_yy) / 2 + M_xy, and so on.
inline Symmetric3 FromQuadraticForms(const std::array<double, 6>& q) {
  Symmetric3 s;
  s.m = {q[0], q[1], q[2], q[3] - (q[0] + q[1]) / 2, q[4] - (q[1] + q[2]) / 2, q[5] - (q[0] + q[2]) / 2};
  return s;
}

// Sample e's vector x v (see the top): lum(e) w / c.
inline Vector3 MomentVector(Rgb e, Vector3 w, float cosine) {
  return w * (Luminance(e) / std::max(cosine, kGrazingCosine));
}

struct IncidentMoments {
  Rgb scalar;                 // F [W/m^2]
  std::array<Rgb, 3> vector;  // D along world x, y, z [W/m^2]
  Symmetric3 covariance;      // of D's luminance [(W/m^2)^2]

  // Adds `weight` times the moments of irradiance sample e arriving from unit direction w, at cosine `cosine` to
  // the surface's normal (its noise is the caller's to add to `covariance`).
  void Add(Rgb e, Vector3 w, float cosine, float weight = 1) {
    const Rgb f = e * (weight / std::max(cosine, kGrazingCosine));
    scalar += f;
    vector[0] += f * w.x, vector[1] += f * w.y, vector[2] += f * w.z;
  }
  void Add(const IncidentMoments& m, float weight = 1) {
    scalar += m.scalar * weight;
    for (int k = 0; k < 3; ++k) vector[k] += m.vector[k] * weight;
    covariance.Add(m.covariance, double(weight) * weight);
  }
  Vector3 LuminanceVector() const {
    return {Luminance(vector[0]), Luminance(vector[1]), Luminance(vector[2])};
  }
  // D . n per channel [W/m^2].
  Rgb Along(Normal3 n) const { return vector[0] * n.x + vector[1] * n.y + vector[2] * n.z; }
};

// The photon estimate's weighted fluxes (baker/3_contributions.h, PhotonIrradiance) of a photon of `flux` [W]
// arriving from unit direction w at `cosine` to its surface's normal: phi / c, then phi (1 + w_m) / c for m = x, y,
// z, with c = max(cosine, kGrazingCosine); each >= 0, so that no estimator sees a negative flux.
// The last six, phi |a . w| / c along CovarianceAxes, carry D's covariance in their estimators' noise.
inline constexpr int kMomentFluxes = 10;
inline std::array<Rgb, kMomentFluxes> MomentFluxes(Rgb flux, Vector3 w, float cosine) {
  const Rgb f = flux * (1 / std::max(cosine, kGrazingCosine));
  std::array<Rgb, kMomentFluxes> out = {f, f * (1 + w.x), f * (1 + w.y), f * (1 + w.z)};
  for (size_t k = 0; k < 6; ++k) out[4 + k] = f * std::fabs(Dot(CovarianceAxes()[k], w));
  return out;
}

// The L1 SH of the radiance per channel: c[0] = L_00, c[1..3] = L_1x, L_1y, L_1z [W/(m^2 sr)].
struct ShL1 {
  std::array<Rgb, 4> c;
};

inline constexpr float kShY00 = 0.28209479177387814f;  // 1 / (2 sqrt(pi))
inline constexpr float kShY1 = 0.48860251190291992f;   // sqrt(3 / (4 pi))

// The SH of moments m at a point of normal n and irradiance H: D's component along n replaced by H (the same in
// expectation, with H's noise and H's estimate, so that ShIrradiance(sh, n) = H).
inline ShL1 ShProjection(const IncidentMoments& m, Normal3 n, Rgb irradiance) {
  const Rgb correction = irradiance - m.Along(n);
  const std::array<float, 3> axis = {n.x, n.y, n.z};
  ShL1 sh;
  sh.c[0] = m.scalar * kShY00;
  for (int k = 0; k < 3; ++k) sh.c[k + 1] = (m.vector[k] + correction * axis[k]) * kShY1;
  return sh;
}

// The standard error of the direction of D (luminance) at a point of normal n and irradiance H [rad]:
// sqrt(tr M - d^T M d) / |D|, with D's part along n set to H as ShProjection sets it; 0 where D is 0.
inline double DirectionNoise(const IncidentMoments& m, Normal3 n, Rgb irradiance) {
  const double correction = double(Luminance(irradiance)) - Luminance(m.Along(n));
  const std::array<double, 3> axis = {n.x, n.y, n.z};
  std::array<double, 3> d;
  for (size_t k = 0; k < 3; ++k) d[k] = Luminance(m.vector[k]) + correction * axis[k];
  const double size = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(size > 0)) return 0.0;
  for (double& x : d) x /= size;
  return std::sqrt(std::max(0.0, m.covariance.Trace() - m.covariance.Quadratic(d))) / size;
}

// E(n) = D . n = sqrt(4 pi / 3) L_1 . n [W/m^2], per channel, floored at 0 (a normal turned from the light).
inline Rgb ShIrradiance(const ShL1& sh, Normal3 n) {
  const Rgb e = (sh.c[1] * n.x + sh.c[2] * n.y + sh.c[3] * n.z) * (1 / kShY1);
  return {std::max(e.r, 0.0f), std::max(e.g, 0.0f), std::max(e.b, 0.0f)};
}

}  // namespace pb
