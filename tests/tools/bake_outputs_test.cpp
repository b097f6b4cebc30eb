// The bake's outputs as a user's files meet them: Ctrl-C finishes the batch in flight and writes valid outputs; a
// bake killed while it writes, or one that fails late, replaces no earlier output and leaves no temporary; outputs
// that collide with each other or an input are refused before any work; a planted symlink is never followed
// (docs/bake.md, "Outputs are one transaction"). The command line's other contracts are in bake_cli_test.cpp.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "baker/files/atomic_file.h"
#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

using BakeRun = test::ToolRun;
using test::RunBake;

// ---- progressive bakes as a user runs them (tests/baker/progressive_test.cpp tests the library) ----

// A lamp 50 m above a 4 x 4 m floor: 99.8% of photons escape, so hundreds of millions of them are cheap in memory.
std::string WriteFarLamp(const std::string& dir) {
  return test::WriteFloorWithLamps(dir, 0.5f, 1.0f, {{-0.5f, 0.5f, -0.5f, 0.5f, 50.0f}});
}

TEST(BakeCli, CtrlCFinishesTheBatchAndWritesValidOutputs) {
  const std::string dir = test::TempDirectory("cli-ctrl-c");
  const std::string scene = WriteFarLamp(dir);
  const std::string bake = std::string(PB_BAKE_EXE) + " " + scene + " -o " + dir + "/out.ply --photons 400000000 "
                           "--save-photons " + dir + "/s.photons --report " + dir + "/r.json";
  // 400M photons take about half a minute; Ctrl-C comes after one second.
  const BakeRun run = test::RunTool("sh -c '" + bake + " & p=$!; sleep 1; kill -INT $p; wait $p'", "");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("interrupted: tracing stopped after"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("INTERRUPTED"), std::string::npos) << "the summary says so";
  const nlohmann::json report = nlohmann::json::parse(test::ReadBytes(dir + "/r.json"));
  EXPECT_TRUE(report.at("progressive").at("interrupted").get<bool>());
  const uint64_t emitted = report.at("photons").at("emitted").get<uint64_t>();
  EXPECT_GT(emitted, 0u);
  EXPECT_LT(emitted, 400'000'000u);
  EXPECT_GT(test::ReadPly(dir + "/out.ply").VertexCount(), 0u);
  // The photon file is valid: it resumes, and the resumed bake holds at least the photons it had.
  const BakeRun resumed = RunBake(scene + " -o " + dir + "/more.ply --photons 1000000 --resume " + dir +
                                  "/s.photons --report " + dir + "/more.json");
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  const nlohmann::json more = nlohmann::json::parse(test::ReadBytes(dir + "/more.json"));
  EXPECT_EQ(more.at("progressive").at("resumed_photons").get<uint64_t>(), emitted);
  EXPECT_GE(more.at("photons").at("emitted").get<uint64_t>(), emitted);
}

TEST(BakeCli, ABakeKilledWhileWritingPhotonsLeavesThePreviousFileIntact) {
  const std::string dir = test::TempDirectory("cli-killed-write");
  const std::string common = PB_SOURCE_DIR "/data/box/box.obj -q -o " + dir + "/out.ply --save-photons " + dir + "/s.photons";
  ASSERT_EQ(RunBake(common + " --photons 20000").status, 0);
  const std::string before = test::ReadBytes(dir + "/s.photons");
  // A file size limit of 1 MB kills the second bake (SIGXFSZ) part-way through its 35 MB photon file.
  const BakeRun killed = test::RunTool("sh -c 'ulimit -f 2048; " + std::string(PB_BAKE_EXE) + " " + common +
                                       " --photons 1000000'", "");
  EXPECT_NE(killed.status, 0);
  EXPECT_TRUE(test::ReadBytes(dir + "/s.photons") == before) << "the previous photon file changed";
  EXPECT_EQ(RunBake(PB_SOURCE_DIR "/data/box/box.obj -q -o " + dir + "/again.ply --resume " + dir + "/s.photons").status, 0);
}

