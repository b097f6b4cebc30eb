// Times pipeline stages in wall-clock seconds and records them, in order, as (name, seconds) pairs. A stage run
// again (a round of a progressive bake) adds to its first record. Also the wall time since the clock was made.
#pragma once

#include <chrono>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace pb {

class StageClock {
 public:
  explicit StageClock(std::vector<std::pair<std::string, double>>& record) : record_(record) {}
  // A clock that keeps its record to itself (tests and tools that do not report stage times).
  StageClock() : record_(own_) {}
  StageClock(const StageClock&) = delete;
  // Seconds since the clock was made.
  double Elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - made_).count(); }
  // Seconds recorded under `name` so far; 0 if none.
  double Seconds(const std::string& name) const {
    for (const auto& [recorded, total] : record_)
      if (recorded == name) return total;
    return 0;
  }
  StageClock& operator=(const StageClock&) = delete;

  // Runs `stage` and records its time under `name`; returns what it returns.
  template <typename F>
  auto Time(const std::string& name, F&& stage) {
    const auto start = std::chrono::steady_clock::now();
    auto finish = [&] {
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      for (auto& [recorded, total] : record_)
        if (recorded == name) return void(total += seconds);
      record_.emplace_back(name, seconds);
    };
    if constexpr (std::is_void_v<decltype(stage())>) {
      stage();
      finish();
    } else {
      auto result = stage();
      finish();
      return result;
    }
  }

 private:
  std::chrono::steady_clock::time_point made_ = std::chrono::steady_clock::now();
  std::vector<std::pair<std::string, double>> own_;
  std::vector<std::pair<std::string, double>>& record_;
};

}  // namespace pb
