// The ranges the tools share (baker/option_ranges.h): bake, render, accuracy and scene-to-gltf refuse the same
// value with the same words and exit 2 before any work, where render once aborted (a CHECK in the OBJ loader for
// --scale 1e-38, std::bad_alloc for --photons 2^64 - 1) or exited 1 (--size 100000x100000).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

namespace fs = std::filesystem;

const std::string kBox = PB_SOURCE_DIR "/data/box/box.obj";

void ExpectRefused(const std::string& exe, const std::string& arguments, const std::string& message) {
  const test::ToolRun run = test::RunTool(exe, arguments);
  EXPECT_EQ(run.status, 2) << exe << " " << arguments << "\n" << run.output;
  EXPECT_NE(run.output.find(message), std::string::npos) << exe << " " << arguments << "\n" << run.output;
}

TEST(OptionRanges, EveryToolRefusesTheSameValueWithTheSameWords) {
  const std::string dir = test::TempDirectory("option-ranges");
  const std::string scale = "--scale: error: must lie in [1e-6, 1e6] metres per scene unit";
  ExpectRefused(PB_BAKE_EXE, kBox + " -o " + dir + "/o.ply --scale 1e-38", scale);
  ExpectRefused(PB_RENDER_EXE, kBox + " -o " + dir + "/o.exr --scale 1e-38", scale);
  ExpectRefused(PB_SCENE_TO_GLTF_EXE, kBox + " -o " + dir + "/o.glb --scale 1e-38", scale);
  const std::string threads = "--threads: error: must lie in [0, 1024]";
  ExpectRefused(PB_BAKE_EXE, kBox + " -o " + dir + "/o.ply --threads 5000", threads);
  ExpectRefused(PB_RENDER_EXE, kBox + " -o " + dir + "/o.exr --threads 5000", threads);
  ExpectRefused(PB_ACCURACY_EXE, "--out " + dir + "/acc --threads 5000", threads);
  const std::string efficacy = "--luminous-efficacy: error: must lie in [1, 683] lm/W";
  ExpectRefused(PB_BAKE_EXE, kBox + " -o " + dir + "/o.ply --luminous-efficacy 900", efficacy);
  ExpectRefused(PB_SCENE_TO_GLTF_EXE, kBox + " -o " + dir + "/o.glb --luminous-efficacy 900", efficacy);
  const std::string h = "--h: error: must be a length in [1e-6, 1e4] m";
  ExpectRefused(PB_BAKE_EXE, kBox + " -o " + dir + "/o.ply --h 1e9", h);
  ExpectRefused(PB_ACCURACY_EXE, "--out " + dir + "/acc --scene box --photons 1000 --h 1e9", h);
  EXPECT_TRUE(fs::is_empty(dir)) << "nothing is written before the options are checked";
}

TEST(OptionRanges, RenderRefusesWhatCannotFitBeforeAnyWork) {
  const std::string dir = test::TempDirectory("render-ranges");
  ExpectRefused(PB_RENDER_EXE, kBox + " -o " + dir + "/o.exr --size 100000x100000",
                "--size: error: must be WIDTHxHEIGHT with each in [1, 16384] pixels");
  ExpectRefused(PB_BAKE_EXE, kBox + " -o " + dir + "/o.ply --preview " + dir + "/p.png --preview-size 9000x10",
                "--preview-size: error: must be WIDTHxHEIGHT with each in [1, 8192] pixels");
  ExpectRefused(PB_RENDER_EXE, kBox + " -o " + dir + "/o.exr --sampling photons --photons 18446744073709551615",
                "--photons: error: must lie in [1, 2^40]");
  // 2^40 photons are within range, but their photon map (56 bytes a hit) is 62 TB: refused by memory.
  ExpectRefused(PB_RENDER_EXE, kBox + " -o " + dir + "/o.exr --sampling photons --photons 1099511627776",
                "--photons: error: a photon map of 1099511627776 photons");
  EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
}  // namespace pb