bool NoTemporariesIn(const std::string& dir) {
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().filename().string().find(".tmp-") != std::string::npos) return false;
  return true;
}

// All outputs are one transaction: a bake whose PLY cannot be written (a 1 MB file-size limit, with SIGXFSZ
// ignored so that write() fails with EFBIG) after its photon file and maps were complete replaces none of them.
TEST(BakeCli, ALateFailureReplacesNoOutput) {
  const std::string dir = test::TempDirectory("cli-transaction");
  std::filesystem::create_directories(dir + "/maps");
  const std::string common = PB_SOURCE_DIR "/data/box/box.obj -q -o " + dir + "/out.ply --save-photons " + dir +
                             "/s.photons --report " + dir + "/r.json --maps " + dir + "/maps --texel 0.1";
  ASSERT_EQ(RunBake(common + " --photons 2000").status, 0);
  const std::vector<std::string> files = {"/out.ply", "/s.photons", "/r.json", "/maps/surface_0.exr"};
  std::vector<std::string> before;
  for (const std::string& f : files) before.push_back(test::ReadBytes(dir + f));
  // 3000 photons make a photon file of about 60 kB; two levels of subdivision a PLY of about 1.5 MB, over the
  // limit of 512 kB. h is given: the automatic h of so few photons is a surface's size, and every point of the
  // subdivided box then lies in a "gap" and gathers paths (13 s where h = 0.05 m takes 3 s).
  const BakeRun failed = test::RunTool("bash -c \"trap '' XFSZ; ulimit -f 512; exec " + std::string(PB_BAKE_EXE) +
                                       " " + common + " --photons 3000 --h 0.05 --subdivide 2\"", "");
  EXPECT_EQ(failed.status, 1) << failed.output;
  EXPECT_NE(failed.output.find("out.ply: error: write failed"), std::string::npos) << failed.output;
  for (size_t i = 0; i < files.size(); ++i)
    EXPECT_TRUE(test::ReadBytes(dir + files[i]) == before[i]) << files[i] << " was replaced by a failed bake";
  EXPECT_TRUE(NoTemporariesIn(dir) && NoTemporariesIn(dir + "/maps")) << "a failed bake left temporary files";
}

// Outputs that collide with each other or with an input, a directory as -o, and a device as an output are
// refused before any work, and nothing is written.
// The maps' commit checks every target before its first rename (issue 60): a folder planted at the name of the last
// surface's map made the rename fail after the earlier maps had been replaced.
TEST(BakeCli, AMapThatCannotBeReplacedReplacesNoOutput) {
  const std::string dir = test::TempDirectory("cli-map-folder");
  const std::string common = PB_SOURCE_DIR "/data/box/box.obj -q -o " + dir + "/out.ply --photons 2000 --h 0.05 "
                             "--maps " + dir + "/maps --texel 0.1";
  ASSERT_EQ(RunBake(common).status, 0);
  const std::string ply = test::ReadBytes(dir + "/out.ply"), first = test::ReadBytes(dir + "/maps/surface_0.exr");
  size_t maps = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir + "/maps")) ++maps;
  const std::string last = dir + "/maps/surface_" + std::to_string(maps - 1) + ".exr";
  std::filesystem::remove(last);
  std::filesystem::create_directory(last);
  const BakeRun failed = RunBake(common + " --seed 2");
  EXPECT_EQ(failed.status, 1) << failed.output;
  EXPECT_NE(failed.output.find(last + ": error: cannot move output into place: a folder has its name; no output was "
                                      "replaced"), std::string::npos) << failed.output;
  EXPECT_TRUE(test::ReadBytes(dir + "/maps/surface_0.exr") == first) << "an earlier map was replaced";
  EXPECT_TRUE(test::ReadBytes(dir + "/out.ply") == ply);
  EXPECT_TRUE(NoTemporariesIn(dir) && NoTemporariesIn(dir + "/maps"));
}

