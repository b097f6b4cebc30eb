// How a sky image's light (mesh/sky_image.h) divides among its texels, for the CDFs its photons are drawn by
// (estimators/sky_sampling.h) and for its flux (Light::Power, mesh/lights.h):
//   from the bounding discs, texel t carries L_t Omega_t per unit disc area [W/m^2], Omega_t its solid angle above
//   the horizon (all of it, for the whole sphere);
//   through a portal of inward normal n and area A, it carries A L_t C_t [W], where C_t = integral over the texel of
//   max(0, n . (-w)) dw [sr] is the cosine-weighted solid angle through which it shines in: in closed form where
//   the cosine keeps its sign over the texel, over 8 x 8 parts of it (each in closed form, clipped) where it does
//   not.
// The luminance of those shares makes the texel CDFs (one per portal), and of the portals' totals the portal CDF;
// their RGB sums are the light's flux.
#pragma once

#include "mesh/lights.h"

namespace pb {

// Fills the light's texelCdf, skyIntegral and skyLuminanceIntegral, and with portals also portalCdf,
// portalTexelCdf, portalTexelSum, portalFlux and portalLuminanceFlux. The light is a sky with an image.
void WeighSkyTexels(Light& light);

// C_t of texel (x, y) for light travelling through a portal of inward normal `inward` [sr].
double TexelCosineSolidAngle(const AnalyticLight& sky, int x, int y, Normal3 inward);

// The texel's extent: polar angle [theta0, theta1] above the horizon (theta1 = theta0 where none is), azimuth
// [phi0, phi1] [rad].
struct TexelSpan {
  double theta0, theta1, phi0, phi1;
  double SolidAngle() const { return (phi1 - phi0) * (std::cos(theta0) - std::cos(theta1)); }
};
TexelSpan SpanOf(const AnalyticLight& sky, int x, int y);

}  // namespace pb
