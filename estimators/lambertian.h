// The Lambertian BRDF f = R / pi [1/sr] for diffuse reflectance R, and sampling of its cosine lobe:
// wi is drawn with pdf cos(theta)/pi [1/sr], so the path weight f cos / pdf equals R.
// Directions wi and wo both point away from the surface (DESIGN.md).
#pragma once

#include "estimators/bsdf.h"
#include "estimators/warps.h"

namespace pb {

inline Rgb LambertianBrdf(Rgb albedo) { return albedo * kInvPi; }

// `side` is the normal of the side the light leaves from (the side the incoming photon or ray came from).
inline BsdfSample SampleLambertian(Rgb albedo, Normal3 side, Point2 u) {
  const DirectionSample d = SampleCosineHemisphere(u);
  return {Frame::FromNormal(side).ToWorld(d.direction), albedo, d.pdf, false};
}

}  // namespace pb