// Two bakes share a --maps folder that the first created and the second found; the first fails and removes it,
// empty: the second makes it again when it writes its maps (issue 60: it failed after its whole bake).
TEST(BakeCli, AMapsFolderRemovedByAnotherRunIsMadeAgainWhenWriting) {
  const std::string maps = test::TempDirectory("cli-shared-maps") + "/maps";
  OutputFiles second;
  {
    OutputFiles first;
    first.MakeDirectory(maps);   // created
    second.MakeDirectory(maps);  // found
  }                              // the first run fails: the folder it created, still empty, goes
  ASSERT_FALSE(std::filesystem::exists(maps));
  second.Write(maps + "/surface_0.exr", [](std::ostream& out) { out << "map"; });
  second.Commit();
  EXPECT_EQ(test::ReadBytes(maps + "/surface_0.exr"), "map");
}

// Maps of an earlier bake left beside a later bake's are named (issue 60: nothing told them apart): the box's 17
// surfaces' maps, then a floor under a lamp (2 surfaces) into the same folder.
TEST(BakeCli, MapsOfAnEarlierBakeInTheFolderAreNamed) {
  const std::string dir = test::TempDirectory("cli-stale-maps");
  const std::string maps = " -q --photons 2000 --h 0.05 --maps " + dir + "/maps --texel 0.2";
  ASSERT_EQ(RunBake(PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/box.ply" + maps).status, 0);
  test::WriteText(dir + "/lamp.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 5 5 5\n");
  test::WriteText(dir + "/lamp.obj", "mtllib lamp.mtl\nusemtl floor\nv 0 0 0\nv 0 0 1\nv 1 0 1\nv 1 0 0\nf 1 2 3 4\n"
                                     "usemtl lamp\nv 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\nf 5 6 7 8\n");
  const BakeRun lamp = RunBake(dir + "/lamp.obj -o " + dir + "/lamp.ply" + maps);
  ASSERT_EQ(lamp.status, 0) << lamp.output;
  EXPECT_NE(lamp.output.find("/maps: warning: 15 maps in this folder are not this bake's (surface_10.exr, "
                             "surface_11.exr, surface_12.exr, ...; it writes 2): an earlier bake's"),
            std::string::npos) << lamp.output;
  const BakeRun again = RunBake(PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/box.ply" + maps);
  EXPECT_EQ(again.output.find("not this bake's"), std::string::npos) << again.output;
}

TEST(BakeCli, CollidingOrNonRegularOutputsAreRefusedAtOnce) {
  const std::string dir = test::TempDirectory("cli-collisions");
  const std::string scene = test::WriteSquareLightOverFloor(dir, 1, 1, 1, 4, 8);
  const std::string sceneBytes = test::ReadBytes(scene);
  ASSERT_EQ(RunBake(scene + " -q -o " + dir + "/keep.ply --photons 1000 --save-photons " + dir + "/s.photons").status, 0);
  const std::string keepBytes = test::ReadBytes(dir + "/keep.ply");
  struct Case {
    std::string arguments, expected;
  };
  const std::vector<Case> cases = {
      {"-o " + scene, "-o would overwrite the input the scene"},
      {"-o " + dir + "/x.ply --report " + dir + "/x.ply", "--report and -o name the same file"},
      {"-o " + dir + "/keep.ply --save-photons " + dir + "/./keep.ply", "--save-photons and -o name the same file"},
      {"-o " + dir + "/y.ply --report " + dir + "/s.photons --resume " + dir + "/s.photons",
       "--report would overwrite the input --resume"},
      {"-o " + dir, "is a directory"},
      {"-o " + dir + "/", "is a directory"},
      {"-o /dev/null", "is not a regular file"},
      // A name that fits the folder but whose temporary would not: refused before the work (issue 60: it failed
      // after the whole bake).
      {"-o " + dir + "/" + std::string(245, 'a') + ".ply", "it passes this folder's limit of 255"},
  };
  for (const Case& c : cases) {
    const BakeRun run = RunBake(scene + " --photons 400000000 " + c.arguments);
    EXPECT_EQ(run.status, 1) << c.arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(c.expected), std::string::npos) << c.arguments << "\n" << run.output;
  }
  EXPECT_TRUE(test::ReadBytes(scene) == sceneBytes);
  EXPECT_TRUE(test::ReadBytes(dir + "/keep.ply") == keepBytes);
  // A scene named as long as a name can be: its lights sidecar's name cannot exist, so it is simply absent.
  const std::string longScene = dir + "/" + std::string(248, 's') + ".obj";
  std::filesystem::copy_file(scene, longScene);
  EXPECT_EQ(RunBake(longScene + " -q -o " + dir + "/long.ply --photons 2000").status, 0);
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.ply"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/y.ply"));
  // --save-photons may name the --resume file: the photons are read before the new file is written.
  EXPECT_EQ(RunBake(scene + " -q -o " + dir + "/z.ply --photons 2000 --resume " + dir + "/s.photons --save-photons " +
                    dir + "/s.photons").status, 0);
  // The scene's material library and textures are inputs too: refused once the scene is loaded, before tracing.
  const std::string texture = test::AddTexture(dir + "/scene.mtl");
  const std::string mtlBytes = test::ReadBytes(dir + "/scene.mtl"), textureBytes = test::ReadBytes(texture);
  for (const Case& c : std::vector<Case>{{"-o " + dir + "/scene.mtl", "-o would overwrite the input the material library"},
                                         {"-o " + dir + "/o.ply --report " + texture, "--report would overwrite the input the texture"}}) {
    const BakeRun run = RunBake(scene + " --photons 400000000 " + c.arguments);
    EXPECT_EQ(run.status, 1) << c.arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(c.expected), std::string::npos) << c.arguments << "\n" << run.output;
  }
  EXPECT_TRUE(test::ReadBytes(dir + "/scene.mtl") == mtlBytes && test::ReadBytes(texture) == textureBytes);
  EXPECT_FALSE(std::filesystem::exists(dir + "/o.ply"));
  // So are the --maps files, once the surfaces are known: -o maps/surface_0.exr --maps maps was accepted, and the
  // map and the PLY were written over each other (issue 39).
  ASSERT_EQ(RunBake(scene + " -q -o " + dir + "/m.ply --photons 2000 --maps " + dir + "/maps").status, 0);
  const std::string mapBytes = test::ReadBytes(dir + "/maps/surface_0.exr");
  for (const Case& c : std::vector<Case>{{"-o " + dir + "/maps/surface_0.exr --maps " + dir + "/maps", "--maps and -o name the same file"},
                                         {"-o " + dir + "/o.ply --report " + dir + "/maps/./surface_1.exr --maps " + dir + "/maps",
                                          "--maps and --report name the same file"}}) {
    const BakeRun run = RunBake(scene + " --photons 400000000 " + c.arguments);
    EXPECT_EQ(run.status, 1) << c.arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(c.expected), std::string::npos) << c.arguments << "\n" << run.output;
  }
  EXPECT_TRUE(test::ReadBytes(dir + "/maps/surface_0.exr") == mapBytes);
  EXPECT_TRUE(NoTemporariesIn(dir + "/maps"));
}

