// bake-mpi: bake shared among the processes of `mpirun -np N bake-mpi SCENE ...` (baker/distribution.h), with bake's
// options. Rank 0 writes what bake would write, the same bytes; the other ranks trace their share of the photons.
// The only file that includes MPI.
// Exit status as bake's: 0, 1 for bad input (reported once, by rank 0), 2 for a bad command line. A rank that dies
// ends the job: mpirun kills the others, names the rank and exits non-zero; rank 0 writes its outputs only after
// every photon is traced, so an earlier output survives.
#include <mpi.h>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <csignal>
#include <cstring>
#include <mutex>
#include <span>
#include <type_traits>
#include <vector>

#include <unistd.h>

#include "baker/runtime/interrupt.h"
#include "baker/bake_run.h"
#include "baker/distribution.h"
#include "baker/runtime/progress.h"
#include "mesh/errors.h"
#include "tools/bake_cli.h"
#include "tools/cli_options.h"

namespace pb {
namespace {

static_assert(std::is_trivially_copyable_v<TraceStats> && std::is_trivially_copyable_v<BlockRange> &&
              std::is_trivially_copyable_v<PhotonHit>, "blocks travel as bytes");

// Appends the bytes of `value`, or reads them at `at`.
template <typename T>
void Put(std::vector<char>& bytes, const T* value, size_t count = 1) {
  const char* p = reinterpret_cast<const char*>(value);
  bytes.insert(bytes.end(), p, p + sizeof(T) * count);
}
template <typename T>
void Get(const std::vector<char>& bytes, size_t& at, T* value, size_t count = 1) {
  PB_CHECK(at + sizeof(T) * count <= bytes.size(), "a rank's blocks arrive whole");
  std::memcpy(value, bytes.data() + at, sizeof(T) * count);
  at += sizeof(T) * count;
}

std::vector<char> Pack(const std::vector<TracedBlock>& blocks) {
  std::vector<char> bytes;
  for (const TracedBlock& b : blocks) {
    const uint64_t hits = b.hits.size();
    Put(bytes, &b.item), Put(bytes, &b.range), Put(bytes, &b.stats), Put(bytes, &hits);
    Put(bytes, b.hits.data(), b.hits.size());
  }
  return bytes;
}

void Unpack(const std::vector<char>& bytes, std::vector<TracedBlock>& into) {
  for (size_t at = 0; at < bytes.size();) {
    TracedBlock& b = into.emplace_back();
    uint64_t hits = 0;
    Get(bytes, at, &b.item), Get(bytes, at, &b.range), Get(bytes, at, &b.stats), Get(bytes, at, &hits);
    b.hits.resize(hits);
    Get(bytes, at, b.hits.data(), hits);
  }
}

class MpiDistribution final : public Distribution {
 public:
  MpiDistribution() {
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    rank_ = unsigned(rank), size_ = unsigned(size);
  }
  unsigned Rank() const override { return rank_; }
  unsigned Size() const override { return size_; }

  std::vector<bool> Agree(bool ready) const override {
    agreed_ = true;
    const int mine = ready ? 1 : 0;
    std::vector<int> all(size_);
    MPI_Allgather(&mine, 1, MPI_INT, all.data(), 1, MPI_INT, MPI_COMM_WORLD);
    return {all.begin(), all.end()};
  }

  // Rank r > 0 sends rank 0 its blocks' bytes; rank 0 takes them rank by rank and sends every process all of them.
  std::vector<TracedBlock> Gather(std::vector<TracedBlock> mine) const override {
    std::vector<char> all;
    if (Root()) {
      all = Pack(mine);
      for (unsigned r = 1; r < size_; ++r) {
        const std::vector<char> theirs = Receive(r);
        all.insert(all.end(), theirs.begin(), theirs.end());
      }
      for (unsigned r = 1; r < size_; ++r) Send(all, r);
    } else {
      Send(Pack(mine), 0);
      all = Receive(0);
    }
    std::vector<TracedBlock> blocks;
    Unpack(all, blocks);
    return blocks;
  }

