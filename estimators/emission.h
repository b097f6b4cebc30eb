// Photon emission (Shirley et al. 1995, "Global Illumination via Density Estimation": each light emits according
// to its own characteristic), in proportion to each light's emission, so that with N photons its flux Phi
// (mesh/lights.h) splits into N equal parts:
//   area:  position uniform over the light's area (pdf 1/A per unit area [1/m^2]), direction cosine-distributed
//          about the front normal (pdf cos(theta)/pi [1/sr]): Ke cos / (N pdfArea pdfDirection) = Phi / N;
//   point: from its position, direction uniform over the sphere; with a profile (mesh/intensity_profile.h), in
//          proportion to its intensity: a cell of the profile's table by its share of the flux, then directions
//          uniform over the cell's solid angle until one is kept, with probability I / (the cell's largest corner),
//          so that the pdf is I / flux [1/sr] (rejection sampling; a cell keeps at least 1/6 of its proposals, so
//          that kProfileTries of them all fail with probability below 1e-20, when the last is kept);
//   spot:  from its position, direction in proportion to its falloff (estimators/warps.h, SampleSpotCone);
//   sun:   direction its own, position uniform on the disc of the bounding sphere's radius R facing along it, R
//          behind the sphere's centre (pdf 1/(pi R^2));
//   sky:   direction uniform over the sky's solid angle (toward the scene, from above its horizon or from
//          anywhere), then a position on such a disc for it; with an image, the direction by its luminance
//          (estimators/sky_sampling.h), the photon weighted by its colour;
//   sun and sky with portals (mesh/lights.h): a portal by its share, a point uniform on it (pdf 1/A_p), and the
//          sun's direction, or for the sky a direction cosine-distributed about the inward normal.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "estimators/rng.h"
#include "estimators/warps.h"
#include "mesh/lights.h"
#include "mesh/scene.h"

namespace pb {

struct EmissionSample {
  Point3 position;     // on the light [m]
  Normal3 normal;      // the light's front normal there (area lights; else the direction)
  bool onSurface = true;  // an area light's point, which a ray leaves by an offset along `normal`
  Vector3 direction;   // unit, world, into the front hemisphere
  uint32_t triangle = 0;
  float pdfArea = 0;       // [1/m^2]; area lights, sun and sky
  float pdfDirection = 0;  // [1/sr]; area, point, spot and sky lights
  bool carriesLight = true;  // false for a portal's sky photon from below the horizon: it ends at once
  Rgb weight{1, 1, 1};       // the share of Phi / N it carries per channel: 1 but for a sky image's photons
};

// A direction in the profile's frame (mesh/lights.h, ProfileFrame), z the nadir, and its pdf [1/sr]. Empty when
// the profile's flux is 0.
inline constexpr int kProfileTries = 256;
std::optional<DirectionSample> SampleProfile(const IntensityProfile& profile, Rng& rng);

EmissionSample SampleEmission(const Scene& scene, const Light& light, Rng& rng);

// Photons per light, N_i = floor(n Phi_i / Phi) (Shirley et al. 1995), with Phi the mean over RGB channels.
// Rounded down, so the counts sum to n minus less than one per light, and never shrink as n grows: a bake given
// more photons adds to every light's stream (largest-remainder rounding would move a photon from one light to
// another as n grows, the Alabama paradox). A light with eligible[i] false (it reaches no receiver) gets none
// and is left out of Phi; empty `eligible` means all.
std::vector<uint64_t> AllocatePhotons(const std::vector<Light>& lights, uint64_t n,
                                      const std::vector<bool>& eligible = {});

}  // namespace pb