// A planted symlink at a temporary file's name is never followed: the temporary is created with O_EXCL |
// O_NOFOLLOW, so the bake takes another name and the symlink's target is untouched.
TEST(BakeCli, APlantedSymlinkIsNotFollowed) {
  const std::string dir = test::TempDirectory("cli-symlink");
  const std::string scene = test::WriteSquareLightOverFloor(dir, 1, 1, 1, 4, 8);
  test::WriteText(dir + "/victim", "precious");
  OutputFiles outputs;
  // The temporary names a fresh process tries first for out.ply: "<path>.tmp-<pid>-<n>" for n = 0, 1, ... (ctest
  // runs each test in a process of its own).
  for (int n = 0; n < 50; ++n)
    std::filesystem::create_symlink(dir + "/victim", dir + "/out.ply.tmp-" + std::to_string(getpid()) + "-" + std::to_string(n));
  outputs.Write(dir + "/out.ply", [](std::ostream& out) { out << "new"; });
  outputs.Commit();
  EXPECT_EQ(test::ReadBytes(dir + "/victim"), "precious");
  EXPECT_EQ(test::ReadBytes(dir + "/out.ply"), "new");
}

// --only bakes part of a scene: the named objects' surfaces are estimated and written, the light traced through
// the whole scene as before. Every point's random streams are keyed by its surface and position, so each written
// vertex is the whole bake's vertex, every property equal (the colours too, at one --exposure; the automatic one
// would be the part's own), in the whole bake's order; the parts named apart add up to the parts named together.
// With --maps, only the named surfaces' maps are written, each the whole bake's bytes. With --resume from the whole
// bake's saved photons, one object is re-baked without tracing. A name that matches nothing is refused before any
// photon is traced, and --refine is refused with it.
std::vector<std::vector<double>> VertexRows(const test::PlyData& ply) {
  std::vector<std::vector<double>> rows(ply.VertexCount());
  for (const std::string& property : ply.vertexProperties)
    for (size_t v = 0; v < rows.size(); ++v) rows[v].push_back(ply.vertex.at(property)[v]);
  return rows;
}

