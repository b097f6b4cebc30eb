// bake-mpi (tools/bake_mpi.cpp, baker/distribution.h) as a user runs it, under `mpirun --oversubscribe -np 3`:
// - the PLY is byte-identical to a single-process bake's, with one and two threads per rank, and the report's
//   photon figures and per-surface tallies are the same: at a fixed h (photons binned while traced), at the
//   defaults and with --target-error (h chosen per surface, rounds), with an IES lamp and a sky image through a
//   portal, and for a photon file saved and then resumed;
// - the small surfaces the rounds' spare time gathers, shared among the ranks, as one process gathers them;
// - --maps: the texels shared among the ranks, the maps those of one process; a disk that fills while rank 0 writes
//   them ends the job, naming the map, with nothing left behind;
// - bad input is reported once (by rank 0) and exits non-zero;
// - a rank killed part-way makes mpirun exit non-zero naming a rank, and the earlier output is left as it was, with
//   no temporary file beside it.
// Skipped where bake-mpi is not built (no MPI found), unless PB_REQUIRE_MPI is set (CI).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "baker/files/atomic_file.h"
#include "baker/files/image_io.h"
#include "tests/ies_text.h"
#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

#define REQUIRE_BAKE_MPI()                                                                     \
  do {                                                                                         \
    if (kBakeMpi.empty()) {                                                                    \
      if (std::getenv("PB_REQUIRE_MPI")) FAIL() << "bake-mpi is not built: install libopenmpi-dev"; \
      GTEST_SKIP() << "bake-mpi is not built (no MPI found)";                                   \
    }                                                                                          \
  } while (0)

#ifdef PB_BAKE_MPI_EXE
const std::string kBakeMpi = PB_BAKE_MPI_EXE;
const std::string kMpirun = "mpirun --allow-run-as-root --oversubscribe -np 3 " PB_BAKE_MPI_EXE;
#else
const std::string kBakeMpi;
const std::string kMpirun;
#endif

const std::string kBox = PB_SOURCE_DIR "/data/box/box_25mm.obj";

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(BakeMpi, ThreeRanksWriteTheBytesOfOneProcess) {
  REQUIRE_BAKE_MPI();
  const std::string dir = test::TempDirectory("bake-mpi");
  // bake-mpi keeps a fixed h (it bins while tracing), where bake would choose one per surface.
  const std::string common = kBox + " -q --photons 600000 --h 0.05 --direct-samples 4";
  const test::ToolRun single = test::RunTool(PB_BAKE_EXE, common + " -o " + dir + "/one.ply --report " + dir + "/one.json");
  ASSERT_EQ(single.status, 0) << single.output;
  // 4 shadow rays a point show as noise: both name the rounds that would find the photons.
  EXPECT_NE(single.output.find("(or --target-noise 0.02 finds the photons itself)"), std::string::npos) << single.output;
  for (const char* threads : {"1", "2"}) {
    const std::string out = dir + "/mpi" + threads;
    const test::ToolRun run = test::RunTool(kMpirun, common + " --threads " + threads + " -o " + out + ".ply --report " + out + ".json");
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("(or --target-noise 0.02 finds the photons itself)"), std::string::npos) << run.output;
    EXPECT_TRUE(test::ReadBytes(out + ".ply") == test::ReadBytes(dir + "/one.ply")) << "--threads " << threads;
    const nlohmann::json a = nlohmann::json::parse(test::ReadBytes(dir + "/one.json"));
    const nlohmann::json b = nlohmann::json::parse(test::ReadBytes(out + ".json"));
    EXPECT_EQ(a.at("photons"), b.at("photons"));
    EXPECT_EQ(a.at("surfaces"), b.at("surfaces"));
    EXPECT_GT(b.at("photons").at("hits_binned_while_traced").get<uint64_t>(), 0u);
  }
}

// The reports of two bakes agree on the photons, the surfaces and the rounds (their photons, noise and error).
void ExpectTheSameFigures(const std::string& one, const std::string& other) {
  const nlohmann::json a = nlohmann::json::parse(test::ReadBytes(one)), b = nlohmann::json::parse(test::ReadBytes(other));
  EXPECT_EQ(a.at("photons"), b.at("photons"));
  EXPECT_EQ(a.at("surfaces"), b.at("surfaces"));
  const nlohmann::json& ra = a.at("progressive").at("rounds");
  const nlohmann::json& rb = b.at("progressive").at("rounds");
  ASSERT_EQ(ra.size(), rb.size());
  for (size_t i = 0; i < ra.size(); ++i)
    for (const char* figure : {"photons", "noise", "error", "shadow_rays"})
      EXPECT_EQ(ra[i].at(figure), rb[i].at(figure)) << "round " << i + 1 << ": " << figure;
}

