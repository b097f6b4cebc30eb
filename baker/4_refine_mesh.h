// Stage 4: a display mesh that follows the light. Starting from the scene's triangles (welded into one
// half-edge mesh, mesh/half_edge_mesh.h), it
//   1. optionally subdivides uniformly, `subdivide` levels (mesh/subdivide.h, OpenSubdiv);
//   2. coarsens where the light is flat: halfedge collapses that keep the geometry exact (mesh/decimate.h,
//      OpenMesh's Decimater; Walter et al. 1997) and keep the interpolation error within the tolerance (and
//      further, the smallest error first, if the mesh is still over the vertex budget);
//   3. refines where the light changes: longest-edge bisection (mesh/refine.h; Shirley et al. 1995) of the
//      faces whose interpolation error exceeds the tolerance, down to a minimum edge length, within a vertex
//      budget;
// and evaluates H, R and Le at every vertex of the result from the estimators (stage 3), never by
// interpolation. No photon is traced again: the estimators hold the photons of the base surfaces.
//
// The error is measured in what a viewer sees: the displayed grey level in [0, 1] of the vertex radiance
// (baker/tone_map.h, DisplayedLuminance, at the PLY's exposure), linearly interpolated across a face, against the
// same grey level of the radiance estimated directly at the point. A tolerance of 0.02 is 2% of the display
// range, about 5 of 255 levels. Faces are judged at the points of a barycentric lattice (mesh/interpolation_error.h)
// whose spacing is at most half the surface's bandwidth h: the estimate has no detail finer than h.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "baker/2_bin_photons.h"
#include "baker/4_refine_settings.h"
#include "baker/3_irradiance_field.h"
#include "baker/baked_mesh.h"
#include "baker/runtime/progress.h"

namespace pb {


// InputError("--subdivide") when the uniform levels would need more memory than the machine has: about 400 bytes
// per final face (half-edge mesh, display mesh and light; measured on the box at levels 3 to 5).
void CheckSubdivisionMemory(size_t triangles, int levels);
// A warning when estimating the vertices of `levels` subdivisions of `triangles` would take over a minute, from the
// time a point of the bake's estimate took [s]; none when it would not.
std::vector<std::string> SubdivisionTimeWarnings(size_t triangles, int levels, double secondsPerPoint);

struct RefineReport {
  bool ran = false;
  size_t verticesBefore = 0, verticesAfter = 0;  // of the written (split) mesh
  size_t facesBefore = 0, facesAfter = 0;
  size_t collapses = 0, splits = 0;
  size_t collapsesPastTolerance = 0;  // made to fit the budget after the tolerance allowed no more
  size_t refusedByBudget = 0, refusedByEdgeLength = 0;  // cuts a constraint refused
  size_t detachedFaces = 0;   // input faces on non-manifold edges, refined on their own
  // Displayed-luminance error of the final mesh, against the estimator, at its faces' lattice points: the
  // largest; the mean over the surface area; the 99th percentile by area (99% of the area lies on faces whose
  // largest error is at most this); and the fraction of the area on faces above the tolerance (where the minimum
  // edge length or the budget stopped refinement).
  double maxError = 0, meanError = 0, p99Error = 0, areaAboveTolerance = 0;
  std::vector<std::string> warnings;  // the budget left faces above the tolerance, or could not be met
  // A Ctrl-C stopped refinement: the refined mesh was given up (empty), and nothing above describes it.
  bool interrupted = false;
};

// What refinement reads: the irradiance field (stage 3), the base mesh (for the input's corner normals and area
// ratios) and the PLY's display exposure.
struct RefineInputs {
  const IrradianceField& field;
  const SplitMesh& base;  // SplitBySurface(scene, surfaces)
  float exposure;
};

struct RefinedMesh {
  BakedMesh mesh;
  RefineReport report;
};
// After a Ctrl-C (baker/runtime/interrupt.h) it stops at the next face or vertex chunk and gives up its mesh
// (report.interrupted), so that the bake writes the mesh it had.
RefinedMesh RefineMesh(const RefineInputs& in, const RefineSettings& settings, const Log& log);

// One warning per lit surface whose estimate is noisier than the tolerance in displayed grey level: refinement
// there follows the noise. The noise is the field's for the surface's photons spread evenly over it
// (PhotonIrradiance::UniformNoise), as a relative deviation of the surface's mean reflected radiance.
std::vector<std::string> NoiseWarnings(const IrradianceField& field, const SurfaceBins& bins, float exposure,
                                       float tolerance);

}  // namespace pb
