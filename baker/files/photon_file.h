// The photon file: a photon store (baker/1_trace_photons.h) saved by --save-photons and continued by --resume.
// Little-endian binary, version 1, laid out in docs/photon-file.md:
//   header  magic "PBPHOTON", version, record size (28 B), scene hash, seed, max bounces, simulated effects,
//           light and block counts;
//   lights  per light: Phi_l [W] (RGB float) and N_l, the photons it has emitted;
//   blocks  per block: its light, photon range and hit count, and its stats in attenuation units;
//   hits    every PhotonHit (attenuation, octahedral direction, triangle and side, barycentrics), block by block;
//   trailer CRC-32 (zlib) of every byte before it.
// It is written to a temporary file and renamed into place (baker/files/atomic_file.h). Reading trusts nothing in the
// file, whose CRC guards only against accidents: it must be a regular file; every size is checked against the
// file's length, in overflow-safe arithmetic, before anything is allocated; the CRC; each light's blocks must be
// aligned, full but for the last, and in order; each block's statistics must add up (every photon ends once) and
// be finite; every record must name a triangle of this scene, with finite non-negative attenuation and
// barycentrics inside it; and the scene, seed and photon options must match this bake. Any failure is an
// InputError that names the file and says what is wrong.
#pragma once

#include <cstdint>
#include <string>

#include "baker/files/atomic_file.h"
#include "baker/0_plan_transport.h"
#include "baker/photon_store.h"
#include "mesh/scene.h"

namespace pb {

// What the photons of a store depend on, besides the lights: a store is only continued with the same.
struct PhotonOrigin {
  uint32_t sceneHash = 0;   // SceneHash of the loaded scene
  uint64_t seed = 0;
  uint32_t maxBounces = 0;
  uint32_t effects = 0;     // SimulatedEffects of the plan, less direct light with --direct sampled
};

// CRC-32 of everything in the loaded scene that photons depend on: positions [m] (after --scale), triangles,
// materials, texture coordinates and texels, the lights that are not surfaces (kind, strength, place, aim, cone,
// sky, the tables of IES profiles and sky images) and the portals. Independent of comments, names and line
// numbers.
uint32_t SceneHash(const Scene& scene);
// Bit e set when the plan simulates Effect e.
uint32_t SimulatedEffects(const TransportPlan& plan);

void WritePhotonFile(OutputFiles& outputs, const std::string& path, const PhotonStore& store, const PhotonOrigin& origin);

// The store in `path`, after every check above; `lightPower` is this scene's Phi_l, one per light, and `triangles`
// its triangle count.
PhotonStore ReadPhotonFile(const std::string& path, const PhotonOrigin& expected, const std::vector<Rgb>& lightPower,
                           size_t triangles);

}  // namespace pb
