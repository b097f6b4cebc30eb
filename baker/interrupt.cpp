#include "baker/interrupt.h"

#include <atomic>
#include <csignal>

namespace pb {
namespace {

std::atomic<bool> requested{false};

extern "C" void OnInterrupt(int) {
  requested.store(true, std::memory_order_relaxed);
  std::signal(SIGINT, SIG_DFL);  // the second Ctrl-C is the user's emergency exit
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