// Issue 59: nothing but the scene and -o (h chosen per surface from the photons, rounds to the noise target), and
// --target-error (whose box takes two rounds, the second planned by rank 0 and shared): the bytes of one process.
TEST(BakeMpi, AtTheDefaultsAndInRoundsThreeRanksWriteTheBytesOfOneProcess) {
  REQUIRE_BAKE_MPI();
  const std::string dir = test::TempDirectory("bake-mpi-defaults");
  const std::string box = PB_SOURCE_DIR "/data/box/box.obj";
  for (const std::string options : {"", " --target-error 0.02"}) {
    SCOPED_TRACE(options);
    const test::ToolRun single =
        test::RunTool(PB_BAKE_EXE, box + " -q -o " + dir + "/one.ply --report " + dir + "/one.json" + options);
    ASSERT_EQ(single.status, 0) << single.output;
    for (const char* threads : {"1", "2"}) {
      const std::string out = dir + "/mpi" + threads;
      const test::ToolRun run =
          test::RunTool(kMpirun, box + " -q --threads " + threads + " -o " + out + ".ply --report " + out + ".json" + options);
      ASSERT_EQ(run.status, 0) << run.output;
      EXPECT_TRUE(test::ReadBytes(out + ".ply") == test::ReadBytes(dir + "/one.ply")) << "--threads " << threads;
      ExpectTheSameFigures(dir + "/one.json", out + ".json");
    }
  }
  const nlohmann::json rounds = nlohmann::json::parse(test::ReadBytes(dir + "/mpi1.json")).at("progressive").at("rounds");
  EXPECT_GE(rounds.size(), 2u) << "--target-error 0.02 on the box takes a second round";
}

// Issue 59: the time budget bounds a distributed estimate as it does one process's (Progressive.TheFirstRoundIsFitted
// ToTheTimeBudget, .TheDeadlineStopsTheFirstRoundsEstimate): the office with books at --quality production (about
// 8 s of estimate on 2 cores) in a budget of 1 s. Rank 0's pilot cuts the first round's shadow rays and gathered
// paths for all, the ranks stop claiming vertex chunks at the estimate's deadline, and the chunks none claimed are
// estimated at the fewest samples: every vertex finite, the report saying so once.
TEST(BakeMpi, TheTimeBudgetCutsAndStopsTheFirstRoundAsInOneProcess) {
  REQUIRE_BAKE_MPI();
  const std::string dir = test::TempDirectory("bake-mpi-budget");
  const test::ToolRun run = test::RunTool(kMpirun, PB_SOURCE_DIR "/data/office_books/office_books.obj -o " + dir +
                                                       "/out.ply --report " + dir + "/out.json --quality production --max-seconds 1");
  ASSERT_EQ(run.status, 0) << run.output;
  const nlohmann::json p = nlohmann::json::parse(test::ReadBytes(dir + "/out.json")).at("progressive");
  EXPECT_LT(p.at("first_round_cut").get<double>(), 1.0);
  EXPECT_GT(p.at("finished_at_fewest_samples_vertices").get<uint64_t>(), 0u);
  EXPECT_NE(p.at("stopped_by").get<std::string>().find("the estimate's deadline (90% of --max-seconds 1) during round 1's estimate"),
            std::string::npos) << p.at("stopped_by");
  EXPECT_EQ(Count(run.output, "are cut to"), 1u) << run.output;
  EXPECT_EQ(Count(run.output, "the vertices left are estimated at the fewest samples"), 1u) << run.output;
  const test::PlyData ply = test::ReadPly(dir + "/out.ply");
  ASSERT_GT(ply.VertexCount(), 0u);
  double sum = 0;
  for (const char* channel : {"irradiance_r", "irradiance_g", "irradiance_b"})
    for (double h : ply.vertex.at(channel)) {
      ASSERT_TRUE(std::isfinite(h) && h >= 0) << channel << " " << h;
      sum += h;
    }
  EXPECT_GT(sum, 0);
}

