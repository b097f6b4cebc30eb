// Irradiance pooled across surfaces, H(x, n) [W/m^2 per unit surface area], for the points of surfaces too small or
// too dim to hold photons enough for a density estimate of their own: a banister cut into thousands of pieces at its
// creases, a chandelier's links, a carved frame. A surface with 5 photons reads 45% noise however its kernel is
// chosen, and one photon within a narrow kernel reads as a spike. Here the photons of every such surface near the
// point, on sides turned nearly as the point's, are divided by the area of those same sides near it:
//
//   H(x, n) = sum_j phi_j w_j / sum_i a_i w_i,    w = (1 - d^2 / r^2) max(0, (n_j . n - c) / (1 - c)),
//
// phi_j the photons' flux [W], a_i the area [m^2] of the pooled surfaces' area samples (each triangle cut into pieces
// as fine as the photons' spacing, AreaSamples), d the distance from x [m], n_j the side's unit normal and
// c = kPooledCosine. Photons and area are weighed alike, so a constant irradiance is read exactly whatever the
// pieces' shapes: a ratio estimator. (Jensen's photon map divides the flux by pi r^2 instead, which reads thin or
// curved pieces, whose area within r is far less, too dark.) Where the light changes within r it is averaged over
// r, as any kernel averages over h: the price of reading 100 photons where a piece holds 5.
//
// r starts at `startRadius` and is rescaled (a few times at most) while the photons of like orientation within it are
// fewer than half `neighbours` (up to `maxRadius`) or more than four times as many, and doubled while the area
// samples' weights sum to less than kMinAreaSamples (past `maxRadius`), so that the area below the sum is never a sliver. Each step
// is a radius search, whose cost is the points it finds. The relative noise is the photons' sum's (their
// arrivals Poisson): sqrt(sum (phi_j w_j)^2) / sum phi_j w_j, in luminance.
//
// Shirley et al. 1995 estimate density per surface; Jensen 1996 ("Global illumination using photon maps") pools
// photons in space. This is the second for the few surfaces where the first has nothing to say.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "estimators/noisy_irradiance.h"
#include "estimators/photon_map.h"
#include "mesh/geometry.h"
#include "mesh/scene.h"

namespace pb {

// Sides whose normals differ by more than acos(kPooledCosine) = 60 degrees from the point's share no photon with it.
inline constexpr float kPooledCosine = 0.5f;
// The least weight of area samples r reaches (their weights w summed: as many samples at the centre, twice as many
// half-way out), where there are that many within reach.
inline constexpr double kMinAreaSamples = 16;

struct PooledSettings {
  uint32_t neighbours = 100;  // photons of like orientation within r: about 10% relative noise
  float maxRadius = 0.5f;     // [m], r at most (unless the area samples ask for more)
  float startRadius = 0.1f;   // [m], r first: where `neighbours` photons lie at the pooled photons' mean density
};

// Points covering `triangles` of `scene`, about `density` per m^2, each carrying the area it stands for [m^2] as its
// flux in all three channels, and a unit normal: a triangle of area A >= 1 / density gets ceil(A density) points
// spread over it by a low-discrepancy sequence, with its own normal; smaller ones (a banister's facets) are gathered
// per cube of side 1 / sqrt(density) and normal direction (cells of about 25 degrees) into one point at their
// area-weighted centroid, with their area-weighted mean normal. Every triangle's area is counted once, exactly.
// normalOf gives each triangle the normal its area was sampled with: the photons on it must be weighed with the
// same (PooledEstimator), so that a constant irradiance reads exactly. Deterministic.
struct AreaSamples {
  std::vector<MapPhoton> samples;
  std::unordered_map<uint32_t, Normal3> normalOf;  // per triangle sampled
};
AreaSamples SampleArea(const Scene& scene, const std::vector<uint32_t>& triangles, double density);

class PooledEstimator {
 public:
  // photons: the pooled surfaces' front hits, each with its flux [W] and the normal its triangle's area was sampled
  // with (AreaSamples::normalOf); area: AreaSamples::samples of the same surfaces.
  PooledEstimator(std::vector<MapPhoton> photons, std::vector<MapPhoton> area, PooledSettings settings);

  // H at x on a side of normal n, and its relative noise; 0 (noise 0) where no photon of like orientation lies
  // within reach.
  NoisyIrradiance Estimate(Point3 x, Normal3 n) const;

  size_t Photons() const { return photons_.Size(); }
  const PooledSettings& Settings() const { return settings_; }
  size_t AreaSampleCount() const { return area_.Size(); }

 private:
  PhotonMap photons_, area_;
  PooledSettings settings_;
};

}  // namespace pb
