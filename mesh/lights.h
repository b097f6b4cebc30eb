// The scene's lights as plain data, each with the flux Phi [W] that its photons share.
//   area: one emissive surface, radiance Ke [W/(m^2 sr)] leaving its front side with a cosine distribution, area
//         A [m^2]: Phi = pi Ke A. The triangle CDF (by area) lets estimators/emission.h pick a point uniformly over
//         it (pdf 1/A per unit area).
//   point: Phi = 4 pi I; with a goniometric profile (an IES file), I [W/sr per cd] times the profile's flux [lm].
//   spot: Phi = I 2 pi [(1 - cos inner) + (cos inner - cos outer) / 3], the integral of glTF's falloff
//         (mesh/scene.h) over the sphere.
//   sun: its photons leave a disc of radius R (the radius of the scene's bounding sphere) facing along its
//        direction, outside the scene: Phi = E pi R^2.
//   sky: its photons leave such discs, one per direction, for directions uniform over the sky's solid angle Omega
//        (2 pi above the horizon, or 4 pi): Phi = L pi R^2 Omega. A surface open to the sky receives H = pi L
//        (upper hemisphere, facing up), whatever R. With an image (mesh/sky_image.h): Phi = pi R^2 sum over its
//        texels (above the horizon) of L Omega_texel, or through portals sum over them of A_p sum L C_p
//        (mesh/sky_texels.h); the texels' shares of that luminous flux are the CDFs its photons pick a texel by.
// With portals (mesh/scene.h), sun and sky photons start on the portals instead, so that none is spent on the
// outside of a closed room: a portal is picked in proportion to its share of the flux, a point uniformly on it;
//   sun: Phi = E sum_p A_p max(0, d . n_p);
//   sky: Phi = L pi sum_p A_p, directions cosine-distributed about the portal's inward normal; a photon whose
//        direction comes from below the sky's horizon carries no light and ends at once (counted as escaped).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/color.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

inline constexpr uint32_t kNoSurface = ~0u;

struct Light {
  LightKind kind = LightKind::kArea;
  uint32_t surface = kNoSurface;    // area: its surface
  Rgb radiance;                     // area: Ke [W/(m^2 sr)]
  std::vector<uint32_t> triangles;  // area: Scene::triangles indices
  std::vector<double> triangleCdf;  // area: cumulative area fraction; back() == 1
  double area = 0;                  // area: [m^2]
  AnalyticLight analytic;           // the other kinds
  Point3 boundsCentre;              // sun, sky: the scene's bounding sphere, local [m]
  float boundsRadius = 0;
  std::vector<Portal> portals;      // sun, sky: the scene's portals; empty: photons leave the bounding discs
  std::vector<double> portalCdf;    // sun, sky with portals: cumulative share of the flux by portal; back() == 1
  // sky with an image (mesh/sky_texels.h): the cumulative share of sum L_lum Omega by texel (back() == 1), and the
  // sums of L Omega [W/m^2] and of its luminance; through portals also, per portal, the cumulative share of sum
  // L_lum C by texel and that sum, and over the portals sum A sum L C [W] and its luminance.
  std::vector<double> texelCdf;
  Rgb skyIntegral;
  double skyLuminanceIntegral = 0;
  std::vector<std::vector<double>> portalTexelCdf;
  std::vector<double> portalTexelSum;
  Rgb portalFlux;
  double portalLuminanceFlux = 0;
  Rgb Power() const;  // Phi [W]
  bool IsArea() const { return kind == LightKind::kArea; }
};

// The integral of the spot's falloff over the sphere [sr]: Phi = I times it.
double SpotSolidAngle(float cosInner, float cosOuter);
// The spot's falloff at cos t from its axis, in [0, 1].
float SpotFalloff(const AnalyticLight& spot, float cosAngle);

// The frame of a point light's profile: s is its horizontal angle 0 (c0), t = s x n its horizontal angle 90
// degrees (counter-clockwise seen from above), n its nadir (direction). Type C photometry, as LM-63 measures.
Frame ProfileFrame(const AnalyticLight& light);
// The factor by which a point or spot light's intensity is multiplied toward the unit direction w leaving it: the
// spot's falloff, a profile's I [cd], or 1.
float RelativeIntensity(const AnalyticLight& light, Vector3 w);

// The frame of a sky with an image: s its front (c0), t = s x n to its right, n its up.
Frame SkyFrame(const AnalyticLight& sky);
// The radiance [W/(m^2 sr)] of a sky arriving from the unit direction `from` (toward the sky): 0 below its
// horizon unless it is the whole sphere; its image's texel times its intensity, or its intensity.
Rgb SkyRadianceFrom(const AnalyticLight& sky, Vector3 from);
// The direction toward the sky at polar angle theta from up and azimuth phi from the image's left edge [rad].
Vector3 SkyDirection(const Frame& frame, double theta, double phi);

// "point", "spot", "sun", "sky" or "area".
const char* LightKindName(LightKind kind);

// The light's name for messages and reports: its material's for an area light, its own (or its kind) otherwise.
std::string LightName(const Scene& scene, const Light& light);

// One light per surface whose material has Ke > 0, in surface order; then the scene's analytic lights, in order,
// sun and sky given the scene's bounding sphere.
std::vector<Light> CollectLights(const Scene& scene, const SurfaceSet& surfaces);

}  // namespace pb
