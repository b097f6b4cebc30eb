#include "baker/runtime/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>

namespace pb {
namespace {

std::atomic<bool> requested{false};

// The held temporaries: a thread claims a slot, writes its path, then sets `holding`, which the handler reads.
constexpr size_t kSlotBytes = 4096;
char held[kMaxHeld][kSlotBytes];
std::atomic<bool> claimed[kMaxHeld], holding[kMaxHeld], folder[kMaxHeld];

// The scopes (main thread only): how deep, whether the first Ctrl-C is taken as a request yet, and the handler the
// outermost found.
int depth = 0;
bool started = false;
struct sigaction before{};

extern "C" void EndWithoutTemporaries(int signal) {
  RemoveHeldTemporaries();
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

// Said at once, so that a Ctrl-C during a stage that does not stop early (the estimate, the outputs) is not taken
// for ignored. write(2) is async-signal-safe; its result is of no use here.
constexpr char kSaid[] =
    "\nCtrl-C: tracing, the estimate and refinement stop, and the bake finishes with what it has (the vertices left "
    "at the fewest samples; in a later round, the round before's estimate; the mesh unrefined), writing every "
    "output; Ctrl-C again stops at once, removes what it was writing and leaves any earlier output as it was\n";

extern "C" void OnInterrupt(int) {
  requested.store(true, std::memory_order_relaxed);
  std::signal(SIGINT, EndWithoutTemporaries);  // the second Ctrl-C is the user's emergency exit
  [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, kSaid, sizeof(kSaid) - 1);
}

int Hold(const std::string& path, bool isFolder) {
  if (path.size() >= kSlotBytes) return -1;
  for (int slot = 0; slot < kMaxHeld; ++slot) {
    bool expected = false;
    if (!claimed[slot].compare_exchange_strong(expected, true)) continue;
    path.copy(held[slot], path.size());
    held[slot][path.size()] = '\0';
    folder[slot].store(isFolder);
    holding[slot].store(true);
    return slot;
  }
  return -1;
}

}  // namespace

int HoldTemporary(const std::string& path) { return Hold(path, false); }
int HoldCreatedFolder(const std::string& path) { return Hold(path, true); }

void ReleaseTemporary(int slot) {
  if (slot >= 0 && slot < kMaxHeld) holding[slot].store(false), claimed[slot].store(false);
}

void RemoveHeldTemporaries() {
  for (int slot = 0; slot < kMaxHeld; ++slot)
    if (holding[slot].load() && !folder[slot].load()) ::unlink(held[slot]);
  // A folder empties when the ones inside it are gone: passes until one removes nothing, in whatever slot order.
  bool removed[kMaxHeld] = {};
  for (bool progress = true; progress;) {
    progress = false;
    for (int slot = 0; slot < kMaxHeld; ++slot)
      if (!removed[slot] && holding[slot].load() && folder[slot].load() && ::rmdir(held[slot]) == 0)
        removed[slot] = progress = true;
  }
}

void RemoveTemporariesOnTermination() {
  std::signal(SIGTERM, EndWithoutTemporaries);
  std::signal(SIGINT, EndWithoutTemporaries);  // outside an InterruptScope, Ctrl-C ends the process at once
}

bool InterruptRequested() { return requested.load(std::memory_order_relaxed); }
void RequestInterrupt() { requested.store(true, std::memory_order_relaxed); }

InterruptScope::InterruptScope(Start start) {
  if (depth++ == 0) ::sigaction(SIGINT, nullptr, &before);
  if (start == Start::kNow && !started) {
    started = true;
    requested.store(false);
    std::signal(SIGINT, OnInterrupt);
  }
}

InterruptScope::~InterruptScope() {
  if (--depth > 0) return;
  if (started) ::sigaction(SIGINT, &before, nullptr);
  started = false;
  requested.store(false);
}

}  // namespace pb
