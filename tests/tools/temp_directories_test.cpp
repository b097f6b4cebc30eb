// The test processes clean up after themselves (tests/temp_directories.cpp): a process whose tests all passed leaves
// none of its temporary directories; one with a failed test keeps them, to be looked at. Checked on this test
// binary itself, run as ctest runs it (one test a process), with a test that fails only when asked to.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

// Makes a temporary directory with a file in it; fails when PB_TEST_FAIL_ON_PURPOSE is set (by the test below).
TEST(TempDirectories, AProbeThatMakesOne) {
  test::WriteText(test::TempDirectory("cleanup-probe") + "/probe.txt", "probe\n");
  if (std::getenv("PB_TEST_FAIL_ON_PURPOSE") != nullptr) FAIL() << "failing on purpose, as asked";
}

// The probe's directory after running it in a process of its own, whose pid the shell prints before it becomes it.
bool ProbeLeftItsDirectory(bool fail) {
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  const test::ToolRun run = test::RunTool(
      "sh", "-c 'echo $$; " + std::string(fail ? "PB_TEST_FAIL_ON_PURPOSE=1 " : "") + "exec \"" + self +
                "\" --gtest_filter=TempDirectories.AProbeThatMakesOne'");
  EXPECT_EQ(run.status, fail ? 1 : 0) << run.output;
  const std::string pid = run.output.substr(0, run.output.find('\n'));
  const auto dir = std::filesystem::temp_directory_path() / ("photonbake-test-" + pid + "-cleanup-probe");
  const bool left = std::filesystem::exists(dir / "probe.txt");
  std::filesystem::remove_all(dir);
  return left;
}

TEST(TempDirectories, RemovedWhenTheTestsPassedKeptWhenOneFailed) {
  EXPECT_FALSE(ProbeLeftItsDirectory(false));
  EXPECT_TRUE(ProbeLeftItsDirectory(true));
}

}  // namespace
}  // namespace pb