  void SumOnAll(std::span<int64_t> values) const override {
    for (size_t at = 0; at < values.size(); at += kChunk) {
      const int count = int(std::min<size_t>(kChunk, values.size() - at));
      MPI_Allreduce(MPI_IN_PLACE, values.data() + at, count, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
    }
  }

  void Broadcast(std::span<std::byte> bytes) const override {
    for (size_t at = 0; at < bytes.size(); at += kChunk)
      MPI_Bcast(bytes.data() + at, int(std::min<size_t>(kChunk, bytes.size() - at)), MPI_BYTE, 0, MPI_COMM_WORLD);
  }

  // The claims live in a window of one int per chunk on rank 0 (0: free, r + 1: taken by rank r), which every rank
  // compares and swaps into, one chunk at a time, under a lock of its own (MPI_THREAD_SERIALIZED).
  void OpenChunks(size_t chunks) const override {
    const MPI_Aint bytes = Root() ? MPI_Aint(chunks * sizeof(int)) : 0;
    MPI_Win_allocate(bytes, sizeof(int), MPI_INFO_NULL, MPI_COMM_WORLD, &claims_, &window_);
    if (Root()) std::fill(claims_, claims_ + chunks, 0);
    chunks_ = chunks;
    MPI_Win_lock_all(0, window_);
    if (Root()) MPI_Win_sync(window_);  // rank 0's stores are the window's
    MPI_Barrier(MPI_COMM_WORLD);        // every claim is free before any is taken
  }
  bool ClaimChunk(size_t c) const override {
    const std::lock_guard<std::mutex> lock(mpi_);
    const int mine = int(rank_) + 1, free = 0;
    int was = -1;
    MPI_Compare_and_swap(&mine, &free, &was, MPI_INT, 0, MPI_Aint(c), window_);
    MPI_Win_flush(0, window_);
    return was == free;
  }
  void CloseChunks() const override {
    MPI_Barrier(MPI_COMM_WORLD);        // every claim made (each flushed)
    if (Root()) MPI_Win_sync(window_);  // and seen in rank 0's memory
    MPI_Win_unlock_all(window_);
    std::vector<int> taken(chunks_, 0);
    if (Root()) std::copy(claims_, claims_ + chunks_, taken.begin());
    Broadcast(std::as_writable_bytes(std::span(taken)));
    MPI_Win_free(&window_);
    holders_.resize(chunks_);
    for (size_t c = 0; c < chunks_; ++c) holders_[c] = taken[c] > 0 ? unsigned(taken[c] - 1) : kNobody;
  }

  // Rank r > 0 sends the chunks it HoldsChunk, in order; rank 0 puts them in place.
  void GatherChunks(std::span<std::byte> items, size_t itemBytes, size_t chunk) const override {
    const size_t chunkBytes = itemBytes * chunk, chunks = (items.size() + chunkBytes - 1) / chunkBytes;
    const auto bytesOf = [&](size_t c) { return items.subspan(c * chunkBytes, std::min(chunkBytes, items.size() - c * chunkBytes)); };
    if (!Root()) {
      std::vector<char> mine;
      for (size_t c = 0; c < chunks; ++c)
        if (HoldsChunk(c)) Put(mine, bytesOf(c).data(), bytesOf(c).size());
      return Send(mine, 0);
    }
    for (unsigned r = 1; r < size_; ++r) {
      const std::vector<char> theirs = Receive(r);
      size_t at = 0;
      for (size_t c = 0; c < chunks; ++c)
        if (ChunkHolder(c) == r) Get(theirs, at, bytesOf(c).data(), bytesOf(c).size());
    }
  }

 private:
  static constexpr uint64_t kChunk = 1u << 30;  // elements per message, below MPI's int counts
  static constexpr int kSizeTag = 1, kBytesTag = 2;

  // Bytes to or from rank `r`: their size, then messages of at most kChunk.
  static void Send(const std::vector<char>& bytes, unsigned r) {
    const uint64_t size = bytes.size();
    MPI_Send(&size, 1, MPI_UINT64_T, int(r), kSizeTag, MPI_COMM_WORLD);
    for (uint64_t at = 0; at < size; at += kChunk)
      MPI_Send(bytes.data() + at, int(std::min<uint64_t>(kChunk, size - at)), MPI_BYTE, int(r), kBytesTag, MPI_COMM_WORLD);
  }
  static std::vector<char> Receive(unsigned r) {
    uint64_t size = 0;
    MPI_Recv(&size, 1, MPI_UINT64_T, int(r), kSizeTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    std::vector<char> bytes(size);
    for (uint64_t at = 0; at < size; at += kChunk)
      MPI_Recv(bytes.data() + at, int(std::min<uint64_t>(kChunk, size - at)), MPI_BYTE, int(r), kBytesTag, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
    return bytes;
  }
  unsigned rank_ = 0, size_ = 1;
  mutable MPI_Win window_ = MPI_WIN_NULL;
  mutable int* claims_ = nullptr;  // rank 0's window
  mutable size_t chunks_ = 0;
  mutable std::mutex mpi_;  // a rank's threads claim one at a time
};

// mpirun ends every rank with SIGTERM when it is interrupted (Ctrl-C) or when a rank fails. Rank 0 says so, with
// write(2), which a signal handler may call; no output has been renamed into place, so an earlier one survives.
constexpr char kEnded[] =
    "bake-mpi: stopped by mpirun (Ctrl-C, or another rank failed): no output written, any earlier output is left as "
    "it was\n";
// A rank that has its exit status and has said why (a bad option, which every rank meets) waits in MPI_Finalize:
// when mpirun ends the job for another rank that exited first, it exits quietly with it. -1 before.
volatile std::sig_atomic_t endedWith = -1;
void EndedByMpirun(int) {
  if (endedWith >= 0) _exit(endedWith);
  pb::RemoveHeldTemporaries();
  [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, kEnded, sizeof kEnded - 1);
  _exit(1);
}
void SayWhenMpirunEndsTheJob(bool root) {
  struct sigaction action{};
  action.sa_handler = root ? EndedByMpirun : SIG_DFL;
  sigemptyset(&action.sa_mask);
  sigaction(SIGTERM, &action, nullptr);
}

// This rank's failure, said once: by rank 0, or by this rank when rank 0 was ready and this rank was not (a file
// that only this rank cannot read). 1.
int Failed(const std::string& message, const MpiDistribution& d) {
  const bool mine = !d.Agreed();  // this rank failed before every rank said it was ready
  const std::vector<bool> ready = mine ? d.Agree(false) : std::vector<bool>(d.Size(), true);
  if (d.Root() || (mine && ready[0]))
    fmt::print(stderr, "{}{}\n", d.Root() ? "" : fmt::format("rank {}: ", d.Rank()), TerminalSafe(message));
  return 1;
}

// Runs this rank's part; 0, or 1 after a failure, caught as `bake` catches it (tools/cli_options.h: RunTool), so
// that the outputs' temporaries are removed as the stack unwinds and no rank ends in std::terminate.
int Run(const tools::BakeCommandLine& c, const MpiDistribution& d) {
  const Log log(c.options.quiet || !d.Root());
  try {
    if (d.Root())
      BakeAndSummarise(c.options, log, &d);
    else
      TraceShareOfBake(c.options, log, d);
    return 0;
  } catch (const InputError& e) {
    return Failed(e.what(), d);
  } catch (const std::bad_alloc&) {
    return Failed("error: out of memory; nothing was written", d);
  } catch (const std::exception& e) {  // a library's own exception that no stage turned into an InputError
    return Failed(fmt::format("error: {}", e.what()), d);
  }
}

}  // namespace
}  // namespace pb

int main(int argc, char** argv) {
  // The estimate's threads claim vertex chunks (MpiDistribution::ClaimChunk), one at a time under a lock.
  int provided = MPI_THREAD_SINGLE;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
  if (provided < MPI_THREAD_SERIALIZED) {
    fmt::print(stderr, "bake-mpi: this MPI cannot be called from more than one thread (MPI_THREAD_SERIALIZED)\n");
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
  const pb::MpiDistribution distribution;
  pb::SayWhenMpirunEndsTheJob(distribution.Root());
  CLI::App app{"bake-mpi: bake, shared among the processes of mpirun (photonbake)"};
  pb::tools::BakeCommandLine c;
  pb::tools::DefineBakeCommandLine(app, c);
  int status = 0;
  try {
    app.parse(argc, argv);
    pb::tools::ApplyBakeCommandLine(app, c);
    status = pb::Run(c, distribution);
  } catch (const CLI::ParseError& e) {
    status = distribution.Root() ? (app.exit(e) == 0 ? 0 : 2) : (e.get_exit_code() == 0 ? 0 : 2);
  } catch (const pb::InputError& e) {  // a bad option value: every rank sees it, rank 0 says it
    if (distribution.Root()) fmt::print(stderr, "{}\n", pb::TerminalSafe(e.what()));
    status = 2;
  } catch (const std::exception& e) {
    if (distribution.Root()) fmt::print(stderr, "error: {}\n", pb::TerminalSafe(e.what()));
    status = 2;
  }
  pb::endedWith = status;
  MPI_Finalize();
  return status;
}
