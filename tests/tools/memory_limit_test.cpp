// A bake under a memory limit it cannot see in the machine's size (issue 60): `ulimit -v` (RLIMIT_AS) or a control
// group. --target-error rounds that would outgrow it stop at it, say so, and write their outputs; before, they
// planned from the physical memory and lost everything to "out of memory" (mesh/memory_budget.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "mesh/memory_budget.h"
#include "tests/gltf_builder.h"
#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

// AddressSanitizer maps terabytes of shadow memory, which no `ulimit -v` leaves room for.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

TEST(MemoryLimit, RoundsUnderAUlimitStopAtItAndWriteTheirOutputs) {
  if (kSanitized) GTEST_SKIP() << "AddressSanitizer's shadow memory does not fit under a ulimit -v";
  const std::string dir = test::TempDirectory("memory-limit");
  // 1.5 GB of address space: a bake of the box maps about 0.8 GB before its photons (threads, arenas), and 0.003
  // would ask for 32M photons in its first round, about 3 GB mapped.
  const test::ToolRun run = test::RunTool("ulimit -v 1500000 && " PB_BAKE_EXE,
                                          PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/out.ply --report " + dir +
                                              "/r.json --target-error 0.003 --max-seconds 120 --threads 2");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("the first round is held to"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("of the process's ulimit -v 1.5 GB of memory"), std::string::npos) << run.output;
  const nlohmann::json report = nlohmann::json::parse(test::ReadBytes(dir + "/r.json"));
  EXPECT_NE(report.at("progressive").at("stopped_by").get<std::string>().find("memory"), std::string::npos)
      << report.at("progressive").dump();
  EXPECT_FALSE(test::ReadBytes(dir + "/out.ply").empty());
}

TEST(MemoryLimit, TheTightestLimitIsTheOneRead) {
  // Under no ulimit in this process, the limit is the machine's or a control group's, never above the machine's.
  const double limit = MemoryLimitBytes();
  ASSERT_GT(limit, 0);
  const double inUse = MemoryInUseBytes();  // read first: the process may grow between the two reads
  EXPECT_GT(inUse, 0);
  EXPECT_GE(PeakMemoryBytes(), inUse);
  if (kSanitized) return;
  const std::string dir = test::TempDirectory("memory-limit-refused");
  const test::ToolRun under = test::RunTool("ulimit -v 3000000 && " PB_BAKE_EXE,
                                            PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/out.ply --subdivide 6 -q");
  // 6 levels of the box (7.8M faces, about 3 GB) fit the machine but not 3 GB of address space: refused up front.
  EXPECT_EQ(under.status, 1) << under.output;
  EXPECT_NE(under.output.find("of the process's ulimit -v 3.1 GB a run may use"), std::string::npos) << under.output;
}

// A glTF of a few kilobytes whose one square is drawn 2^24 times by EXT_mesh_gpu_instancing: 33.5M triangles, under
// the expansion cap (2^26), about 10 GB of bake. Under 4 GB of address space it is refused as it is read, naming
// the file and the figure, before a triangle is built (it exhausted the memory late).
TEST(MemoryLimit, AGltfThatExpandsPastTheMemoryIsRefusedBeforeItIsBuilt) {
  if (kSanitized) GTEST_SKIP() << "AddressSanitizer's shadow memory does not fit under a ulimit -v";
  const std::string dir = test::TempDirectory("memory-limit-gltf");
  test::GltfBuilder b;
  b.AddMesh(b.AddPositions({{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}), b.AddIndices({0, 1, 2, 0, 2, 3}));
  const int zeros = b.AddAccessor(-1, 5126, size_t(1) << 24, "VEC3");  // 2^24 instances, all at the node
  b.SetRoots({b.AddNode(
      {{"mesh", 0}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", zeros}}}}}}}})});
  const std::string scene = b.WriteGltf(dir, "instanced");
  const test::ToolRun run = test::RunTool("ulimit -v 4000000 && " PB_BAKE_EXE, scene + " -q -o " + dir + "/out.ply");
  EXPECT_EQ(run.status, 1) << run.output;
  EXPECT_NE(run.output.find(scene + ": error: the scene's 33554432 triangles (after its instances and shared nodes"),
            std::string::npos) << run.output;
  EXPECT_NE(run.output.find("more than the 80% of the process's ulimit -v 4.1 GB a run may use"), std::string::npos)
      << run.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.ply"));
}

// The largest sky image (16384 x 8192 texels) fits 4 GB of address space alone (2.7 GB with its CDF), but not seen
// through two portals (a CDF more per portal: 4.8 GB). Its header says so, and the lights file says how many portals
// there are: the image is refused before its texels are read, naming the file and the figure (it exhausted the
// memory late, weighing its texels). Without the portals the same header passes the check and the truncated data
// is what fails.
TEST(MemoryLimit, ASkyImageThatCannotBeWeighedForItsPortalsIsRefusedFromItsHeader) {
  if (kSanitized) GTEST_SKIP() << "AddressSanitizer's shadow memory does not fit under a ulimit -v";
  const std::string dir = test::TempDirectory("memory-limit-sky");
  test::WriteText(dir + "/sky.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n");
  const std::string portal = R"({"corners_m": [[0.1, 0.1, 0.559], [0.2, 0.1, 0.559], [0.2, 0.2, 0.559], [0.1, 0.2, 0.559]]})";
  for (const bool portals : {true, false}) {
    std::filesystem::copy_file(PB_SOURCE_DIR "/data/box/box.obj", dir + "/box.obj",
                               std::filesystem::copy_options::overwrite_existing);
    std::filesystem::copy_file(PB_SOURCE_DIR "/data/box/box.mtl", dir + "/box.mtl",
                               std::filesystem::copy_options::overwrite_existing);
    test::WriteText(dir + "/box.lights.json", R"({"lights": [{"type": "sky", "image": "sky.hdr"}], "portals": [)" +
                                                  (portals ? portal + ", " + portal : std::string()) + "]}");
    const test::ToolRun run = test::RunTool("ulimit -v 4000000 && " PB_BAKE_EXE, dir + "/box.obj -q -o " + dir + "/out.ply");
    EXPECT_EQ(run.status, 1) << run.output;
    const bool refused = run.output.find(dir + "/sky.hdr: error: a sky image of 16384 x 8192 pixels seen through 2 "
                                         "portals, with the tables its photons are drawn by, needs about 4.8 GB, more "
                                         "than the 80% of the process's ulimit -v 4.1 GB") != std::string::npos;
    EXPECT_EQ(refused, portals) << run.output;
    EXPECT_FALSE(std::filesystem::exists(dir + "/out.ply"));
  }
}

}  // namespace
}  // namespace pb
