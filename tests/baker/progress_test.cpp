// The progress of long stages (baker/runtime/progress.h): a stage that would take over a minute at the rate of its
// first second says so once, before the time is spent (issue 39: work that multiplies, like --photons or
// --reference, ran for minutes with only the progress line's time left to say so).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "baker/runtime/progress.h"

namespace pb {
namespace {

// A stage of `total` steps' worth on `workers` threads: `steps` steps of `firstStep` ended at once, a pause of over a
// second, one more step, then one more (a warning is said once), then the rest.
// With `endsWithin`, the stage stops within that many seconds whatever its count.
std::vector<std::string> Heard(uint64_t total, uint64_t firstStep, size_t workers = 1, int steps = 3,
                               double endsWithin = INFINITY) {
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, workers);
  std::vector<std::string> heard;
  const Log log(true, [&](const std::string& line) { heard.push_back(line); });
  {
    Progress progress(log, "trace photons", total);
    progress.EndsWithin(endsWithin);
    for (int k = 0; k < steps; ++k) progress.Advance(firstStep);
    std::this_thread::sleep_for(std::chrono::milliseconds(1050));
    progress.Advance(firstStep);
    progress.Advance(firstStep);  // said once, not at every step
    progress.Advance(total - uint64_t(steps + 2) * firstStep);
  }
  return heard;
}

TEST(Progress, AStageOverAMinuteAtItsFirstSecondsRateSaysSoOnce) {
  // 4 of 1,000 in over a second on one thread: about 260 s in all.
  const std::vector<std::string> slow = Heard(1000, 1);
  ASSERT_EQ(slow.size(), 2u);
  EXPECT_NE(slow[0].find("trace photons: warning: about "), std::string::npos) << slow[0];
  EXPECT_NE(slow[0].find(" in all at the rate of its first 1."), std::string::npos) << slow[0];
  EXPECT_EQ(slow[1], "trace photons: done");
  // 400 of 1,000 in a second: 2.6 s in all, no warning.
  const std::vector<std::string> quick = Heard(1000, 100);
  ASSERT_EQ(quick.size(), 1u);
  EXPECT_EQ(quick[0], "trace photons: done");
}

// A stage that fills the time a budget left (the small surfaces gathered after the rounds) is not foretold past
// that time: its count is only an upper bound.
TEST(Progress, AStageBoundedInTimeIsForetoldOnlyPastAMinuteOfIt) {
  ASSERT_EQ(Heard(1000, 1, 1, 3, 50.0).size(), 1u);  // about 260 s at its rate, but ends within 50 s
  const std::vector<std::string> bounded = Heard(1000, 1, 1, 3, 200.0);
  ASSERT_EQ(bounded.size(), 2u);
  EXPECT_NE(bounded[0].find("trace photons: warning: about 3 min 20 s in all"), std::string::npos) << bounded[0];
}

// With W threads, each has a step in flight when the first end: the rate is read only once 4 W steps have ended.
TEST(Progress, TheRateWaitsForFourStepsAThread) {
  // On 2 threads, 5 steps of 1,000 over a second (as slow as above) say nothing yet: 4 W is 8.
  ASSERT_EQ(Heard(1000, 1, 2, 3).size(), 1u);
  // 8 steps, then 9 over the second: said.
  const std::vector<std::string> after = Heard(1000, 1, 2, 7);
  ASSERT_EQ(after.size(), 2u);
  EXPECT_NE(after[0].find("(8 of 1000)"), std::string::npos) << after[0];
}

}  // namespace
}  // namespace pb
