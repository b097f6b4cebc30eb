// Progress of long stages on stderr, and the log of warnings. Thread-safe: workers call Advance.
// Each line gives the stage, its fraction done, the count, the seconds so far, the rate (per second) and, once a
// tenth of a second has passed, the time left at that rate. On a terminal a stage redraws one line at most 10
// times a second; otherwise (a log file, CI) it prints a line every 5 seconds, so that no long stage is silent,
// and its final line. A stage that finishes before its count (coarsening stops when no collapse is left within
// the tolerance) calls Complete(), so that its last line reads 100%. A stage that would take over a minute at its
// rate of its first second says so once, as a warning (quiet or not): the option that multiplies its work (photons,
// reference paths, preview size) can be changed before the time is spent. The rate is read once 4 W steps (calls
// of Advance) have ended, W the threads allowed: each worker has a step in flight when the first ones end, and the
// first k steps' rate reads about (k + W / 2) / k times too slow.
#pragma once

#include <atomic>
#include <cmath>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "mesh/work_progress.h"

namespace pb {

// "42 s", "3 min 20 s", "2 h 05 min".
std::string DurationText(double seconds);

// The warning, before it starts, for work an option multiplies when it would take over a minute: "OPTION: warning:
// WHAT, about T at the X ms a point of the estimate took (progress shows the time left); REMEDY", with `remedy`
// told the predicted seconds. None within a minute.
std::vector<std::string> LongWorkWarnings(const std::string& option, const std::string& what, double points,
                                          double secondsPerPoint, const std::function<std::string(double)>& remedy);

// `text` safe to print on a terminal: control characters other than a newline or tab (ESC, BEL, ...; C1's CSI as
// UTF-8) written as \xNN or \uNNNN, so that a light named with escape codes cannot retitle or clear the terminal.
std::string TerminalSafe(const std::string& text);

// Info lines go to stderr unless quiet, warnings always, both TerminalSafe; both also to `listener` when given (an application's own
// log, or a test that acts at a point of the bake), which hears "STAGE: done" too as each Progress ends.
class Log {
 public:
  explicit Log(bool quiet, std::function<void(const std::string&)> listener = nullptr);
  bool Quiet() const { return quiet_; }
  bool Interactive() const { return interactive_; }
  void Info(const std::string& line) const;
  void Warning(const std::string& line) const;
  // The first 10 of `lines` as warnings, then how many more there are (the report keeps them all).
  void Warnings(const std::vector<std::string>& lines) const;
  void Notify(const std::string& line) const {  // to the listener alone
    if (listener_) listener_(line);
  }

 private:
  bool quiet_;
  bool interactive_;
  std::function<void(const std::string&)> listener_;
};

class Progress {
 public:
  Progress(const Log& log, std::string stage, uint64_t total);
  ~Progress();
  void Advance(uint64_t done);
  // The stage's work is done before its count (an upper bound) was reached: the count reached becomes the total,
  // and the last line reads 100%.
  void Complete();
  // The stage stops within `seconds` of its start whatever its count (a pass that fills the time a budget left):
  // the time left shown is at most what remains of them, and its length is foretold only past a minute of them.
  void EndsWithin(double seconds) { endsWithin_ = seconds; }

 private:
  void Draw(uint64_t done, bool final);
  void ForetellLength(uint64_t done, uint64_t steps, std::chrono::steady_clock::time_point now);

  const Log& log_;
  std::string stage_;
  uint64_t total_;
  std::atomic<uint64_t> done_{0}, steps_{0};
  std::mutex drawing_;
  std::chrono::steady_clock::time_point start_, lastDraw_;
  std::atomic<bool> complete_{false};
  bool foretold_ = false;  // the warning of a long stage was given
  double endsWithin_ = INFINITY;  // [s] from start_
};

// A stage's progress on `log` as `stage`, for a library's callback (mesh/work_progress.h), from its first report
// (when the total is known); `progress` holds it and ends it when it goes (or is reset). Nothing without a log.
WorkProgress ShowProgress(const Log* log, const char* stage, std::unique_ptr<Progress>& progress);

}  // namespace pb
