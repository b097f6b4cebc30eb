// Ctrl-C as a request to stop early with valid outputs. While an InterruptScope lives, the first SIGINT only sets
// a flag: long loops poll InterruptRequested() between units of work (a block of photons, a round, a chunk of a
// later round's vertices), finish the unit they are in, and the bake writes what it has; the handler says so on
// stderr at once. It then steps aside, so a second Ctrl-C ends the process at once (any output being written is a
// temporary file; the previous file stays intact).
#pragma once

namespace pb {

bool InterruptRequested();
// As a SIGINT would; for tests, and for callers that stop a bake for their own reasons.
void RequestInterrupt();

class InterruptScope {
 public:
  InterruptScope();  // installs the handler and clears any earlier request
  ~InterruptScope();  // restores the previous handler
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

 private:
  void (*previous_)(int);
};

}  // namespace pb
