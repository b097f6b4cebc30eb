// The bake pipeline (DESIGN.md, "Data flow"): load scene -> trace photons -> bin per surface -> estimate H at
// vertices -> (refine the mesh) -> write PLY or glTF (and the JSON report). Throws InputError for bad input before any output is written.
#pragma once

#include "baker/5_write_gltf.h"
#include "baker/bake_run.h"
#include "baker/files/atomic_file.h"
#include "baker/options.h"
#include "baker/runtime/progress.h"
#include "baker/report.h"

namespace pb {

// The whole bake: BakeMesh, then the PLY and the JSON report. Every output is one transaction
// (baker/files/atomic_file.h): none is renamed into place until all are written.
class Distribution;

// With a distribution (baker/distribution.h), on its rank 0: the photons are traced by every process.
BakeReport Bake(const BakeOptions& options, const Log& log, const Distribution* distribution = nullptr);

// Everything before writing the PLY: the report (all but the write time) and the baked
// mesh. options.outputPath and reportPath are not used; irradiance maps are written when
// options.mapsDirectory is set. For tools that measure the estimate (tools/accuracy.cpp).
struct BakeResult {
  BakeReport report;
  BakedMesh mesh;
  SurfaceNames names;  // each surface's object and material, for the glTF output
};
// Irradiance maps and the photon file (--maps, --save-photons) are staged in `outputs`; the overload without it
// commits them itself.
BakeResult BakeMesh(const BakeOptions& options, const Log& log, OutputFiles& outputs,
                    const Distribution* distribution = nullptr);
BakeResult BakeMesh(const BakeOptions& options, const Log& log);

}  // namespace pb
