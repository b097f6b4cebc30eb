// A bake shared among processes (`mpirun -np N bake-mpi ...`; tools/bake_mpi.cpp is the only file that includes
// MPI). Every process prepares the scene; each traces its turns of every light's work items (TraceShare). Where a
// single-process bake would bin its photons while tracing them (a fixed h, no rounds: baker/2_bin_photons.h), each
// process does so and shares its blocks' stats and the few hits it kept, and the node sums, exact integers, are
// summed over the processes; otherwise (the defaults: h chosen per surface, rounds to a target) every process
// takes every process's blocks and holds the whole store, as one process would. Every process then holds the same
// irradiance field and estimates the chunks of vertices it claims first (kVertexChunk, baker/3_irradiance_field.h;
// ClaimChunk), which rank 0 gathers; rank 0 decides whether another round follows and broadcasts its plan. With --maps,
// rank 0 broadcasts what its field learned last (IrradianceField::LateState) and the processes share the maps'
// texels alike (baker/5_write_maps.h); rank 0 alone refines and writes the outputs. The photons are exactly those of a single-process bake, so its bytes
// are too, for any N and --threads.
//
// Before any photon is traced, every process says whether it is ready (Agree): a process that failed to read the
// scene or refused the options says so instead of leaving the others waiting, and every process then stops.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "baker/1_trace_share.h"
#include "estimators/rng.h"

namespace pb {

class Distribution : public TraceShare {
 public:
  virtual unsigned Rank() const = 0;
  virtual unsigned Size() const = 0;
  bool Root() const { return Rank() == 0; }
  // Each light's items go to the processes in turn, the first to a hash of the light: every process traces nearly
  // the same number of every light's photons (within one block) and of one-block lights. The work list interleaves
  // the lights, so item i modulo N gave one of two ranks every block of one light on the box (1.63x for 2 ranks,
  // where threads give 1.9x); a hash of i gave one rank 128 of the 246 blocks of 16M photons.
  std::vector<bool> Takes(std::span<const uint32_t> itemLights) const final {
    std::vector<uint64_t> turn;
    std::vector<bool> mine(itemLights.size());
    for (size_t i = 0; i < itemLights.size(); ++i) {
      const uint32_t l = itemLights[i];
      if (l >= turn.size()) turn.resize(l + 1, 0);
      mine[i] = (SplitMix64(l) + turn[l]++) % Size() == Rank();
    }
    return mine;
  }
  // The estimate's vertex chunks go to whichever process asks for them first: every process calls ClaimChunk once
  // for each chunk, from any of its threads and in any order, and estimates the chunks it won, so that a process
  // whose chunks cost more (gathered paths, pooled queries) takes fewer of them. In turn (chunk c to process c
  // modulo N) one of Lost Empire's 2 ranks had 30% more work than the other. OpenChunks(n) on every process
  // before, CloseChunks() on every process after; ChunkHolder(c) then says, on every process, who took chunk c, or
  // kNobody when no process claimed it (each stopped claiming at the rounds' deadline).
  virtual void OpenChunks(size_t chunks) const = 0;
  virtual bool ClaimChunk(size_t c) const = 0;
  virtual void CloseChunks() const = 0;
  static constexpr unsigned kNobody = ~0u;
  unsigned ChunkHolder(size_t c) const { return holders_[c]; }
  bool HoldsChunk(size_t c) const { return ChunkHolder(c) == Rank(); }

  // Called once by every process before tracing, with whether it is ready: every process's answer, by rank.
  virtual std::vector<bool> Agree(bool ready) const = 0;
  bool Agreed() const { return agreed_; }
  // Sums `values` over the processes, into every process's. Exact: integers.
  virtual void SumOnAll(std::span<int64_t> values) const = 0;
  // Rank 0's `bytes` into every process's (the same length on each): what rank 0 alone decides, such as whether
  // another round follows and its plan, so that every process traces and estimates it together.
  virtual void Broadcast(std::span<std::byte> bytes) const = 0;
  // `items` is an array of items of `itemBytes` each, in chunks of `chunk` items; each process filled the chunks c
  // it HoldsChunk(c). Afterwards rank 0's holds every chunk (the others' are left as they were).
  virtual void GatherChunks(std::span<std::byte> items, size_t itemBytes, size_t chunk) const = 0;

 protected:
  mutable bool agreed_ = false;
  mutable std::vector<unsigned> holders_;  // per vertex chunk, the process that took it (CloseChunks)
};

}  // namespace pb
