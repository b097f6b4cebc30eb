// Progress of long stages on stderr, and the log of warnings. Thread-safe: workers call Advance.
// On a terminal a stage redraws one line at most 10 times a second; otherwise only its final line is printed.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace pb {

class Log {
 public:
  explicit Log(bool quiet);
  bool Quiet() const { return quiet_; }
  bool Interactive() const { return interactive_; }
  void Info(const std::string& line) const;
  void Warning(const std::string& line) const;

 private:
  bool quiet_;
  bool interactive_;
};

class Progress {
 public:
  Progress(const Log& log, std::string stage, uint64_t total);
  ~Progress();
  void Advance(uint64_t done);

 private:
  void Draw(uint64_t done, bool final);

  const Log& log_;
  std::string stage_;
  uint64_t total_;
  std::atomic<uint64_t> done_{0};
  std::mutex drawing_;
  std::chrono::steady_clock::time_point start_, lastDraw_;
};

}  // namespace pb
