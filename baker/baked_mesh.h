// The bake's result: the split display mesh with, per vertex, irradiance H [W/m^2], diffuse reflectance R
// (Kd, dimensionless) and emitted radiance Le [W/(m^2 sr)]. H and R are stored apart, as the paper advises;
// the outgoing radiance is derived: L = Le + R H / pi [W/(m^2 sr)].
#pragma once

#include <vector>

#include "baker/3_gap_weights.h"
#include "estimators/incident_moments.h"
#include "mesh/color.h"
#include "mesh/split_mesh.h"

namespace pb {

// L = Le + R H / pi [W/(m^2 sr)].
inline Rgb OutgoingRadiance(Rgb emitted, Rgb albedo, Rgb irradiance) { return emitted + albedo * irradiance * kInvPi; }

struct BakedMesh {
  SplitMesh mesh;
  std::vector<Rgb> irradiance;  // H [W/m^2]
  std::vector<Rgb> albedo;      // R
  std::vector<Rgb> emitted;     // Le [W/(m^2 sr)], non-zero on lights' front sides
  std::vector<double> irradianceNoise;  // sigma_H / H per vertex, when asked for (withNoise); else empty
  // The photons' share of each vertex's variance sigma_H^2, in [0, 1]; the rest is the points' own samples
  // (shadow rays, or --reference paths). Filled with irradianceNoise.
  std::vector<double> photonVarianceShare;
  // Of the points' share, the paths gathered in a narrow gap (--gap-paths): a variance that neither more photons
  // nor more shadow rays lower. Filled with irradianceNoise.
  std::vector<double> gatheredVarianceShare;
  // The points' own samples' share of each vertex's H (luminance), in [0, 1]: what the shadow rays (or gathered
  // paths) brought, of which the photons brought the rest. Filled with irradianceNoise.
  std::vector<double> sampledShare;
  // The photons' predicted smoothing bias at each vertex, relative to H's luminance: its surface's RMS
  // (estimators/bandwidth.h, PredictedBias) over the vertex's H; 0 where paths are gathered. Filled with
  // irradianceNoise.
  std::vector<double> irradianceBias;
  // Per vertex in a narrow gap, its two estimates of the scattered light (baker/3_gap_weights.h), from which
  // WeighGatheredPaths learns each surface's weight and mixes them; emptied once it has. Filled with irradianceNoise.
  std::vector<GapPair> gapPairs;
  // With --sh: per vertex, the L1 SH of its incident radiance per colour (estimators/incident_moments.h); else empty.
  std::vector<ShL1> sh;
  std::vector<double> directionNoise;  // with --sh: the standard error of each vertex's L1 direction [rad]

  Rgb Radiance(size_t vertex) const { return OutgoingRadiance(emitted[vertex], albedo[vertex], irradiance[vertex]); }
};

}  // namespace pb
