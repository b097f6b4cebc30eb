// How a distributed bake shares its work (baker/distribution.h), without MPI: every work item and every vertex
// chunk goes to exactly one process, and each process gets the same number of every light's blocks, within one
// (on a work list that interleaves two lights as the box's does, with single-block lights after them), and of
// the vertex chunks. The bytes of a distributed bake are tested with mpirun in tests/tools/bake_mpi_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "baker/distribution.h"

namespace pb {
namespace {

// A process `rank` of `size`, whose exchanges are never called here.
class Process final : public Distribution {
 public:
  Process(unsigned rank, unsigned size) : rank_(rank), size_(size) {}
  unsigned Rank() const override { return rank_; }
  unsigned Size() const override { return size_; }
  std::vector<bool> Agree(bool) const override { return {}; }
  void SumOnAll(std::span<int64_t>) const override {}
  void Broadcast(std::span<std::byte>) const override {}
  void GatherChunks(std::span<std::byte>, size_t, size_t) const override {}
  std::vector<TracedBlock> Gather(std::vector<TracedBlock> mine) const override { return mine; }

 private:
  unsigned rank_, size_;
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

TEST(Distribution, VertexChunksGoToOneProcessEachInTurn) {
  for (unsigned size : {1u, 2u, 3u}) {
    for (size_t c = 0; c < 10; ++c) {
      unsigned takers = 0;
      for (unsigned r = 0; r < size; ++r) takers += Process(r, size).TakesChunk(c);
      EXPECT_EQ(takers, 1u);
      EXPECT_TRUE(Process(unsigned(c % size), size).TakesChunk(c));
    }
  }
}

}  // namespace
}  // namespace pb
