// What a BSDF sampler returns, and which quantity a path carries through it.
// Directions wi and wo both point away from the surface (DESIGN.md). A sample's weight is f cos(theta) / pdf:
// the factor by which the carried flux (photons) or throughput (camera paths) is multiplied, dimensionless.
#pragma once

#include "mesh/color.h"
#include "mesh/geometry.h"

namespace pb {

struct BsdfSample {
  Vector3 wi;          // unit, world
  Rgb weight;          // f cos(theta) / pdf, dimensionless
  float pdf = 0;       // [1/sr]; 0 for delta lobes
  bool delta = false;  // true for ideal specular lobes (mirror reflection, smooth refraction)
};

// Which way a path runs. Refraction is not symmetric (Veach 1997, "Robust Monte Carlo Methods for Light
// Transport Simulation", section 5.2): radiance crossing from index n_i into n_t is scaled by (n_t/n_i)^2,
// flux (importance, photons) is not. Photon tracing carries flux: kImportance. Camera paths carry radiance
// backwards: kRadiance, whose refraction weight is divided by (n_t/n_i)^2 with n_t on the wi side.
enum class TransportMode : uint8_t { kImportance, kRadiance };

}  // namespace pb
