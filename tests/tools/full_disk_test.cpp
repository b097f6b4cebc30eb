// A disk that fills at any byte of a bake's outputs (PB_FAIL_WRITES_AFTER, baker/files/atomic_file.h): the PLY, the
// maps, the report, the photon file and the preview. Wherever the writes stop, the bake exits 1 naming the file
// and the cause, leaves no temporary, and every output of the earlier run keeps its bytes. A full disk during
// --maps once aborted the bake (OpenEXR's exception, thrown on a worker thread) and left three temporaries. And the
// temporaries a killed run leaves are removed by the next run beside them, which says so.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <map>
#include <string>

#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

namespace fs = std::filesystem;

// Every file under `dir`, by its path, with its bytes.
std::map<std::string, std::string> Snapshot(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file()) files[entry.path().string()] = test::ReadBytes(entry.path().string());
  return files;
}

TEST(FullDisk, ABakeThatRunsOutOfSpaceAnywhereChangesNothing) {
  const std::string dir = test::TempDirectory("full-disk");
  const std::string bake = PB_BAKE_EXE " " PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/box.ply --maps " + dir +
                           "/maps --texel 0.02 --report " + dir + "/report.json --save-photons " + dir +
                           "/photons.bin --preview " + dir + "/preview.png --preview-size 32x32 --photons 20000 "
                           "--h 0.05 --direct-samples 16 -q";
  const test::ToolRun first = test::RunTool(bake, "--seed 1");
  ASSERT_EQ(first.status, 0) << first.output;
  const std::map<std::string, std::string> before = Snapshot(dir);
  ASSERT_EQ(before.size(), 4u + 17u);  // the PLY, report, photons and preview, and a map per surface
  size_t total = 0;
  for (const auto& [path, bytes] : before) total += bytes.size();
  std::vector<size_t> limits = {0, 1, 4095, 65536, total - 1};
  for (size_t k = 1; k < 16; ++k) limits.push_back(total * k / 16);
  for (const size_t limit : limits) {
    const test::ToolRun run = test::RunTool("PB_FAIL_WRITES_AFTER=" + std::to_string(limit) + " " + bake, "--seed 2");
    EXPECT_EQ(run.status, 1) << "full after " << limit << " of " << total << " bytes:\n" << run.output;
    EXPECT_NE(run.output.find("No space left on device"), std::string::npos) << limit << ":\n" << run.output;
    EXPECT_TRUE(Snapshot(dir) == before) << "full after " << limit << " bytes: an output changed or a temporary is left";
  }
  const test::ToolRun roomy = test::RunTool("PB_FAIL_WRITES_AFTER=" + std::to_string(2 * total) + " " + bake, "--seed 2");
  EXPECT_EQ(roomy.status, 0) << "room for every byte: " << roomy.output;
}

// A run killed outright cannot remove its temporaries; the next run removes those of its own outputs whose pid no
// longer runs, and names each. Another output's, or a running process's, are left alone.
TEST(FullDisk, TheTemporariesOfAKilledRunAreRemovedByTheNext) {
  const std::string dir = test::TempDirectory("killed-run");
  const test::ToolRun gone = test::RunTool("sh -c 'echo $$'", "");  // a pid that has exited
  const std::string dead = gone.output.substr(0, gone.output.find('\n')), alive = std::to_string(getpid());
  fs::create_directories(dir + "/maps");
  const std::vector<std::string> stale = {dir + "/box.ply.tmp-" + dead + "-0", dir + "/maps/surface_2.exr.tmp-" + dead + "-3"};
  const std::vector<std::string> kept = {dir + "/box.ply.tmp-" + alive + "-1", dir + "/other.ply.tmp-" + dead + "-0",
                                         dir + "/maps/notes.txt.tmp-" + dead + "-0"};
  for (const std::string& f : stale) test::WriteText(f, "half a file");
  for (const std::string& f : kept) test::WriteText(f, "not ours to remove");
  const test::ToolRun run = test::RunTool(PB_BAKE_EXE, PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/box.ply --maps " +
                                                           dir + "/maps --photons 20000 --h 0.05 --direct-samples 16");
  ASSERT_EQ(run.status, 0) << run.output;
  for (const std::string& f : stale) {
    EXPECT_FALSE(fs::exists(f)) << f;
    EXPECT_NE(run.output.find(f + ": warning: removed this temporary file, left by a run (pid " + dead + ")"),
              std::string::npos) << run.output;
  }
  for (const std::string& f : kept) EXPECT_TRUE(fs::exists(f)) << f;
}

