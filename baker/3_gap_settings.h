// Stage 3's gathering in narrow gaps as the command line sets it (--gap-*); the gathering itself is
// baker/3_gap_gather.h's, which validates these settings.
#pragma once

#include <cstdint>

namespace pb {

// Gathering in narrow gaps, with --direct sampled: the command line's --gap-* options (what the bake reads of them).
struct GapSettings {
  uint32_t paths = 256;  // --gap-paths: paths gathered at a point in a gap (with `noise`: at most); 0: none; [0, 1e6]
  double noise = 0;      // --gap-noise: the gathered points' relative noise target; 0: always `paths`; [0, 1]
  uint32_t probes = 32;  // rays that decide whether a point lies in a gap
  float facing = 0.3f;   // the fraction of them that must meet a near parallel surface
  float reach = 0.5f;    // how near, as a fraction of the point's h
  float smallArea = 0;   // a surface of area below smallArea h^2 is gathered everywhere, and never read
  // Of the scene's triangles, the most that the small surfaces gathered may hold: the smallest are gathered first,
  // and the rest read the photons (1: every small surface; the defaults' cap, so that a scene of tiny faces, a
  // Minecraft world, does not gather everywhere).
  float smallShare = 1;
  bool edges = false;    // --gap-edges: also gather at every point on a planar surface's boundary
  bool fixedPaths = false;  // --gap-paths given: the rounds keep `paths` as it is
  void Validate() const;  // --gap-paths, --gap-noise, --gap-small-area; an InputError naming the option
};

}  // namespace pb
