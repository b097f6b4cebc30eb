// Directions toward a sky with an image (mesh/sky_image.h, mesh/lights.h) in proportion to its luminance: a
// texel by its share of sum L_lum Omega (Light::texelCdf), then a direction uniform over the texel's solid angle
// (above the horizon, for a sky that is not the whole sphere), so that the pdf is L_lum(w) / sum L_lum Omega
// [1/sr] exactly: the image is constant over each texel. Photons drawn so carry, per channel, the weight
// (L_c / L_lum)(w) (sum L_lum Omega / sum L_c Omega), whose mean is 1: the light's flux per channel is kept.
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

}  // namespace pb