// The box baked with maps into `maps` (a folder under `dir`) and, when there are `signals` to send (kill names, one
// after the other, half a second apart), held staged for 6 s before its commit (PB_PAUSE_BEFORE_COMMIT_MS,
// baker/files/atomic_file.h) and sent them once its PLY is staged: at most 1.6 s after staging, so the pause leaves
// over 4 s to spare (it was 20 s, idle time that cost the sanitizer pass 40 s). What the shell's wait saw
// ("status N") is in the output.
test::ToolRun SignalWhileStaged(const std::string& dir, const std::string& maps, const std::vector<std::string>& signals,
                                int seed) {
  const std::string bake = PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/box.ply --maps " + maps + " --texel 0.05 "
                           "--report " + dir + "/report.json --photons 20000 --h 0.05 --direct-samples 16 -q --seed " +
                           std::to_string(seed) + " 2>&1";
  if (signals.empty()) return test::RunTool(PB_BAKE_EXE, bake + "; echo \"status $?\"");
  std::string kills;
  for (const std::string& signal : signals) kills += "kill -" + signal + " $pid; sleep 0.5; ";
  // The shell's own job runs in the background, so it is sent the signal by pid.
  return test::RunTool("PB_PAUSE_BEFORE_COMMIT_MS=6000 " PB_BAKE_EXE,
                       bake + " & pid=$!; while ! ls " + dir + "/box.ply.tmp-* >/dev/null 2>&1; do "
                       "sleep 0.1; done; sleep 0.5; " + kills + "wait $pid; echo \"status $?\"");
}

// SIGTERM (what timeout, systemd and CI send) while every output is staged, and a second Ctrl-C alike: the bake
// removes its temporaries and the maps folder it created, and ends by the signal; the earlier run's outputs keep
// their bytes. Before, SIGTERM left every temporary behind for the next run to find, and the folder stayed.
TEST(FullDisk, ASignalWhileTheOutputsAreStagedLeavesNoTemporaryAndNoCreatedFolder) {
  const std::string dir = test::TempDirectory("signalled-run");
  const test::ToolRun first = SignalWhileStaged(dir, dir + "/maps", {}, 1);
  ASSERT_NE(first.output.find("status 0"), std::string::npos) << first.output;
  const std::map<std::string, std::string> before = Snapshot(dir);
  for (const std::vector<std::string>& signals : {std::vector<std::string>{"TERM"}, {"INT", "INT"}}) {
    const test::ToolRun run = SignalWhileStaged(dir, dir + "/new/maps", signals, 2);
    EXPECT_NE(run.output.find(signals[0] == "TERM" ? "status 143" : "status 130"), std::string::npos)
        << signals[0] << ": " << run.output;
    EXPECT_TRUE(Snapshot(dir) == before) << signals[0] << ": an output changed or a temporary is left";
    EXPECT_FALSE(fs::exists(dir + "/new")) << signals[0] << ": the folders the run created are left";
  }
}

// One Ctrl-C after tracing (here, with every output staged) asks the bake to finish: it commits every output, as its
// message on stderr promises, and exits 0. Before, a Ctrl-C after the estimate ended the bake at once.
TEST(FullDisk, OneCtrlCAfterTheEstimateLetsTheBakeFinish) {
  const std::string dir = test::TempDirectory("ctrl-c-finishes");
  const test::ToolRun run = SignalWhileStaged(dir, dir + "/maps", {"INT"}, 2);
  EXPECT_NE(run.output.find("status 0"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("Ctrl-C: tracing, the estimate and refinement stop"), std::string::npos) << run.output;
  const std::map<std::string, std::string> written = Snapshot(dir);
  EXPECT_EQ(written.size(), 2u + 17u);  // the PLY and report, and a map per surface; no temporary
  EXPECT_EQ(test::ReadPly(dir + "/box.ply").VertexCount(), 1204u);
}

}  // namespace
}  // namespace pb
