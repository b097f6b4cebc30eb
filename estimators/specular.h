// Ideal specular scattering: mirror reflection and refraction at a smooth dielectric interface.
// Fresnel equations for unpolarised light (Born & Wolf, "Principles of Optics", section 1.5.2): the reflected
// fraction of flux F(cos theta_i, eta), dimensionless, with eta = n_t / n_i the ratio of the refractive index on
// the transmitted side to the incident side. Snell's law sin theta_t = sin theta_i / eta; total internal
// reflection (F = 1) when that exceeds 1. Directions are unit vectors pointing away from the surface; `n` is the
// surface normal on the side of wo.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "mesh/geometry.h"

namespace pb {

// The mirror image of wo about n: the ideal reflection direction.
inline Vector3 Reflect(Vector3 wo, Normal3 n) { return AsVector(n) * (2.0f * Dot(wo, n)) - wo; }

// Cosine of the refraction angle for incident cosine cosI in [0, 1], or nothing under total internal reflection.
inline std::optional<float> RefractedCosine(float cosI, float eta) {
  const float sin2T = std::max(0.0f, 1.0f - cosI * cosI) / (eta * eta);
  if (sin2T >= 1.0f) return std::nullopt;
  return std::sqrt(1.0f - sin2T);
}

// Reflectance of a smooth dielectric interface for unpolarised light; 1 under total internal reflection.
inline float FresnelDielectric(float cosI, float eta) {
  cosI = std::clamp(cosI, 0.0f, 1.0f);
  const std::optional<float> cosT = RefractedCosine(cosI, eta);
  if (!cosT) return 1.0f;
  const float rs = (cosI - eta * *cosT) / (cosI + eta * *cosT);  // s-polarised amplitude ratio
  const float rp = (eta * cosI - *cosT) / (eta * cosI + *cosT);  // p-polarised amplitude ratio
  return 0.5f * (rs * rs + rp * rp);
}

// The refracted direction (on the side opposite n) of wo, given the refracted cosine from RefractedCosine.
inline Vector3 Refract(Vector3 wo, Normal3 n, float eta, float cosT) {
  const float cosI = Dot(wo, n);
  return wo * (-1.0f / eta) + AsVector(n) * (cosI / eta - cosT);
}

}  // namespace pb
