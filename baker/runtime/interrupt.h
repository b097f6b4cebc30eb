// Ctrl-C as a request to stop early with valid outputs. While an InterruptScope lives, the first SIGINT only sets
// a flag: long loops poll InterruptRequested() between units of work (a block of photons, a round, a chunk of a
// later round's vertices, a pass of refinement), finish the unit they are in, and the bake writes what it has; the
// handler says so on stderr at once. It then steps aside, so a second Ctrl-C ends the process at once (any output
// being written is a temporary file, removed as the process ends with the folders the run created; the previous
// file stays intact).
#pragma once

#include <string>

namespace pb {

bool InterruptRequested();
// As a SIGINT would; for tests, and for callers that stop a bake for their own reasons.
void RequestInterrupt();

// The temporary outputs the process holds (baker/files/atomic_file.h), and the folders it created for them, removed
// when a signal ends it: SIGTERM (what timeout, systemd and CI send; handled from RemoveTemporariesOnTermination on)
// and the second Ctrl-C. A fixed table of kMaxHeld paths that the handler reads with unlink(2) and rmdir(2), which a
// signal handler may call; a temporary past the table, or longer than a slot, is left for the next run to remove
// (RemoveStaleTemporaries), a folder past it stays.
inline constexpr int kMaxHeld = 256;
int HoldTemporary(const std::string& path);     // its slot, or -1
int HoldCreatedFolder(const std::string& path);  // its slot, or -1; removed only while it is empty
void ReleaseTemporary(int slot);                // either kind; -1: nothing
// Unlinks every held temporary, then removes every held folder left empty, the innermost first;
// async-signal-safe.
void RemoveHeldTemporaries();
// From here on, SIGTERM, and Ctrl-C outside an InterruptScope, remove the held temporaries and then end the process
// as they would have (exit by the signal): every earlier output is as it was, and no temporary is left.
void RemoveTemporariesOnTermination();

// Scopes nest: only the outermost installs and restores. A bake's run holds one from before its scene is read
// (kFromInnerScope: Ctrl-C still ends the process at once, as there is nothing yet to finish with) to its outputs'
// commit; tracing opens an inner scope (kNow), from which on the first Ctrl-C asks every later stage to finish, up
// to the commit.
class InterruptScope {
 public:
  enum class Start { kNow, kFromInnerScope };
  // With kNow, outermost or under a kFromInnerScope scope not yet started: installs the handler and clears any
  // earlier request.
  explicit InterruptScope(Start start = Start::kNow);
  ~InterruptScope();  // the outermost restores the previous handler and clears the request
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
};

}  // namespace pb
