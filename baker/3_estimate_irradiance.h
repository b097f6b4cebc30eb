// Stage 3: irradiance H [W/m^2] at every vertex of the split mesh, by kernel density estimation over the
// photons of the vertex's own surface (estimators/kernel_estimator.h) with bandwidth h [m]. Also fills each
// vertex's reflectance R and emitted radiance Le from its surface's material.
#pragma once

#include "baker/2_bin_photons.h"
#include "baker/baked_mesh.h"
#include "baker/progress.h"
#include "estimators/kernels.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

BakedMesh EstimateIrradiance(const Scene& scene, const SurfaceSet& surfaces, SplitMesh mesh, const SurfaceBins& bins,
                             Kernel kernel, float bandwidth, const Log& log);

}  // namespace pb