// Issue 59: --save-photons under MPI writes the file bake writes, and --resume from it (every rank reads it)
// continues as bake does.
TEST(BakeMpi, APhotonFileSavedAndResumedIsThatOfOneProcess) {
  REQUIRE_BAKE_MPI();
  const std::string dir = test::TempDirectory("bake-mpi-photon-file");
  const std::string common = kBox + " -q --h 0.05 --direct-samples 4";
  const auto bake = [&](const std::string& tool, int photons, const std::string& name, const std::string& file) {
    return test::RunTool(tool, common + " --photons " + std::to_string(photons) + " -o " + dir + "/" + name + ".ply " + file);
  };
  ASSERT_EQ(bake(PB_BAKE_EXE, 200000, "one", "--save-photons " + dir + "/one.photons").status, 0);
  const test::ToolRun saved = bake(kMpirun, 200000, "mpi", "--save-photons " + dir + "/mpi.photons");
  ASSERT_EQ(saved.status, 0) << saved.output;
  EXPECT_TRUE(test::ReadBytes(dir + "/mpi.photons") == test::ReadBytes(dir + "/one.photons"));
  EXPECT_TRUE(test::ReadBytes(dir + "/mpi.ply") == test::ReadBytes(dir + "/one.ply"));
  ASSERT_EQ(bake(PB_BAKE_EXE, 500000, "one2", "--resume " + dir + "/one.photons").status, 0);
  const test::ToolRun resumed = bake(kMpirun, 500000, "mpi2", "--resume " + dir + "/mpi.photons");
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_TRUE(test::ReadBytes(dir + "/mpi2.ply") == test::ReadBytes(dir + "/one2.ply"));
}

// The time the rounds leave gathers the small surfaces the share left out (the door left ajar: one, 187 vertices);
// under MPI the ranks share each batch of their vertices (issue 59), and the bake is one process's, the report saying
// the same.
TEST(BakeMpi, TheSpareTimesSmallSurfacesAreSharedAndAreThoseOfOneProcess) {
  REQUIRE_BAKE_MPI();
  const std::string dir = test::TempDirectory("bake-mpi-spare-time");
  const std::string scene = PB_SOURCE_DIR "/data/door_ajar/door_ajar.obj -q";
  const test::ToolRun single = test::RunTool(PB_BAKE_EXE, scene + " -o " + dir + "/one.ply --report " + dir + "/one.json");
  ASSERT_EQ(single.status, 0) << single.output;
  const test::ToolRun run = test::RunTool(kMpirun, scene + " -o " + dir + "/mpi.ply --report " + dir + "/mpi.json");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_TRUE(test::ReadBytes(dir + "/mpi.ply") == test::ReadBytes(dir + "/one.ply"));
  ExpectTheSameFigures(dir + "/one.json", dir + "/mpi.json");
  const nlohmann::json small =
      nlohmann::json::parse(test::ReadBytes(dir + "/mpi.json")).at("progressive").at("small_surfaces_left_out");
  EXPECT_EQ(small.at("gathered"), 1) << small;
  EXPECT_EQ(small.at("vertices_gathered"), 187) << small;
}

// --maps under MPI (issue 59): the texels are shared among the ranks, each estimating the chunks it claims, from
// rank 0's field as its last steps left it (the box's short block's back weighs its gathered light against its
// photons: a rank that had not learned that weight would read it otherwise), and rank 0 writes the maps: at the
// defaults with --sh, and with --only, every map the bytes of one process's.
TEST(BakeMpi, TheMapsAreSharedAmongTheRanksAndAreThoseOfOneProcess) {
  REQUIRE_BAKE_MPI();
  const std::string dir = test::TempDirectory("bake-mpi-maps");
  const std::string box = PB_SOURCE_DIR "/data/box/box.obj -q --texel 0.02";
  for (const std::string options : {" --sh", " --only short_block_side3,floor"}) {
    SCOPED_TRACE(options);
    const test::ToolRun single = test::RunTool(PB_BAKE_EXE, box + options + " -o " + dir + "/one.ply --maps " + dir + "/one");
    ASSERT_EQ(single.status, 0) << single.output;
    const test::ToolRun run = test::RunTool(kMpirun, box + options + " -o " + dir + "/mpi.ply --maps " + dir + "/mpi");
    ASSERT_EQ(run.status, 0) << run.output;
    size_t maps = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir + "/one")) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(test::ReadBytes(dir + "/mpi/" + name) == test::ReadBytes(entry.path().string())) << name;
      ++maps;
    }
    EXPECT_EQ(maps, options == " --sh" ? 17u : 2u);
    EXPECT_TRUE(test::ReadBytes(dir + "/mpi.ply") == test::ReadBytes(dir + "/one.ply"));
    std::filesystem::remove_all(dir + "/one"), std::filesystem::remove_all(dir + "/mpi");
  }
}

