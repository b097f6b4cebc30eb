// Stage 2: photon hits grouped per surface (the paper's "hits are binned per surface"). Only hits on a
// surface's front side are kept for estimation: that side is the one the display mesh shows. Hits on back sides
// are counted per surface. Arrays are structure-of-arrays in surface order: (u,v) [m] and flux [W].
//
// Words for a photon's light, used alike in every file: its "attenuation" is the dimensionless fraction of its
// emitted flux that it still carries (1 at emission); its "flux" [W] is Phi_l / N_l times that; a light's
// "power" Phi [W] is what all its photons share (Light::Power).
#pragma once

#include "baker/progress.h"

#include <cstdint>
#include <span>
#include <vector>

#include "baker/1_trace_photons.h"

namespace pb {

struct SurfaceBins {
  std::vector<uint32_t> start;  // surface s owns entries [start[s], start[s+1])
  std::vector<Point2> uv;       // chart position [m]
  std::vector<Rgb> flux;        // [W]
  std::vector<uint64_t> backHits;  // per surface: hits on its back side, not estimated

  size_t SurfaceCount() const { return start.size() - 1; }
  uint64_t FrontHits(size_t s) const { return start[s + 1] - start[s]; }
  std::span<const Point2> Uv(size_t s) const { return {uv.data() + start[s], start[s + 1] - start[s]}; }
  std::span<const Rgb> Flux(size_t s) const { return {flux.data() + start[s], start[s + 1] - start[s]}; }
  // The flux [W] that reached surface s's front side, summed in hit order.
  Rgb FrontFlux(size_t s) const {
    RgbSum sum;
    for (const Rgb& p : Flux(s)) sum.Add(p);
    return sum.ToRgb();
  }
};

// Stable: within a surface, hits keep their trace order, so sums over them are reproducible.
SurfaceBins BinPhotons(const SurfaceSet& surfaces, const PhotonStore& hits);
// The same, with its progress on `log` (two passes over the hits; 10^8 hits take seconds).
SurfaceBins BinPhotons(const SurfaceSet& surfaces, const PhotonStore& hits, const Log& log);

}  // namespace pb
