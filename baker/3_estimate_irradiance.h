// Stage 3: irradiance H [W/m^2] at every vertex of the split mesh, estimated from the photons of the vertex's
// own surface (estimators/density_estimator.h: kernel, histogram or k nearest, edge-corrected over the
// surface's region in its chart). Also fills each vertex's reflectance R and emitted radiance Le from its
// surface's material.
#pragma once

#include "baker/2_bin_photons.h"
#include "baker/baked_mesh.h"
#include "baker/progress.h"
#include "estimators/density_estimator.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

BakedMesh EstimateIrradiance(const Scene& scene, const SurfaceSet& surfaces, SplitMesh mesh, const SurfaceBins& bins,
                             const EstimatorSettings& settings, const Log& log);

}  // namespace pb