// A disk that fills while rank 0 writes the first of two batches of texels (a 1 m floor at 0.8 mm texels, 1.56
// million, a batch of its own, and the lamp's): rank 0 still takes its part in the second batch, which the others
// wait for, then fails naming the map; the job ends (it hung until mpirun was killed when rank 0 threw at once), and
// nothing is left behind.
TEST(BakeMpi, ADiskThatFillsWhileTheMapsAreWrittenEndsTheJob) {
  REQUIRE_BAKE_MPI();
  const std::string dir = test::TempDirectory("bake-mpi-full-disk");
  test::WriteText(dir + "/q.mtl", "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n");
  test::WriteText(dir + "/q.obj", "mtllib q.mtl\nusemtl grey\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 4 3 2\n"
                                  "usemtl lamp\nv 0.4 1 0.4\nv 0.6 1 0.4\nv 0.6 1 0.6\nv 0.4 1 0.6\nf 5 6 7 8\n");
  const test::ToolRun run = test::RunTool("PB_FAIL_WRITES_AFTER=1000 timeout 300 " + kMpirun,
                                          dir + "/q.obj -q -o " + dir + "/q.ply --maps " + dir + "/maps --texel 0.0008 "
                                          "--photons 20000 --h 0.2 --direct photons");
  EXPECT_EQ(run.status, 1) << run.output;  // 124: timeout ended a job that hung
  EXPECT_NE(run.output.find("surface_0.exr"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/q.ply"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/maps"));
}

// A grey room under an image sky through its window and an IES lamp inside, with --sh: three ranks bake the bytes of
// one.
TEST(BakeMpi, IesLampsAndSkyImagesBakeAsInOneProcess) {
  REQUIRE_BAKE_MPI();
  const std::string dir = test::TempDirectory("bake-mpi-lights");
  test::WriteText(dir + "/r.mtl", "newmtl grey\nKd 0.6 0.6 0.6\n");
  test::WriteText(dir + "/r.obj", "mtllib r.mtl\nusemtl grey\n"
                  "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 4 3 2\n"  // the floor, facing up
                  "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\nv -0.25 1 -0.25\nv 0.25 1 -0.25\nv 0.25 1 0.25\n"
                  "v -0.25 1 0.25\nf 5 6 10 9\nf 6 7 11 10\nf 7 8 12 11\nf 8 5 9 12\n"  // the ceiling about its window
                  "f 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");                    // the walls, facing in
  Image sky(16, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) sky.At(x, y) = {1.0f + float(x % 4), 2.0f, 8.0f / float(1 + y)};
  OutputFiles images;
  WriteExr(images, dir + "/sky.exr", sky);
  images.Commit();
  test::WriteText(dir + "/lamp.ies", test::IesText({{0, 30, 60, 90}, {0, 90}, [](double g, double c) { return 200 - g + c; }}));
  test::WriteText(dir + "/r.lights.json", R"({"lights": [{"type": "sky", "image": "sky.exr"},
      {"type": "point", "ies": "lamp.ies", "position_m": [0.5, 0.8, 0.3], "scale": 10}],
      "portals": [{"corners_m": [[-0.25, 1, -0.25], [0.25, 1, -0.25], [0.25, 1, 0.25], [-0.25, 1, 0.25]]}]})");
  const std::string common = dir + "/r.obj -q --photons 600000 --h 0.2 --direct-samples 16 --sh";
  const test::ToolRun single = test::RunTool(PB_BAKE_EXE, common + " -o " + dir + "/one.ply");
  ASSERT_EQ(single.status, 0) << single.output;
  const test::ToolRun run = test::RunTool(kMpirun, common + " -o " + dir + "/mpi.ply");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_TRUE(test::ReadBytes(dir + "/mpi.ply") == test::ReadBytes(dir + "/one.ply"));
  EXPECT_NE(test::ReadBytes(dir + "/mpi.ply").find("property float sh_b3"), std::string::npos);
}

