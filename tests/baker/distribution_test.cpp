// How a distributed bake shares its work (baker/distribution.h), without MPI: every work item and every vertex
// chunk goes to exactly one process, each process gets the same number of every light's blocks, within one (on a
// work list that interleaves two lights as the box's does, with single-block lights after them), and a vertex
// chunk goes to the process that claims it first. The bytes of a distributed bake are tested with mpirun in tests/tools/bake_mpi_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

#include "baker/distribution.h"

namespace pb {
namespace {

// A process `rank` of `size`, whose exchanges are never called here. The vertex chunks' claims, which bake-mpi keeps
// in a window on rank 0, are `claims`, shared by the processes of one test (0: free, r + 1: taken by rank r).
class Process final : public Distribution {
 public:
  Process(unsigned rank, unsigned size, std::vector<std::atomic<int>>* claims = nullptr)
      : rank_(rank), size_(size), claims_(claims) {}
  unsigned Rank() const override { return rank_; }
  unsigned Size() const override { return size_; }
  std::vector<bool> Agree(bool) const override { return {}; }
  void SumOnAll(std::span<int64_t>) const override {}
  void Broadcast(std::span<std::byte>) const override {}
  void GatherChunks(std::span<std::byte>, size_t, size_t) const override {}
  std::vector<TracedBlock> Gather(std::vector<TracedBlock> mine) const override { return mine; }
  void OpenChunks(size_t) const override {}
  bool ClaimChunk(size_t c) const override {
    int free = 0;
    return (*claims_)[c].compare_exchange_strong(free, int(rank_) + 1);
  }
  void CloseChunks() const override {
    holders_.clear();
    for (const std::atomic<int>& claim : *claims_) holders_.push_back(unsigned(claim.load() - 1));
  }

 private:
  unsigned rank_, size_;
  std::vector<std::atomic<int>>* claims_;
};

// Light 0 and light 1 alternate for 246 items (light 0 every third one), then 1,000 lights of one block each.
std::vector<uint32_t> BoxThenLeds() {
  std::vector<uint32_t> lights;
  for (uint32_t i = 0; i < 246; ++i) lights.push_back(i % 3 == 0 ? 0 : 1);
  for (uint32_t l = 2; l < 1002; ++l) lights.push_back(l);
  return lights;
}

TEST(Distribution, EveryBlockGoesToOneProcessAndEveryLightIsSharedEvenly) {
  const std::vector<uint32_t> lights = BoxThenLeds();
  for (unsigned size : {1u, 2u, 3u, 8u}) {
    std::vector<unsigned> takers(lights.size(), 0);
    std::vector<std::vector<size_t>> perLight(size, std::vector<size_t>(1002, 0));
    std::vector<size_t> singles(size, 0);
    for (unsigned r = 0; r < size; ++r) {
      const std::vector<bool> mine = Process(r, size).Takes(lights);
      ASSERT_EQ(mine.size(), lights.size());
      for (size_t i = 0; i < lights.size(); ++i) {
        if (!mine[i]) continue;
        ++takers[i], ++perLight[r][lights[i]];
        singles[r] += lights[i] >= 2;
      }
    }
    EXPECT_TRUE(std::all_of(takers.begin(), takers.end(), [](unsigned t) { return t == 1; })) << size << " processes";
    for (uint32_t l : {0u, 1u}) {
      size_t least = SIZE_MAX, most = 0;
      for (unsigned r = 0; r < size; ++r) least = std::min(least, perLight[r][l]), most = std::max(most, perLight[r][l]);
      EXPECT_LE(most - least, 1u) << "light " << l << ", " << size << " processes";
    }
    // The single-block lights start at a hash of the light: binomial, so within 4 sigma of 1000/size.
    const double mean = 1000.0 / size, sigma = std::sqrt(1000.0 * (1.0 / size) * (1.0 - 1.0 / size));
    for (unsigned r = 0; r < size; ++r) EXPECT_NEAR(double(singles[r]), mean, 4 * sigma + 1e-9) << "rank " << r;
  }
}

// Three processes claim 500 chunks at once, each from its own thread and in its own order (forward, backward, a
// stride): every chunk goes to exactly one, the one whose claim won, and every process agrees on who holds what.
TEST(Distribution, EveryVertexChunkGoesToTheFirstProcessToClaimIt) {
  constexpr size_t kChunks = 500;
  constexpr unsigned kSize = 3;
  std::vector<std::atomic<int>> claims(kChunks);
  std::vector<Process> processes;
  for (unsigned r = 0; r < kSize; ++r) processes.emplace_back(r, kSize, &claims);
  std::vector<std::vector<size_t>> won(kSize);
  std::vector<std::thread> threads;
  for (unsigned r = 0; r < kSize; ++r)
    threads.emplace_back([&, r] {
      processes[r].OpenChunks(kChunks);
      for (size_t k = 0; k < kChunks; ++k) {
        const size_t c = r == 0 ? k : r == 1 ? kChunks - 1 - k : (k * 7) % kChunks;  // 7 is prime to 500
        if (processes[r].ClaimChunk(c)) won[r].push_back(c);
      }
    });
  for (std::thread& t : threads) t.join();
  for (const Process& p : processes) p.CloseChunks();
  std::vector<unsigned> takers(kChunks, 0);
  for (unsigned r = 0; r < kSize; ++r)
    for (size_t c : won[r]) {
      ++takers[c];
      for (const Process& p : processes) EXPECT_EQ(p.ChunkHolder(c), r) << "chunk " << c;
      EXPECT_TRUE(processes[r].HoldsChunk(c));
    }
  EXPECT_TRUE(std::all_of(takers.begin(), takers.end(), [](unsigned t) { return t == 1; }));
  // A process that claims again finds every chunk taken.
  for (size_t c = 0; c < kChunks; ++c) EXPECT_FALSE(processes[0].ClaimChunk(c));
}

}  // namespace
}  // namespace pb
