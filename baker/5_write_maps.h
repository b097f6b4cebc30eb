// Stage 5b: irradiance maps. Each surface's H(u,v) [W/m^2] sampled at the centres of a regular grid of square
// texels of side `texel` [m] over its chart, and written as one OpenEXR image per surface: the paper's "sample
// H(u,v) at a finite set of locations and interpolate" form.
//
// Image layout: texel (i, j) (column i, row j, row 0 first) has its centre at chart point
// (u0 + (i + 1/2) texel, v0 + (j + 1/2) texel), with (u0, v0) the corner of the chart's bounding box. R, G, B hold
// H there; A holds the fraction of the texel's area that lies on the
// surface. Each texel asks the irradiance field (stage 3) at the surface point under its centre
// (SurfacePointSampler::AtChartPoint: on curved charts with the area ratio interpolated from the vertices, so
// that a texel centre at a vertex reads exactly what the vertex holds); a centre off the surface reads the
// surface's nearest point. The header names the quantity and units, the surface (index, object, material), the texel size and
// the chart: origin and u, v axes in world coordinates [m], and (u0, v0). With --sh, twelve more channels hold the
// L1 SH of the incident radiance (estimators/incident_moments.h).
#pragma once

#include <string>
#include <vector>

#include "baker/files/atomic_file.h"
#include "baker/3_irradiance_field.h"
#include "baker/runtime/progress.h"
#include "mesh/split_mesh.h"

namespace pb {

class Distribution;

struct MapsWritten {
  std::vector<std::string> paths;
  size_t texels = 0;
};

// One file per surface, "DIR/surface_<index>.exr" (MapPaths). InputError if DIR is not a writable folder or a chart
// would need more than 8192 texels on a side.
std::vector<std::string> MapPaths(const std::string& directory, size_t surfaces);
// Whether a file name (no folder) is a map's name as MapPaths writes it, "surface_<...>.exr": the files a killed
// run's temporaries and an earlier bake's maps are told by.
bool IsMapName(const std::string& name);
// InputError("--texel") when a surface's chart would need more than 8192 texels on a side, or when the maps being
// written at once (one per thread, the largest first) would need more memory than the machine has, at about 40
// bytes per texel (H, coverage, overlap area and OpenEXR's buffers): checked before any photon is traced.
void CheckMapTexels(float texel, const SurfaceRegions& regions, unsigned threads);
// Texels of all the maps at `texel` [m].
double MapTexelCount(float texel, const SurfaceRegions& regions);
// A warning when the maps would take over a minute, from the time a point of the bake's estimate took
// [s] (a texel is estimated as a vertex is); none when they would not.
std::vector<std::string> MapTimeWarnings(float texel, const SurfaceRegions& regions, double secondsPerPoint);
// A warning when DIR holds maps ("surface_<n>.exr") that this bake does not write (`written`): an earlier bake's of
// another scene, or of surfaces that --only left out, which would otherwise pass for this one's.
std::vector<std::string> StaleMapWarnings(const std::string& directory, const std::vector<std::string>& written);
// Bytes of the `threads` largest maps at once.
double MapMemoryBytes(float texel, const SurfaceRegions& regions, unsigned threads);

// `base` is SplitBySurface of the field's scene, every surface. With `only` (a flag per surface, --only), the maps
// of those surfaces alone, each the same as in a bake of them all. With `sh` (--sh; the field's moments prepared),
// each map also holds the channels sh_r0..sh_b3, the texel's L1 SH as a vertex's (EstimateDirections).
// With `distribution` (rank 0 of a distributed bake), the texels are shared among the processes, each of which
// calls ShareIrradianceMaps with the same arguments meanwhile, and rank 0 writes the maps: the bytes of one process.
MapsWritten WriteIrradianceMaps(OutputFiles& outputs, const std::string& directory, float texel, const IrradianceField& field,
                                const SplitMesh& base, const Log& log, const std::vector<bool>& only = {},
                                bool sh = false, const Distribution* distribution = nullptr);
// A process other than rank 0's share of the maps' texels (WriteIrradianceMaps with a distribution); it writes nothing.
void ShareIrradianceMaps(float texel, const IrradianceField& field, const SplitMesh& base, const std::vector<bool>& only,
                         bool sh, const Distribution& distribution);

}  // namespace pb
