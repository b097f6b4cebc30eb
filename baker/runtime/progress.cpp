#include "baker/runtime/progress.h"

#include <fmt/core.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pb {

Log::Log(bool quiet, std::function<void(const std::string&)> listener)
    : quiet_(quiet), interactive_(!quiet && isatty(STDERR_FILENO)), listener_(std::move(listener)) {}

std::string TerminalSafe(const std::string& text) {
  std::string safe;
  safe.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    const bool c1 = c == 0xC2 && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
                    static_cast<unsigned char>(text[i + 1]) <= 0x9F;
    if ((c < 0x20 && c != '\n' && c != '\t') || c == 0x7F) {
      safe += fmt::format("\\x{:02x}", c);
    } else if (c1) {
      safe += fmt::format("\\u{:04x}", static_cast<unsigned char>(text[++i]));
    } else {
      safe += char(c);
    }
  }
  return safe;
}

void Log::Info(const std::string& line) const {
  const std::string safe = TerminalSafe(line);
  if (!quiet_) fmt::print(stderr, "{}\n", safe);
  Notify(safe);
}

void Log::Warning(const std::string& line) const {
  const std::string safe = TerminalSafe(line);
  fmt::print(stderr, "{}\n", safe);
  Notify(safe);
}

void Log::Warnings(const std::vector<std::string>& lines) const {
  constexpr size_t kShown = 10;
  for (size_t i = 0; i < lines.size() && i < kShown; ++i) Warning(lines[i]);
  if (lines.size() > kShown) Warning(fmt::format("... and {} more warnings", lines.size() - kShown));
}

Progress::Progress(const Log& log, std::string stage, uint64_t total)
    : log_(log), stage_(std::move(stage)), total_(total), start_(std::chrono::steady_clock::now()), lastDraw_(start_) {}

Progress::~Progress() {
  if (complete_) total_ = done_.load();  // the count was an upper bound; what was reached is all there was to do
  Draw(done_.load(), true);
  log_.Notify(stage_ + ": done");
}

void Progress::Complete() { complete_ = true; }

void Progress::Advance(uint64_t done) {
  const uint64_t now = done_.fetch_add(done) + done, steps = steps_.fetch_add(1) + 1;
  std::unique_lock lock(drawing_, std::try_to_lock);  // a busy drawer means someone else is printing.
  if (!lock.owns_lock()) return;
  const auto t = std::chrono::steady_clock::now();
  ForetellLength(now, steps, t);
  if (log_.Quiet()) return;
  const auto interval = log_.Interactive() ? std::chrono::milliseconds(100) : std::chrono::milliseconds(5000);
  if (t - lastDraw_ < interval) return;
  lastDraw_ = t;
  Draw(now, false);
}

namespace {

constexpr double kLongWork = 60;  // [s]: work that would take longer is foretold

}  // namespace

// The staircase's estimate at --quality production, 1,024-vertex steps on 2 cores, had said "about 4 min 18 s" from
// one step ended in 1.1 s, the other nearly; it took 100 s.
void Progress::ForetellLength(uint64_t done, uint64_t steps, std::chrono::steady_clock::time_point now) {
  const double seconds = std::chrono::duration<double>(now - start_).count();
  if (foretold_ || seconds < 1 || done == 0 || done >= total_) return;
  const size_t workers = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  if (steps < 4 * std::max<size_t>(workers, 1)) return;
  const double all = std::min(seconds * double(total_) / double(done), endsWithin_);
  if (all <= kLongWork) return;
  foretold_ = true;
  if (log_.Interactive()) fmt::print(stderr, "\n");  // below the progress line being drawn
  log_.Warning(fmt::format("{}: warning: about {} in all at the rate of its first {:.1f} s ({} of {}); the time left "
                           "shows as it goes", stage_, DurationText(all), seconds, done, total_));
}

std::string DurationText(double seconds) {
  const auto s = uint64_t(std::llround(std::clamp(seconds, 0.0, 1e15)));
  if (s < 60) return fmt::format("{} s", s);
  if (s < 3600) return fmt::format("{} min {:02} s", s / 60, s % 60);
  return fmt::format("{} h {:02} min", s / 3600, (s % 3600) / 60);
}

std::vector<std::string> LongWorkWarnings(const std::string& option, const std::string& what, double points,
                                          double secondsPerPoint, const std::function<std::string(double)>& remedy) {
  const double seconds = points * secondsPerPoint;
  if (!(seconds > kLongWork)) return {};
  return {fmt::format("{}: warning: {}, about {} at the {:.3g} ms a point of the estimate took (progress shows the "
                      "time left); {}", option, what, DurationText(seconds), 1e3 * secondsPerPoint, remedy(seconds))};
}

namespace {

// 1234567 -> "1.23 M".
std::string Count(double x) {
  if (x >= 1e9) return fmt::format("{:.3g} G", x / 1e9);
  if (x >= 1e6) return fmt::format("{:.3g} M", x / 1e6);
  if (x >= 1e3) return fmt::format("{:.3g} k", x / 1e3);
  return fmt::format("{:.3g}", x);
}

}  // namespace

void Progress::Draw(uint64_t done, bool final) {
  if (log_.Quiet() || (!final && done >= total_ && !log_.Interactive())) return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double percent = total_ ? std::min(100.0, 100.0 * double(done) / double(total_)) : 100.0;
  const double rate = seconds > 0 ? double(done) / seconds : 0.0;
  std::string tail = fmt::format("{:7.2f} s  {:>8}/s", seconds, Count(rate));
  if (!final && seconds >= 0.1 && rate > 0 && done < total_)
    tail += fmt::format("  {} left", DurationText(std::min(double(total_ - done) / rate, endsWithin_ - seconds)));
  fmt::print(stderr, "{}  {:<22} {:5.1f}%  {:>12} / {:<12} {:<40}{}", log_.Interactive() ? "\r" : "", stage_,
             percent, std::min(done, total_ ? total_ : done), total_, tail, final || !log_.Interactive() ? "\n" : "");
  std::fflush(stderr);
}

WorkProgress ShowProgress(const Log* log, const char* stage, std::unique_ptr<Progress>& progress) {
  if (log == nullptr) return {};
  return [log, stage, &progress](uint64_t done, uint64_t total) {
    if (!progress) progress = std::make_unique<Progress>(*log, stage, total);
    progress->Advance(done);
  };
}

}  // namespace pb
