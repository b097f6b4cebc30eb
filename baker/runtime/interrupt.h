// Ctrl-C as a request to stop early with valid outputs. While an InterruptScope lives, the first SIGINT only sets
// a flag: long loops poll InterruptRequested() between units of work (a block of photons, a round, a chunk of a
// later round's vertices), finish the unit they are in, and the bake writes what it has; the handler says so on
// stderr at once. It then steps aside, so a second Ctrl-C ends the process at once (any output being written is a
// temporary file, removed as the process ends; the previous file stays intact).
#pragma once

#include <string>

namespace pb {

bool InterruptRequested();
// As a SIGINT would; for tests, and for callers that stop a bake for their own reasons.
void RequestInterrupt();

// The temporary outputs the process holds (baker/files/atomic_file.h), removed when a signal ends it: SIGTERM (what
// timeout, systemd and CI send; handled from RemoveTemporariesOnTermination on) and the second Ctrl-C. A fixed table
// of kMaxHeld paths that the handler reads with unlink(2), which a signal handler may call; a path past the table,
// or longer than a slot, is left for the next run to remove (RemoveStaleTemporaries).
inline constexpr int kMaxHeld = 256;
int HoldTemporary(const std::string& path);  // its slot, or -1
void ReleaseTemporary(int slot);             // -1: nothing
// Unlinks every held temporary; async-signal-safe.
void RemoveHeldTemporaries();
// From here on, SIGTERM, and Ctrl-C outside an InterruptScope, remove the held temporaries and then end the process
// as they would have (exit by the signal): every earlier output is as it was, and no temporary is left.
void RemoveTemporariesOnTermination();

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
