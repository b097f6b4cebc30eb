// Directions toward a sky with an image (mesh/sky_image.h, mesh/lights.h) in proportion to its luminance: a
// texel by its share of sum L_lum Omega (Light::texelCdf), then a direction uniform over the texel's solid angle
// (above the horizon, for a sky that is not the whole sphere), so that the pdf is L_lum(w) / sum L_lum Omega
// [1/sr] exactly: the image is constant over each texel. Photons drawn so carry, per channel, the weight
// (L_c / L_lum)(w) (sum L_lum Omega / sum L_c Omega), whose mean is 1: the light's flux per channel is kept.
// Through a portal the texel is drawn by L_lum C_t instead (its light through the portal), and the weight
// follows (below).
#pragma once

#include <optional>

#include "mesh/geometry.h"
#include "mesh/lights.h"

namespace pb {

struct SkySample {
  Vector3 from;   // unit, world: toward the sky, the opposite of the way its light travels
  float pdf = 0;  // [1/sr]
};

// Empty when the image is black (above the horizon).
std::optional<SkySample> SampleSkyImage(const Light& sky, Point2 u);
float SkyImagePdf(const Light& sky, Vector3 from);
// A photon's weight per channel for the radiance L it leaves with (SkyRadianceFrom).
Rgb SkyPhotonWeight(const Light& sky, Rgb radiance);
// Toward the light's portals from the point p: a portal by its share of the light (Light::portalCdf), a point
// uniform on it; the direction and its pdf [1/sr] = P(portal) d^2 / (A cos) (estimators/warps.h's change of
// measure). Empty when the chosen point lies behind p's side of the portal (the direction would not go out).
std::optional<SkySample> SampleTowardPortals(const Light& sky, Point3 p, Point2 u);
// The pdf [1/sr] of SampleTowardPortals for the direction w from p: the sum over the portals a ray along w meets.
float TowardPortalsPdf(const Light& sky, Point3 p, Vector3 w);

// Through portal `portal` (of the light's): `from`, drawn by the portal's texel CDF (mesh/sky_texels.h) and uniform
// over the texel's solid angle, and the photon's weight per channel, L cos Omega / (pmf Z_p) over the channel's
// flux per unit of luminous flux (0 where the direction, in a texel the portal's plane cuts, does not come in).
// Empty when no texel shines in.
std::optional<Rgb> SampleSkyThroughPortal(const Light& sky, uint32_t portal, Point2 u, Vector3& from);

}  // namespace pb
