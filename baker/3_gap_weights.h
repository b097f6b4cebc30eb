// Stage 3, how far to trust the paths gathered in narrow gaps (baker/3_gap_gather.h), per surface. At a point in a
// narrow gap both the gathered paths, g, and the photons, p, estimate the light scattered at least once, E_s
// [W/m^2]: g without bias but noisy (one lucky path among 256 holds it where the light is small and near), p with
// little noise but with the bias the gap is there to remove. Per surface, the field takes
//   E_s = p + alpha (g - p),   alpha = (b^2 + s_p^2) / (b^2 + s_p^2 + s_g^2),
// the weight that minimises the expected squared error of the mix (g = T + e_g, p = T + b + e_p): s_g^2 and s_p^2
// are the means over the surface's narrow-gap vertices of each estimate's variance, and b^2, the photons' squared
// bias there, is the mean of (g - p)^2 less both (0 where that is negative), all in luminance [(W/m^2)^2]. Pooled
// over a surface, so that no vertex's weight follows its own paths' luck. Between two books 1 mm apart (s_g small,
// b large) alpha stays near 1, the gathered light; on a car's tail-lamp pieces, where g's standard error is 1.3-3.1
// times its mean and p lies within g's own error, it falls towards the photons (docs/real-assets.md, "What holds
// the sports car's noise"). As the paths grow, s_g falls and alpha goes to 1: the mix is consistent.
//
// A surface smaller than its kernel, gathered at every point, is weighed alike: there p is the photons' estimate the
// surface would have had (its own kernel, or the photons pooled across sparse surfaces, which average the light
// over up to half a metre about it). A bath's side in a room lit through a window, 0.3-0.9 m^2, reads its pooled
// photons faithfully and its 256 paths 20-28% noisy, so alpha falls; bottles on a shelf, whose pooled photons read
// a third of their light, keep alpha near 1 (docs/bake.md, "Narrow gaps"). On a planar surface's boundary
// (--gap-edges) the photons' bias of 0.5-1.3% is below what a surface's few noisy edge vertices can show, so the
// edges keep the gathered light (alpha 1).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "estimators/noisy_irradiance.h"

namespace pb {

// A weighed vertex's two estimates of E_s (in a narrow gap, on a surface smaller than its kernel), and the rest of
// its H (the direct light, whose noise is independent).
struct GapPair {
  static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  uint32_t surface = kNone;  // kNone: the vertex's light is not weighed
  NoisyIrradiance gathered, photons, rest;
  bool Present() const { return surface != kNone; }
};

// Per surface: the weight of the gathered paths, the photons' RMS bias at its weighed vertices [W/m^2,
// luminance] (what 1 - alpha of it leaves in H), and how many vertices it was learned from.
struct GapWeight {
  double alpha = 1, bias = 0;
  uint32_t vertices = 0;
};

// The weights of surfaces 0 .. surfaces - 1 from the narrow-gap vertices among `pairs` (any order; summed in
// order, so the same on any thread count); alpha 1 on a surface with none.
std::vector<GapWeight> LearnGapWeights(const std::vector<GapPair>& pairs, size_t surfaces);

// E_s at a narrow-gap point by its surface's weight, with its variance split into the gathered paths' and the
// photons' shares [(W/m^2)^2] and the photons' part of the value.
struct BlendedGap {
  NoisyIrradiance value;
  double gatheredVariance = 0, photonVariance = 0;
  Rgb photonPart;
};
BlendedGap Blend(const NoisyIrradiance& gathered, const NoisyIrradiance& photons, double alpha);

}  // namespace pb
