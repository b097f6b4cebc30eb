// The photon file: a photon store (baker/1_trace_photons.h) saved by --save-photons and continued by --resume.
// Little-endian binary, version 1, laid out in docs/photon-file.md:
//   header  magic "PBPHOTON", version, record size (28 B), scene hash, seed, max bounces, simulated effects,
//           light and block counts;
//   lights  per light: Phi_l [W] (RGB float) and N_l, the photons it has emitted;
//   blocks  per block: its light, photon range and hit count, and its stats in attenuation units;
//   hits    every PhotonHit (attenuation, octahedral direction, triangle and side, barycentrics), block by block;
//   trailer CRC-32 (zlib) of every byte before it.
// It is written to a temporary file and renamed into place (baker/atomic_file.h). Reading checks everything
// before any of it is used: the file's size against its header, the CRC, and that the scene, seed and photon
// options match this bake; any mismatch is an InputError that names the file and says what differs.
#pragma once

#include <cstdint>
#include <string>

#include "baker/atomic_file.h"
#include "baker/0_plan_transport.h"
#include "baker/1_trace_photons.h"
#include "mesh/scene.h"

namespace pb {

// What the photons of a store depend on, besides the lights: a store is only continued with the same.
struct PhotonOrigin {
  uint32_t sceneHash = 0;   // SceneHash of the loaded scene
  uint64_t seed = 0;
  uint32_t maxBounces = 0;
  uint32_t effects = 0;     // SimulatedEffects of the plan
};

// CRC-32 of everything in the loaded scene that photons depend on: positions [m] (after --scale), triangles,
// materials, texture coordinates and texels. Independent of comments, names and line numbers.
uint32_t SceneHash(const Scene& scene);
// Bit e set when the plan simulates Effect e.
uint32_t SimulatedEffects(const TransportPlan& plan);

void WritePhotonFile(OutputFiles& outputs, const std::string& path, const PhotonStore& store, const PhotonOrigin& origin);

// The store in `path`, after every check above; `lightPower` is this scene's Phi_l, one per light.
PhotonStore ReadPhotonFile(const std::string& path, const PhotonOrigin& expected, const std::vector<Rgb>& lightPower);

}  // namespace pb
