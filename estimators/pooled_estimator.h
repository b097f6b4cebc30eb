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
// r, as any kernel averages over h: the price of reading 200 photons where a piece holds 5.
//
// r reaches the `neighbours`-th nearest photon of like orientation, at most `maxRadius`, and doubles (a few times at
// most) while the area samples' weights sum to less than kMinAreaSamples, so that the area below the sum is never a
// sliver. A query costs the points its searches find (one for the photons, one for the area, where no doubling is
// asked): photons and area samples are kept in one kd-tree per normal direction (about 25 degrees wide), and a point
// searches only the trees that can hold a side within 60 degrees of its own, so a side facing away from the light
// pays little for the lit ones around it. The relative noise is the photons' sum's (their arrivals Poisson):
// sqrt(sum (phi_j w_j)^2) / sum phi_j w_j, in luminance.
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
// half-way out), where there are that many within reach: about half what r holds at the bake's sampling density.
inline constexpr double kMinAreaSamples = 8;

struct PooledSettings {
  // Photons of like orientation within r: weighed by w, about as many as 100 of weight 1, so about 10% noise.
  uint32_t neighbours = 200;
  float maxRadius = 0.5f;  // [m], r at most (unless the area samples ask for more)
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

  size_t Photons() const { return photonCount_; }
  const PooledSettings& Settings() const { return settings_; }
  size_t AreaSampleCount() const { return areaCount_; }

 private:
  // The photons and area samples whose normals fall in one cell of the normal grid, and the cone holding them.
  struct Direction {
    Normal3 axis;        // their mean normal
    float leastCosine;   // a point of normal n can share photons with them where Dot(n, axis) >= leastCosine
    PhotonMap photons, area;
  };
  // A point of like orientation near x: its squared distance [m^2] and orientation weight, (n_j . n - c) / (1 - c).
  struct Near {
    float distance2;
    float orientation;
    const MapPhoton* point;
  };
  // Every point of `map` in `directions` within `radius` of x and of like orientation to n, into `found`, in the
  // same order on every thread.
  static void Collect(const std::vector<const Direction*>& directions, PhotonMap Direction::*map, Point3 x,
                      float radius, Normal3 n, std::vector<Near>& found);

  // r [m]: as far as the `neighbours`-th nearest photon of like orientation, or `maxRadius` where fewer lie within
  // it; 0 where none does. `photons` holds those within `maxRadius`.
  float Reach(const std::vector<const Direction*>& facing, Point3 x, Normal3 n, std::vector<Near>& photons) const;
  // H within r of x (doubling r while the area samples' weights sum to less than kMinAreaSamples), from `photons`
  // found within r (searched again as r doubles); `area` is scratch.
  NoisyIrradiance RatioWithin(const std::vector<const Direction*>& facing, Point3 x, Normal3 n, float r,
                              std::vector<Near>& photons, std::vector<Near>& area) const;

  std::vector<Direction> directions_;
  size_t photonCount_, areaCount_;
  PooledSettings settings_;
};

}  // namespace pb
