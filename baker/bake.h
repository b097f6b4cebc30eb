// The bake pipeline (DESIGN.md, "Data flow"): load scene -> trace photons -> bin per surface -> estimate H at
// vertices -> write PLY (and the JSON report). Throws InputError for bad input before any output is written.
#pragma once

#include "baker/options.h"
#include "baker/progress.h"
#include "baker/report.h"

namespace pb {

BakeReport Bake(const BakeOptions& options, const Log& log);

}  // namespace pb
