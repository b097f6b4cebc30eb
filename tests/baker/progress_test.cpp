// The progress of long stages (baker/runtime/progress.h): a stage that would take over a minute at the rate of its
// first second says so once, before the time is spent (issue 39: work that multiplies, like --photons or
// --reference, ran for minutes with only the progress line's time left to say so).
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "baker/runtime/progress.h"

namespace pb {
namespace {

std::vector<std::string> Heard(uint64_t total, uint64_t firstStep) {
  std::vector<std::string> heard;
  const Log log(true, [&](const std::string& line) { heard.push_back(line); });
  {
    Progress progress(log, "trace photons", total);
    progress.Advance(firstStep);
    std::this_thread::sleep_for(std::chrono::milliseconds(1050));
    progress.Advance(firstStep);
    progress.Advance(firstStep);  // said once, not at every step
    progress.Advance(total - 3 * firstStep);
  }
  return heard;
}

TEST(Progress, AStageOverAMinuteAtItsFirstSecondsRateSaysSoOnce) {
  // 3 of 1,000 in over a second: about 350 s in all.
  const std::vector<std::string> slow = Heard(1000, 1);
  ASSERT_EQ(slow.size(), 2u);
  EXPECT_NE(slow[0].find("trace photons: warning: about "), std::string::npos) << slow[0];
  EXPECT_NE(slow[0].find(" in all at the rate of its first 1."), std::string::npos) << slow[0];
  EXPECT_EQ(slow[1], "trace photons: done");
  // 300 of 1,000 in a second: 3.5 s in all, no warning.
  const std::vector<std::string> quick = Heard(1000, 100);
  ASSERT_EQ(quick.size(), 1u);
  EXPECT_EQ(quick[0], "trace photons: done");
}

}  // namespace
}  // namespace pb
