// Stage 1 shared among processes (baker/distribution.h, bake-mpi): what a process traced, block by block, and the
// interface by which the tracer (baker/1_trace_photons.h) asks which blocks are its own and gathers every
// process's.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "baker/photon_store.h"

namespace pb {

// A block as one process traced it, for a trace shared among processes: the index of its work item, its range,
// stats (in attenuation units) and the hits it kept.
struct TracedBlock {
  uint64_t item = 0;
  BlockRange range;
  TraceStats stats;
  HitBlock hits;
};

// A trace shared among processes (bake-mpi, tools/bake_mpi.cpp): each process traces the work items it Takes,
// given the light of each item in the order the items are claimed, then every process calls Gather once with its blocks, which returns every process's blocks. Every store then
// holds the same bytes as one traced by one process. A store that every process holds alike (the rounds', --resume's)
// grows alike.
class TraceShare {
 public:
  virtual ~TraceShare() = default;
  virtual std::vector<bool> Takes(std::span<const uint32_t> itemLights) const = 0;
  virtual std::vector<TracedBlock> Gather(std::vector<TracedBlock> mine) const = 0;
};

}  // namespace pb
