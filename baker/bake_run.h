// The bake as a command runs it (tools/bake_cli.h, tools/bake_mpi.cpp): every output written as one transaction,
// then the summary on `log`; on bake-mpi's other processes, their share of the photons and the estimate. What it
// computes and how: baker/bake.h.
#pragma once

#include "baker/options.h"
#include "baker/runtime/progress.h"

namespace pb {

class Distribution;

// Bake (baker/bake.h), then PrintSummary (baker/report.h). With a distribution, on its rank 0.
void BakeAndSummarise(const BakeOptions& options, const Log& log, const Distribution* distribution = nullptr);
// On a distribution's other ranks: prepares the scene and traces this process's share of the photons for rank 0.
void TraceShareOfBake(const BakeOptions& options, const Log& log, const Distribution& distribution);

}  // namespace pb
