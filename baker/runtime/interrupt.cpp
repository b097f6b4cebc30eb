#include "baker/runtime/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>

namespace pb {
namespace {

std::atomic<bool> requested{false};

// Said at once, so that a Ctrl-C during a stage that does not stop early (the estimate, the outputs) is not taken
// for ignored. write(2) is async-signal-safe; its result is of no use here.
constexpr char kSaid[] =
    "\nCtrl-C: tracing stops and the bake finishes with the photons it has (estimate and outputs; in a later round "
    "of --target-noise, with the round before's estimate); Ctrl-C again stops at once and leaves any earlier output "
    "as it was\n";

extern "C" void OnInterrupt(int) {
  requested.store(true, std::memory_order_relaxed);
  std::signal(SIGINT, SIG_DFL);  // the second Ctrl-C is the user's emergency exit
  [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, kSaid, sizeof(kSaid) - 1);
}

}  // namespace

bool InterruptRequested() { return requested.load(std::memory_order_relaxed); }
void RequestInterrupt() { requested.store(true, std::memory_order_relaxed); }

InterruptScope::InterruptScope() {
  requested.store(false);
  previous_ = std::signal(SIGINT, OnInterrupt);
}

InterruptScope::~InterruptScope() {
  std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_);
  requested.store(false);
}

}  // namespace pb
