// A bake shared among processes (`mpirun -np N bake-mpi ...`; tools/bake_mpi.cpp is the only file that includes
// MPI). Every process prepares the scene; each traces the work items of the photon trace that a hash of their index
// gives its rank (TraceShare), bins its hits while it traces them (baker/2_bin_photons.h), and shares its blocks'
// stats and the few hits it kept; the node sums, exact integers, are summed over the processes. Every process then
// holds the same irradiance field and estimates its share of the vertices, in chunks (kVertexChunk,
// baker/3_irradiance_field.h), which rank 0 gathers; rank 0 alone refines, writes maps and writes the outputs. The
// photons are exactly those of a single-process bake, so its bytes are too, for any N and --threads.
//
// Before any photon is traced, every process says whether it is ready (Agree): a process that failed to read the
// scene or refused the options says so instead of leaving the others waiting, and every process then stops.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "baker/1_trace_photons.h"
#include "estimators/rng.h"

namespace pb {

class Distribution : public TraceShare {
 public:
  virtual unsigned Rank() const = 0;
  virtual unsigned Size() const = 0;
  bool Root() const { return Rank() == 0; }
  // Items by a hash of their index: the work list interleaves the lights, so that item i modulo N would give one
  // rank every block of one light (measured with two ranks on the box: 1.63x for 2 ranks where threads give 1.9x).
  bool Takes(size_t item) const final { return Holder(item) == Rank(); }
  unsigned Holder(size_t item) const { return unsigned(SplitMix64(item) % Size()); }

  // Called once by every process before tracing, with whether it is ready: every process's answer, by rank.
  virtual std::vector<bool> Agree(bool ready) const = 0;
  bool Agreed() const { return agreed_; }
  // Sums `values` over the processes, into every process's. Exact: integers.
  virtual void SumOnAll(std::span<int64_t> values) const = 0;
  // `items` is an array of items of `itemBytes` each, in chunks of `chunk` items; each process filled the chunks c
  // it Takes(c). Afterwards rank 0's holds every chunk (the others' are left as they were).
  virtual void GatherChunks(std::span<std::byte> items, size_t itemBytes, size_t chunk) const = 0;

 protected:
  mutable bool agreed_ = false;
};

}  // namespace pb
