// A run's outputs as one transaction (docs/bake.md, "Exit status"): readers never see a half-written file, and a run
// that fails anywhere leaves every earlier output as it was.
//
// OutputFiles::Write stages one output: its bytes go to a new temporary file "<path>.tmp-<pid>-<n>" in the
// output's own directory, created with O_CREAT | O_EXCL | O_NOFOLLOW (a file or symlink planted at that name is
// never followed or overwritten), written through the descriptor and fsync'ed. Commit() checks that every staged
// file can replace its path (its temporary still there; the path not a folder, in a folder still writable), then
// renames each over its path, in the order staged, and syncs their directories: a commit that fails for a reason
// it can see fails before any output is replaced. A process killed
// between two renames (microseconds) leaves the outputs staged before new and the rest old; the bake stages its
// photon file, maps, preview, then -o, then --report, so a new report (or, without one, a new -o) means all are
// new. SIGTERM and a second Ctrl-C remove the temporaries, and the folders MakeDirectory created that are left empty,
// before the process ends (HoldTemporary, HoldCreatedFolder); the next run
// removes those a killed run left (RemoveStaleTemporaries) and says so. Destroying
// an OutputFiles that was not committed removes its temporaries, and the folders MakeDirectory created that are
// still empty. Write makes its file's folder again where it has gone since the run began (a second run that
// created the same --maps folder failed and removed it while it was empty). An InputError names the path that failed.
//
// Fault injection (tests/tools/full_disk_test.cpp): with the environment variable PB_FAIL_WRITES_AFTER=BYTES, the
// process's output writes fail with ENOSPC ("No space left on device") once BYTES have been written in all, as a
// disk that fills at that byte would; with PB_PAUSE_BEFORE_COMMIT_MS=MS, Commit waits that long with every output
// staged before it renames them (tests/tools/full_disk_test.cpp sends SIGTERM then).
#pragma once

#include <functional>
#include <mutex>
#include <ostream>
#include <string>
#include <vector>

namespace pb {

class OutputFiles {
 public:
  OutputFiles() = default;
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;
  ~OutputFiles();

  // Stages `path`; safe to call from several threads at once.
  void Write(const std::string& path, const std::function<void(std::ostream&)>& write);
  // Creates the folder `path` and any missing parents (--maps DIR). If the run is not committed, the folders it
  // created are removed again when they are still empty. InputError naming `path` when it cannot be made.
  void MakeDirectory(const std::string& path);
  // Renames every staged file into place.
  void Commit();

 private:
  struct Staged {
    std::string temporary, path;
    int held = -1;  // its slot among the temporaries a signal removes (baker/runtime/interrupt.h)
  };
  std::mutex mutex_;
  std::vector<Staged> staged_;
  struct Created {
    std::string path;
    int held = -1;  // its slot among the folders a signal removes
  };
  std::vector<Created> createdDirectories_;  // outermost first
};

// Removes the temporaries "<name>.tmp-<pid>-<n>" in `directory` that a process no longer running here left (it
// was killed before it could remove them), for the output names `isOutput` accepts; returns the paths removed, with
// the pid of the run that left each. A temporary of a process that still runs is left alone (as is one of a
// process on another machine sharing the folder, when its pid is in use here).
std::vector<std::pair<std::string, long>> RemoveStaleTemporaries(
    const std::string& directory, const std::function<bool(const std::string& name)>& isOutput);

// One file as a transaction of its own.
void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// Throws an InputError naming `path` unless it can be an output: its directory exists and is writable, and
// nothing but a regular file is there now (not a directory, a device such as /dev/null, or a FIFO). Called
// before long work, so that a typo in an output path fails in a second, not after the bake.
void RequireWritableLocation(const std::string& path);

// Throws an InputError when two of `outputs`, or an output and one of `inputs`, name the same file (compared
// after resolving ".", "..", symlinks and hard links). Empty paths are skipped.
void RequireDistinctFiles(const std::vector<std::pair<std::string, std::string>>& outputs,
                          const std::vector<std::pair<std::string, std::string>>& inputs);

}  // namespace pb
