#include "baker/progress.h"

#include <fmt/core.h>
#include <unistd.h>

#include <cstdio>

namespace pb {

Log::Log(bool quiet) : quiet_(quiet), interactive_(!quiet && isatty(STDERR_FILENO)) {}

void Log::Info(const std::string& line) const {
  if (!quiet_) fmt::print(stderr, "{}\n", line);
}

void Log::Warning(const std::string& line) const { fmt::print(stderr, "{}\n", line); }

Progress::Progress(const Log& log, std::string stage, uint64_t total)
    : log_(log), stage_(std::move(stage)), total_(total), start_(std::chrono::steady_clock::now()), lastDraw_(start_) {}

Progress::~Progress() { Draw(done_.load(), true); }

void Progress::Advance(uint64_t done) {
  const uint64_t now = done_.fetch_add(done) + done;
  if (!log_.Interactive()) return;
  std::unique_lock lock(drawing_, std::try_to_lock);  // a busy drawer means someone else is printing.
  if (!lock.owns_lock()) return;
  const auto t = std::chrono::steady_clock::now();
  if (t - lastDraw_ < std::chrono::milliseconds(100)) return;
  lastDraw_ = t;
  Draw(now, false);
}

void Progress::Draw(uint64_t done, bool final) {
  if (log_.Quiet() || (!final && !log_.Interactive())) return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double percent = total_ ? 100.0 * double(done) / double(total_) : 100.0;
  fmt::print(stderr, "{}  {:<22} {:5.1f}%  {:>12} / {:<12} {:7.2f} s{}", log_.Interactive() ? "\r" : "", stage_,
             percent, done, total_, seconds, final ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace pb