TEST(BakeMpi, BadInputIsReportedOnce) {
  REQUIRE_BAKE_MPI();
  const std::string dir = test::TempDirectory("bake-mpi-errors");
  const test::ToolRun missing = test::RunTool(kMpirun, dir + "/missing.obj -o " + dir + "/x.ply");
  EXPECT_NE(missing.status, 0);
  EXPECT_EQ(Count(missing.output, "missing.obj: error: cannot open scene file"), 1u) << missing.output;
  // An output whose temporary's name is too long (issue 60: std::terminate on every rank) is one clear error.
  const test::ToolRun longName = test::RunTool(kMpirun, kBox + " -q -o " + dir + "/" + std::string(245, 'a') + ".ply");
  EXPECT_NE(longName.status, 0);
  EXPECT_EQ(Count(longName.output, "passes this folder's limit of 255"), 1u) << longName.output;
  EXPECT_EQ(longName.output.find("terminate called"), std::string::npos) << longName.output;
  // A bad option: every rank meets it, rank 0 says it, and none then says mpirun stopped it (the first rank to exit
  // makes mpirun end the others).
  const test::ToolRun badOption = test::RunTool(kMpirun, kBox + " -q -o " + dir + "/x.ply --max-seconds 0.5");
  EXPECT_EQ(Count(badOption.output, "--max-seconds: error: must lie in [1, 1e7] seconds"), 1u) << badOption.output;
  EXPECT_EQ(badOption.output.find("stopped by mpirun"), std::string::npos) << badOption.output;
}

// dir holds out.ply as it was ("earlier output") and nothing else.
void ExpectOnlyTheEarlierOutput(const std::string& dir) {
  EXPECT_EQ(test::ReadBytes(dir + "/out.ply"), "earlier output");
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u) << "a temporary file was left beside the output";
}

TEST(BakeMpi, AKilledRankFailsTheJobAndLeavesTheEarlierOutput) {
  REQUIRE_BAKE_MPI();
  const std::string dir = test::TempDirectory("bake-mpi-kill");
  std::ofstream(dir + "/out.ply") << "earlier output";
  // 400M photons take minutes; rank 1 (the second of mpirun's children) is killed after two seconds.
  const std::string job = kMpirun + " " + kBox + " -q --photons 400000000 -o " + dir + "/out.ply";
  const test::ToolRun run = test::RunTool("sh", "-c '" + job + " & sleep 2; kill -9 $(pgrep -P $! | sed -n 2p); wait $!'");
  EXPECT_NE(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("rank"), std::string::npos) << run.output;
  ExpectOnlyTheEarlierOutput(dir);
}

TEST(BakeMpi, CtrlCOnMpirunSaysSoAndLeavesTheEarlierOutput) {
  REQUIRE_BAKE_MPI();
  const std::string dir = test::TempDirectory("bake-mpi-interrupt");
  std::ofstream(dir + "/out.ply") << "earlier output";
  // On Ctrl-C mpirun ends every rank with SIGTERM. That SIGTERM is sent here to rank 0 (the first of mpirun's
  // children) itself, once it reports the trace's progress (so past MPI_Init and its handler): sent to mpirun,
  // the SIGINT reached the ranks, but mpirun did not always pass rank 0's last line on before it quit (two
  // clean-clone CI runs of three, under load). The log lives outside `dir`, and is printed after.
  const std::string log = test::TempDirectory("bake-mpi-interrupt-log") + "/log";
  const std::string job = kMpirun + " " + kBox + " --photons 400000000 -o " + dir + "/out.ply > " + log + " 2>&1";
  const std::string tracing = "until grep -q \"trace photons\" " + log + " 2>/dev/null || ! kill -0 $!; do sleep 0.1; done";
  const test::ToolRun run = test::RunTool(
      "sh", "-c '" + job + " & " + tracing + "; kill -TERM $(pgrep -P $! | sed -n 1p); wait $!; s=$?; cat " + log +
                "; exit $s'");
  EXPECT_NE(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("bake-mpi: stopped by mpirun (Ctrl-C, or another rank failed): no output written"),
            std::string::npos)
      << run.output;
  ExpectOnlyTheEarlierOutput(dir);
}

}  // namespace
}  // namespace pb
