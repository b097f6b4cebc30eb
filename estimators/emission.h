// Photon emission from an area light (Shirley et al. 1995, "Global Illumination via Density Estimation": each
// light emits according to its own characteristic). The position is uniform over the light's area
// (pdf 1/A per unit area [1/m^2]) and the direction is cosine-distributed about the front normal
// (pdf cos(theta)/pi [1/sr]). With N photons the light's flux Phi = pi Ke A [W] splits into N equal parts:
// Ke cos / (N pdfArea pdfDirection) = Phi / N.
#pragma once

#include <cstdint>
#include <vector>

#include "estimators/rng.h"
#include "mesh/lights.h"
#include "mesh/scene.h"

namespace pb {

struct EmissionSample {
  Point3 position;     // on the light [m]
  Normal3 normal;      // the light's front normal there
  Vector3 direction;   // unit, world, into the front hemisphere
  uint32_t triangle = 0;
  float pdfArea = 0;       // [1/m^2]
  float pdfDirection = 0;  // [1/sr]
};

EmissionSample SampleEmission(const Scene& scene, const AreaLight& light, Rng& rng);

// Photons per light, N_i = floor(n Phi_i / Phi) (Shirley et al. 1995), with Phi the mean over RGB channels.
// Rounded down, so the counts sum to n minus less than one per light, and never shrink as n grows: a bake given
// more photons adds to every light's stream (largest-remainder rounding would move a photon from one light to
// another as n grows, the Alabama paradox). A light with eligible[i] false (it reaches no receiver) gets none
// and is left out of Phi; empty `eligible` means all.
std::vector<uint64_t> AllocatePhotons(const std::vector<AreaLight>& lights, uint64_t n,
                                      const std::vector<bool>& eligible = {});

}  // namespace pb