TEST(BakeCli, OnlyWritesTheNamedObjectsVerticesOfTheWholeBake) {
  const std::string dir = test::TempDirectory("cli-only");
  const std::string common = PB_SOURCE_DIR "/data/box/box.obj -q --photons 100000 --exposure 1 -o " + dir;
  const auto rows = [&](const std::string& name, const std::string& only) {
    const BakeRun run = RunBake(common + "/" + name + ".ply" + (only.empty() || only[0] == ' ' ? only : " --only '" + only + "'"));
    EXPECT_EQ(run.status, 0) << run.output;
    return VertexRows(test::ReadPly(dir + "/" + name + ".ply"));
  };
  const auto whole = rows("whole", " --save-photons " + dir + "/whole.photons"), part = rows("part", "short_block*,floor");
  ASSERT_GT(part.size(), 0u);
  ASSERT_LT(part.size(), whole.size());
  size_t next = 0;  // each part vertex is a whole-bake vertex, in the whole bake's order
  for (const auto& row : part) {
    while (next < whole.size() && whole[next] != row) ++next;
    ASSERT_LT(next, whole.size()) << "a vertex of --only is not the whole bake's";
    ++next;
  }
  const auto floor = rows("floor", "floor");
  EXPECT_EQ(floor.size() + rows("blocks", "short_block*").size(), part.size());
  EXPECT_EQ(rows("floor-again", " --only floor --resume " + dir + "/whole.photons"), floor)
      << "re-baking one object from the whole bake's saved photons traces none and writes its vertices";
  EXPECT_EQ(rows("white", "white").size() + rows("coloured", "red,green").size() + rows("lights", "*_light").size(),
            whole.size()) << "by material, the box's white, red, green and light surfaces are all of it";
  const BakeRun none = RunBake(common + "/none.ply --only 'tall_blocks*'");
  EXPECT_EQ(none.status, 1);
  EXPECT_NE(none.output.find("--only: error: 'tall_blocks*' names no object or material of the scene"), std::string::npos)
      << none.output;
  const std::string maps = " --maps " + dir + "/MAPS --texel 0.05";
  ASSERT_EQ(RunBake(common + "/all-maps.ply" + std::regex_replace(maps, std::regex("MAPS"), "all")).status, 0);
  ASSERT_EQ(RunBake(common + "/floor-maps.ply --only floor" + std::regex_replace(maps, std::regex("MAPS"), "floor")).status, 0);
  std::vector<std::filesystem::path> floorMaps;
  for (const auto& entry : std::filesystem::directory_iterator(dir + "/floor")) floorMaps.push_back(entry.path());
  ASSERT_EQ(floorMaps.size(), 1u) << "--only floor writes the floor's map alone";
  EXPECT_TRUE(test::ReadBytes(floorMaps[0].string()) == test::ReadBytes(dir + "/all/" + floorMaps[0].filename().string()));
  EXPECT_EQ(RunBake(common + "/refined.ply --only floor --refine").status, 2);
  EXPECT_FALSE(std::filesystem::exists(dir + "/none.ply") || std::filesystem::exists(dir + "/refined.ply"));
}

}  // namespace
}  // namespace pb
