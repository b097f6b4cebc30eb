// What the bake warns about once the light is estimated (the driver's, baker/bake.cpp, and bake-mpi's rank 0): each
// function reads what its stages made (the prepared scene, the photons and their bins, the field, the vertices)
// and returns warnings as "FILE: warning: ...", none where all is well. The noise that shows as blotches is
// judged at 2% of the displayed light (about 5 of 255 grey levels).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "baker/0_prepare_scene.h"
#include "baker/2_bin_photons.h"
#include "baker/3_contributions.h"
#include "baker/3_irradiance_field.h"
#include "baker/baked_mesh.h"
#include "baker/photon_store.h"

namespace pb {

// Each surface whose h is below half its mean photon spacing sqrt(A / hits), A the area that no other geometry
// covers (where H is 0 in truth): most of its vertices see no photon within h, so the photons' H there reads 0
// between them. knn adapts its radius, and --h auto keeps 20 photons within h wherever a surface has photons
// enough to choose from (one with a handful, a table leg's end, is too small to matter): neither is warned about.
std::vector<std::string> BandwidthWarnings(const IrradianceField& field, const SurfaceBins& bins,
                                           const EstimatorSettings& estimator);

// The lights that reach the scene but got no photon: their share n Phi_l / Phi is below one, so their light is
// missing from the bake (with the direct light `sampled`, only their interreflected light). Up to three lights are
// named one by one; more make one line: how many, the flux they carry, and the brightest of them.
std::vector<std::string> UnlitLightWarnings(const PreparedScene& scene, const PhotonStore& photons, bool sampled);

// The user's --exposure shows every lit vertex black, or every one white (each channel it has at 255): within its
// range it can still be far from this scene's light (the automatic exposure says how far). None when automatic.
std::vector<std::string> ExposureWarnings(std::optional<float> exposure, const BakedMesh& baked);

// Every vertex reads no light: the lights shine only on back sides or along the surfaces (a sun from below the
// ground, a point light in the plane of the only surface), so the outputs are black.
std::vector<std::string> DarkBakeWarnings(const std::string& scenePath, const BakedMesh& baked);

// The surfaces lit only from behind: photons reached their back sides (at least 20) but no vertex of their front
// reads any light, so they are black. Their fronts usually face into the object they close (faces wound the wrong
// way round in the modelling tool): on the staircase, 4 surfaces and 0.7 m^2 read 0 this way without a word. The
// three largest are named, the rest counted.
std::vector<std::string> BackLitWarnings(const PreparedScene& scene, const SurfaceBins& bins, const BakedMesh& baked);

// The surfaces whose vertices show less than a quarter of the light that their photons brought (the vertices' H,
// interpolated across the faces, against the photons' flux over the surface's area; on surfaces of at least
// kPooledBelowHits photons): a large face whose corners sit in the dark, under other geometry, shows the light
// that falls on its middle nowhere. On the staircase a 72 m^2 wall that 150,494 photons lit at 0.88 W/m^2 read 0 at
// every vertex without a word. Where the direct light is sampled the photons carry only the rest, so such a surface
// shows less than a quarter of even that. The three largest are named, the rest counted.
std::vector<std::string> MissedLightWarnings(const PreparedScene& scene, const SurfaceBins& bins, const BakedMesh& baked);

// What the visible-noise warning reads.
struct VisibleNoise {
  const std::string& scenePath;
  const BakedMesh& baked;
  double noise = 0;             // the bake's predicted noise (BakeNoise)
  uint64_t emitted = 0;         // photons
  uint32_t referencePaths = 0;  // --reference's paths a point; 0: photons
  const DirectSettings& direct;  // as the user set them
  bool rounds = false;          // traced in rounds to a target the user chose: no warning
};
// The bake's noise is visible: names what would bring it under 2% (RemedyForNoise, baker/photons/progressive.h):
// more photons, and more shadow rays (or --reference paths) where the points' own noise is most of it, and the
// rounds that find them; or that the paths gathered in narrow gaps hold it.
std::vector<std::string> VisibleNoiseWarnings(const VisibleNoise& in);

}  // namespace pb
