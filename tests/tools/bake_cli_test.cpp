// The bake command as a user runs it: exit status, messages that name file:line, no output left behind on
// error, --help that documents units, and byte-identical output for 1 and 2 threads.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <map>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "baker/files/atomic_file.h"
#include "mesh/memory_budget.h"
#include "baker/report.h"
#include "tests/lambert.h"
#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

using BakeRun = test::ToolRun;
using test::RunBake;

// Leaves nothing named out.ply* (the output or its temporary) in `dir`.
bool NoOutputIn(const std::string& dir) {
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().filename().string().rfind("out.ply", 0) == 0) return false;
  return true;
}

TEST(BakeCli, HelpDocumentsEveryOptionWithUnits) {
  const BakeRun run = RunBake("--help");
  EXPECT_EQ(run.status, 0);
  for (const char* text : {"--kernel", "--h", "[m]", "--photons", "--seed", "--threads", "--report", "--scale",
                           "--ascii", "--exposure", "typical", "W/(m^2 sr)", "--refine", "--tolerance",
                           "--max-vertices", "--subdivide"})
    EXPECT_NE(run.output.find(text), std::string::npos) << text << "\n" << run.output;
}

std::set<std::string> Matches(const std::string& text, const std::regex& pattern, int group) {
  std::set<std::string> found;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), pattern); it != std::sregex_iterator(); ++it)
    found.insert((*it)[group]);
  return found;
}

std::string Lines(const std::set<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += " " + n;
  return s;
}

// Every option that docs/bake.md's table and --help document is one the command line takes, and every option it
// takes is documented in both. (--max-bounces was once documented in both and refused by the parser.)
TEST(BakeCli, EveryDocumentedOptionIsACommandLineOption) {
  const BakeRun help = RunBake("--help");
  ASSERT_EQ(help.status, 0);
  // Defined: the option column of --help, "  -o,--output TEXT ..." or "  --h TEXT ...".
  const std::set<std::string> defined = Matches(help.output, std::regex(R"(\n  (?:-\w,)?(--[a-z][a-z-]*))"), 1);
  ASSERT_GT(defined.size(), 20u) << help.output;
  // Mentioned anywhere in --help's text.
  for (const std::string& name : Matches(help.output, std::regex(R"((--[a-z][a-z-]*))"), 1))
    EXPECT_TRUE(defined.count(name)) << name << " is mentioned in --help but is not an option";
  // The manual's table of options, docs/bake.md (every --option the page names must be one).
  std::ifstream file(PB_SOURCE_DIR "/docs/bake.md");
  const std::string section((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  ASSERT_NE(section.find("# Using `bake`"), std::string::npos);
  std::set<std::string> table = Matches(section, std::regex(R"(\n\| `(?:-\w, )?(--[a-z][a-z-]*))"), 1);
  table.insert("--help");
  EXPECT_EQ(table, defined) << "docs/bake.md:" << Lines(table) << "\n--help:" << Lines(defined);
  for (const std::string& name : Matches(section, std::regex(R"((--[a-z][a-z-]*))"), 1))
    EXPECT_TRUE(defined.count(name)) << name << " is mentioned in docs/bake.md but is not an option";
}

// Each numeric option is checked against its documented range before any work is done, and refused as a bad
// command line (exit 2); values too large or small for their type are out of range, never a crash (issue 16).
TEST(BakeCli, OutOfRangeOptionsAreRefusedBeforeAnyWork) {
  const std::string dir = test::TempDirectory("cli-ranges");
  const std::string scene = test::WriteSquareLightOverFloor(dir, 1, 1, 1, 4, 8);
  for (const auto& [option, name] : std::vector<std::pair<std::string, std::string>>{
           {"--h 0", "--h"}, {"--h -1", "--h"}, {"--h 1e300", "--h"}, {"--h 1e-45", "--h"}, {"--h 1e8", "--h"},
           {"--k 1", "--k"}, {"--photons 0", "--photons"}, {"--photons -1", "--photons"},
           {"--threads 4294967295", "--threads"}, {"--scale 0", "--scale"}, {"--scale 1e-38", "--scale"},
           {"--scale 1e11", "--scale"}, {"--max-bounces 10001", "--max-bounces"},
           {"--guide-photons 2000000000", "--guide-photons"}, {"--guide-photons 1000 --gap-paths 0", "--guide-photons"}, {"--exposure 0", "--exposure"},
           {"--exposure inf", "--exposure"}, {"--texel 0", "--texel"}, {"--tolerance 1", "--tolerance"},
           {"--subdivide 9", "--subdivide"}, {"--max-vertices 2", "--max-vertices"},
           {"--target-noise 0", "--target-noise"}, {"--target-noise 0.1 --max-photons 10", "--max-photons"},
           {"--target-error 1", "--target-error"}, {"--target-error 0.03 --target-noise 0.03", "--target-error"},
           {"--target-error 0.03 --estimator knn", "--target-error"}, {"--target-error 0.1 --max-photons 10", "--max-photons"},
           {"--direct-noise 1e-5", "--direct-noise"}, {"--direct-noise 2", "--direct-noise"},
           {"--direct-noise -0.01", "--direct-noise"}}) {
    // 4e8 photons would take minutes: a refusal in moments shows that nothing was traced first.
    const std::string photons = name == "--photons" ? "" : " --photons 400000000 ";
    const BakeRun run = RunBake(scene + " -o " + dir + "/out.ply " + photons + option);
    EXPECT_EQ(run.status, 2) << option << "\n" << run.output;
    EXPECT_NE(run.output.find(name + ": error:"), std::string::npos) << option << "\n" << run.output;
    EXPECT_TRUE(NoOutputIn(dir)) << option;
  }
  // Eight levels of subdivision of the box (1.25e8 faces, about 50 GB) are refused with the estimate, before tracing.
  const BakeRun subdivide = RunBake(PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/out.ply --photons 400000000 "
                                    "--subdivide 8");
  if (MemoryLimitBytes() < 60e9) {  // a machine of this kind
    EXPECT_EQ(subdivide.status, 1) << subdivide.output;
    EXPECT_NE(subdivide.output.find("--subdivide: error: 8 levels of 1906 triangles (1.25e+08 faces) needs about "
                                    "50.0 GB"), std::string::npos) << subdivide.output;
  }
  // A texel too small for this scene's surfaces is bad input for this scene (exit 1), found before tracing.
  const BakeRun texel = RunBake(scene + " -o " + dir + "/out.ply --photons 400000000 --texel 1e-5 --maps " + dir);
  EXPECT_EQ(texel.status, 1) << texel.output;
  EXPECT_NE(texel.output.find("--texel: error: surface 0 would need"), std::string::npos) << texel.output;
}

TEST(BakeCli, BadInputFailsWithFileLineAndLeavesNoOutput) {
  const std::string dir = test::TempDirectory("cli-bad");
  test::WriteText(dir + "/m.mtl", "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 1 1 1\n");
  const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n";
  struct Case {
    std::string name, obj, expected;
  };
  const std::vector<Case> cases = {
      {"missing", "", "missing.obj: error: cannot open scene file"},
      {"malformed", "mtllib m.mtl\nv 1 2 oops\n", "malformed.obj:2: error: malformed number 'oops'"},
      {"index", "mtllib m.mtl\n" + quad + "usemtl grey\nf 1 2 9\n", "index.obj:7: error: vertex index 9 is out of range"},
      {"nan", "mtllib m.mtl\nv 0 0 nan\n", "nan.obj:2: error: non-finite number"},
      {"nolight", "mtllib m.mtl\n" + quad + "usemtl grey\nf 1 4 3 2\n", "nolight.obj: error: scene has no light"},
  };
  for (const Case& c : cases) {
    if (!c.obj.empty()) test::WriteText(dir + "/" + c.name + ".obj", c.obj);
    const BakeRun run = RunBake(dir + "/" + c.name + ".obj -o " + dir + "/out.ply --photons 1000 --report " + dir +
                            "/out.ply.json");
    EXPECT_EQ(run.status, 1) << c.name << ": " << run.output;
    EXPECT_NE(run.output.find(c.expected), std::string::npos) << c.name << ": " << run.output;
    EXPECT_TRUE(NoOutputIn(dir)) << c.name;
  }
}

TEST(BakeCli, BadOptionsFailBeforeAnyWork) {
  const std::string dir = test::TempDirectory("cli-options");
  const std::string scene = test::WriteSquareLightOverFloor(dir, 1, 1, 1, 2, 4);
  const BakeRun h = RunBake(scene + " -o " + dir + "/out.ply --h -1");
  EXPECT_EQ(h.status, 2);
  EXPECT_NE(h.output.find("--h: error: must be a length in [1e-6, 1e4] m"), std::string::npos) << h.output;
  const BakeRun kernel = RunBake(scene + " -o " + dir + "/out.ply --kernel box");
  EXPECT_EQ(kernel.status, 2);
  EXPECT_NE(kernel.output.find("--kernel: unknown kernel 'box'; choose one of: uniform,"), std::string::npos) << kernel.output;
  const BakeRun where = RunBake(scene + " -o /nonexistent/dir/out.ply");
  EXPECT_EQ(where.status, 1);
  EXPECT_NE(where.output.find("/nonexistent/dir/out.ply: error: cannot write here"), std::string::npos);
  const BakeRun missingOutput = RunBake(scene);
  EXPECT_EQ(missingOutput.status, 2);
  for (const char* seed : {"-1", "18446744073709551616", "0x10"}) {  // CLI11 alone read the first two as 2^64 - 1
    const BakeRun run = RunBake(scene + " -o " + dir + "/out.ply --seed " + seed);
    EXPECT_EQ(run.status, 2) << seed;
    EXPECT_NE(run.output.find("--seed: expects a whole number from 0 to 18446744073709551615"), std::string::npos) << run.output;
  }
  EXPECT_TRUE(NoOutputIn(dir));
}

// --exposure has a range, and within it an exposure that shows every lit vertex black or white is warned about
// (issue 39: --exposure 1e-45 wrote an all-black PLY with exit 0).
TEST(BakeCli, AnExposureThatShowsNothingIsRefusedOrWarnedAbout) {
  const std::string dir = test::TempDirectory("cli-exposure");
  const std::string bake = test::WriteSquareLightOverFloor(dir, 1, 1, 1, 2, 4) + " --photons 20000 -o " + dir + "/out.ply";
  const BakeRun tiny = RunBake(bake + " --exposure 1e-45");
  EXPECT_EQ(tiny.status, 2);
  EXPECT_NE(tiny.output.find("--exposure: error: must lie in [1e-30, 1e30]"), std::string::npos) << tiny.output;
  for (const auto& [exposure, shown] : {std::pair{"1e-20", "black"}, std::pair{"1e20", "white"}}) {
    const BakeRun run = RunBake(bake + " --exposure " + exposure);
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find(std::string("warning: the display colours show every lit vertex ") + shown +
                              "; the automatic exposure would be "), std::string::npos) << run.output;
  }
  const BakeRun plain = RunBake(bake + " --exposure 1");
  EXPECT_EQ(plain.output.find("show every lit vertex"), std::string::npos) << plain.output;
}

TEST(BakeCli, RefineKeepsTheBudgetAndReportsItsWork) {
  const std::string dir = test::TempDirectory("cli-refine");
  const std::string common = PB_SOURCE_DIR "/data/box/box.obj --photons 200000 --refine -o " + dir + "/out.ply";
  const BakeRun run = RunBake(common + " --max-vertices 500 --tolerance 0.01 --report " + dir + "/r.json");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("refine    1204 -> "), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("the vertex budget (500 vertices) left faces above the tolerance"), std::string::npos);
  const test::PlyData ply = test::ReadPly(dir + "/out.ply");
  EXPECT_LE(ply.VertexCount(), 500u);
  const nlohmann::json refine = nlohmann::json::parse(test::ReadBytes(dir + "/r.json")).at("refine");
  EXPECT_EQ(refine.at("vertices_before"), 1204);
  EXPECT_EQ(refine.at("vertices_after"), ply.VertexCount());
  EXPECT_GT(refine.at("refused_by_budget").get<int>() + refine.at("collapses_past_tolerance").get<int>(), 0);
  EXPECT_GT(refine.at("max_error").get<double>(), refine.at("mean_error").get<double>());
  for (const std::string bad : {"--tolerance 0", "--tolerance 1.5", "--subdivide 9", "--max-vertices 2"}) {
    const BakeRun failed = RunBake(common + " " + bad);
    EXPECT_EQ(failed.status, 2) << bad;
    EXPECT_NE(failed.output.find(bad.substr(0, bad.find(' ')) + ": error: must"), std::string::npos) << failed.output;
  }
}

TEST(BakeCli, AFailedRunLeavesAnEarlierOutputIntact) {
  const std::string dir = test::TempDirectory("cli-intact");
  test::WriteText(dir + "/out.ply", "previous result");
  test::WriteText(dir + "/bad.obj", "v 1 2 x\n");
  EXPECT_EQ(RunBake(dir + "/bad.obj -o " + dir + "/out.ply").status, 1);
  EXPECT_EQ(test::ReadBytes(dir + "/out.ply"), "previous result");
}

TEST(BakeCli, VersionPrintsAndExits) {
  const BakeRun run = RunBake("--version");
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_EQ(run.output, "photonbake " PB_VERSION "\n");
}

// --maps DIR makes DIR (and its parents) when they are missing; a run that fails takes away what it made.
TEST(BakeCli, MapsFolderIsCreatedAndRemovedAgainOnFailure) {
  const std::string dir = test::TempDirectory("cli-maps-folder");
  const std::string scene = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 2.0f, 4);
  const BakeRun run = RunBake(scene + " -o " + dir + "/out.ply --photons 10000 -q --maps " + dir + "/new/maps");
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/new/maps/surface_0.exr"));
  const BakeRun failed = RunBake(dir + "/missing.obj -o " + dir + "/out2.ply -q --maps " + dir + "/other/maps");
  EXPECT_EQ(failed.status, 1) << failed.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/other")) << "a failed run leaves no folder behind";
  test::WriteText(dir + "/file", "");
  const BakeRun notFolder = RunBake(scene + " -o " + dir + "/out3.ply -q --maps " + dir + "/file/maps");
  EXPECT_EQ(notFolder.status, 1) << notFolder.output;
  EXPECT_NE(notFolder.output.find("cannot create the folder"), std::string::npos) << notFolder.output;
  // --maps naming a file is refused before any work (it failed after the whole bake).
  const BakeRun file = RunBake(scene + " -o " + dir + "/out4.ply --maps " + dir + "/file");
  EXPECT_EQ(file.status, 1) << file.output;
  EXPECT_NE(file.output.find("/file: error: is not a folder"), std::string::npos) << file.output;
  EXPECT_EQ(file.output.find("trace photons"), std::string::npos) << file.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out4.ply"));
}

// Every bake reports its predicted noise (issue 23); above 2% it warns, naming what would bring it under 2%, and
// following that advice does. On the closed-form floor (under a black light, so its light is direct only): with --direct
// photons the remedy is photons; with the direct light sampled it is shadow rays, which photons cannot replace.
TEST(BakeCli, NoiseIsInEverySummaryAndItsRemedyWorks) {
  const std::string dir = test::TempDirectory("cli-noise");
  const std::string scene = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 2.0f, 20, 0.5f);
  const auto bake = [&](const std::string& args) {
    const BakeRun run = RunBake(scene + " -o " + dir + "/out.ply --h 0.1 --report " + dir + "/r.json " + args);
    EXPECT_EQ(run.status, 0) << run.output;
    return std::pair{run.output, nlohmann::json::parse(test::ReadBytes(dir + "/r.json")).at("noise").get<double>()};
  };
  const std::regex advice(R"(the bake's noise is [0-9.]+%.* about (--[a-z-]+) ([0-9]+) would bring it under 2%)");
  for (const std::string mode : {"--direct photons --photons 20000", "--direct sampled --photons 1000000 --direct-samples 4"}) {
    const auto [output, noise] = bake(mode);
    EXPECT_GT(noise, 0.02) << mode;
    EXPECT_NE(output.find(fmt::format("noise     {:.2f}% predicted", 100 * noise)), std::string::npos) << output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(output, m, advice)) << output;
    EXPECT_EQ(m[1], mode.find("photons --") != std::string::npos ? "--photons" : "--direct-samples") << output;
    const std::string followed = std::regex_replace(mode, std::regex(m[1].str() + " [0-9]+"), m[1].str() + " " + m[2].str());
    const auto [after, lower] = bake(followed);
    EXPECT_LE(lower, 0.02) << followed;
    EXPECT_EQ(after.find("enough to show as blotches"), std::string::npos) << after;
  }
}

// With no --h and no --photons the scene chooses (docs/bake.md, "Defaults that suit the scene"): h per surface, and
// rounds to 3% noise, which the summary and the report state; the same bytes on 1 and 2 threads. Given options
// mean exactly what they say: one round of --photons at the given h.
TEST(BakeCli, WithoutHOrPhotonsTheSceneChoosesAndSaysSo) {
  const std::string dir = test::TempDirectory("cli-scene-defaults");
  const std::string scene = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 2.0f, 20, 0.5f);
  const auto bake = [&](const std::string& name, const std::string& args) {
    const BakeRun run = RunBake(scene + " -o " + dir + "/" + name + ".ply --report " + dir + "/" + name + ".json " + args);
    EXPECT_EQ(run.status, 0) << run.output;
    return std::pair{run.output, nlohmann::json::parse(test::ReadBytes(dir + "/" + name + ".json"))};
  };
  const auto [summary, report] = bake("one", "--threads 1");
  EXPECT_EQ(report.at("options").at("h_m"), "auto");
  EXPECT_FLOAT_EQ(report.at("progressive").at("target_noise").get<float>(), 0.03f);
  const nlohmann::json& rounds = report.at("progressive").at("rounds");
  ASSERT_GE(rounds.size(), 1u);
  EXPECT_TRUE(report.at("progressive").at("target_met").get<bool>()) << summary;
  EXPECT_LE(report.at("noise").get<double>(), 0.03);
  EXPECT_NE(summary.find("to target noise 0.0300"), std::string::npos) << summary;
  EXPECT_NE(summary.find("per surface from its photons (--h auto)"), std::string::npos) << summary;
  bake("two", "--threads 2");
  EXPECT_TRUE(test::ReadBytes(dir + "/one.ply") == test::ReadBytes(dir + "/two.ply"));

  const auto [given, fixed] = bake("given", "--h 0.05 --photons 50000");
  EXPECT_FLOAT_EQ(fixed.at("options").at("h_m").get<float>(), 0.05f);
  EXPECT_TRUE(fixed.at("progressive").at("rounds").empty());
  EXPECT_GE(fixed.at("photons").at("emitted").get<uint64_t>(), 49'999u);  // n Phi_l / Phi rounded down per light
  for (const nlohmann::json& surface : fixed.at("surfaces")) EXPECT_FLOAT_EQ(surface.at("h_m").get<float>(), 0.05f);
}

// With --direct-noise the points' count follows their target, so the remedy names a lower target, and following it
// brings the noise under 2%.
TEST(BakeCli, WithADirectNoiseTargetTheRemedyIsALowerTarget) {
  const std::string dir = test::TempDirectory("cli-direct-noise");
  const std::string scene = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 2.0f, 20, 0.5f);
  const auto bake = [&](const std::string& args) {
    const BakeRun run = RunBake(scene + " -o " + dir + "/out.ply --h 0.1 --photons 1000000 --direct-samples 65536 --report " + dir +
                                "/r.json " + args);
    EXPECT_EQ(run.status, 0) << run.output;
    return std::pair{run.output, nlohmann::json::parse(test::ReadBytes(dir + "/r.json")).at("noise").get<double>()};
  };
  const auto [output, noise] = bake("--direct-noise 0.2");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(output, m, std::regex(R"(about --direct-noise ([0-9.e-]+) would bring it under 2%)")))
      << output;
  const double target = std::stod(m[1].str());
  EXPECT_LT(target, 0.2);
  const auto [after, lower] = bake("--direct-noise " + m[1].str());
  std::printf("noise %.4f at --direct-noise 0.2, %.4f at the advised %g\n", noise, lower, target);
  EXPECT_LE(lower, 0.02);
  EXPECT_EQ(after.find("enough to show as blotches"), std::string::npos) << after;
}

// Off a terminal, every long stage prints its final line, with its rate, and every stage ends at 100%: coarsening
// stops when no collapse is left within the tolerance, long before its bound of one per vertex (issue 23).
TEST(BakeCli, EveryStageEndsAt100PercentWithItsRate) {
  const std::string dir = test::TempDirectory("cli-progress");
  const BakeRun run = RunBake(PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/out.ply --photons 50000 --refine");
  ASSERT_EQ(run.status, 0) << run.output;
  const std::regex line(R"(^  ([a-z ]+?) +([0-9.]+)%  +([0-9]+) / ([0-9]+) +[0-9.]+ s +[0-9.]+( [kMG])?/s)");
  // Each stage's last line (a stage that lasts over 5 s, as under the sanitizers, prints earlier ones too).
  std::map<std::string, std::array<std::string, 4>> last;
  std::istringstream lines(run.output);
  for (std::string text; std::getline(lines, text);) {
    std::smatch m;
    if (std::regex_search(text, m, line)) last[m[1]] = {text, m[2], m[3], m[4]};
  }
  for (const auto& [stage, final] : last) {
    EXPECT_EQ(final[1], "100.0") << final[0];
    EXPECT_EQ(final[2], final[3]) << final[0];
  }
  for (const char* stage : {"trace photons", "estimate irradiance", "coarsen mesh", "measure mesh error", "find covers"})
    EXPECT_TRUE(last.count(stage)) << stage << " printed no progress line:\n" << run.output;
}

// --quality names a target and the first round's photons; h is the scene's (--h auto) and the rounds choose the
// shadow rays. On the square light over a grey floor (Lambert's formula is H), with the photons carrying the
// direct light too (so that the photons' noise is the error), draft's error target of 8% is met, and the floor
// vertices' error in the target's measure (the RMS over them relative to their mean H) lies within 1.5 times it.
// draft's first round takes 16 shadow rays and 16 gathered paths a point. medium is the defaults' noise target.
// production also gathers the edges. What the command line gives explicitly wins.
TEST(BakeCli, QualityPresetsAreTargetsWithTheScenesH) {
  const std::string dir = test::TempDirectory("cli-quality");
  const std::string scene = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 40, 0.5f);
  const auto report = [&](const std::string& args) {
    const BakeRun run = RunBake(scene + " -o " + dir + "/out.ply -q --report " + dir + "/r.json " + args);
    EXPECT_EQ(run.status, 0) << args << ": " << run.output;
    return nlohmann::json::parse(test::ReadBytes(dir + "/r.json"));
  };
  const nlohmann::json draft = report("--quality draft --direct photons --ascii");
  EXPECT_EQ(draft.at("options").at("photons"), 160000);
  EXPECT_EQ(draft.at("options").at("h_m"), "auto");
  EXPECT_FLOAT_EQ(draft.at("options").at("target_error").get<float>(), 0.08f);
  const nlohmann::json& rounds = draft.at("progressive").at("rounds");
  ASSERT_FALSE(rounds.empty());
  EXPECT_LE(rounds.back().at("error").get<double>(), 0.08);
  EXPECT_TRUE(draft.at("progressive").at("target_met").get<bool>());
  // With the photons carrying all the light, their noise alone is the bake's.
  EXPECT_DOUBLE_EQ(draft.at("noise_parts").at("photons").get<double>(), draft.at("noise").get<double>());
  EXPECT_EQ(draft.at("noise_parts").at("points").get<double>(), 0.0);
  const test::PlyData ply = test::ReadPly(dir + "/out.ply");
  double sum = 0, squared = 0, n = 0;
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    if (ply.vertex.at("y")[v] != 0) continue;
    const double exact = test::SquareLightIrradiance(ply.vertex.at("x")[v], ply.vertex.at("z")[v]);
    sum += exact, squared += std::pow(ply.vertex.at("irradiance_g")[v] - exact, 2), ++n;
  }
  const double rmse = std::sqrt(squared / n) / (sum / n);
  std::printf("draft: relative RMS error %.4f against its target 0.08\n", rmse);
  EXPECT_LT(rmse, 1.5 * 0.08);
  const nlohmann::json sampledReport = report("--quality draft");
  const nlohmann::json& sampled = sampledReport.at("options");
  EXPECT_EQ(sampled.at("direct_samples"), 16);
  EXPECT_EQ(sampled.at("gap_paths"), 16);
  const double noise = sampledReport.at("noise").get<double>();  // each source alone is at most the whole
  EXPECT_GT(sampledReport.at("noise_parts").at("points").get<double>(), 0.0);
  for (const char* part : {"photons", "points", "gathered"})
    EXPECT_LE(sampledReport.at("noise_parts").at(part).get<double>(), noise) << part;
  EXPECT_EQ(report("--quality draft --direct-samples 64").at("options").at("direct_samples"), 64);
  EXPECT_FLOAT_EQ(report("--quality medium --direct photons").at("options").at("target_noise").get<float>(), 0.03f);
  const nlohmann::json given = report("--quality production --photons 1000 --h 0.2 --direct-samples 9 --target-noise 0.5");
  EXPECT_EQ(given.at("options").at("photons"), 1000);
  EXPECT_FLOAT_EQ(given.at("options").at("h_m").get<float>(), 0.2f);
  EXPECT_EQ(given.at("options").at("direct_samples"), 9);
  EXPECT_FLOAT_EQ(given.at("options").at("target_noise").get<float>(), 0.5f);
  EXPECT_EQ(given.at("options").at("gap_edges"), true);  // production gathers the edges, from 1,024 paths
  EXPECT_EQ(given.at("options").at("gap_paths"), 1024);
  EXPECT_EQ(report("--quality production --photons 1000 --target-noise 0.5 --gap-paths 16").at("options").at("gap_paths"), 16);
  // Every bake gathers on its smallest surfaces, up to a tenth of the triangles, unless --gap-small-area is given.
  EXPECT_FLOAT_EQ(given.at("options").at("gap_small_area_h2").get<float>(), 6.0f);
  EXPECT_FLOAT_EQ(given.at("options").at("gap_small_share").get<float>(), 0.1f);
  const nlohmann::json all = report("--quality medium --direct photons --gap-small-area 4").at("options");
  EXPECT_FLOAT_EQ(all.at("gap_small_area_h2").get<float>(), 4.0f);
  EXPECT_FLOAT_EQ(all.at("gap_small_share").get<float>(), 1.0f);
  const BakeRun bad = RunBake(scene + " -o " + dir + "/out.ply --quality ultra");
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find("draft, medium, high, production"), std::string::npos) << bad.output;
}

TEST(BakeCli, EveryEstimatorAndAutoBandwidthRunAndAreReported) {
  const std::string dir = test::TempDirectory("cli-estimators");
  const std::string scene = test::WriteSquareLightOverFloor(dir, 1, 1, 1, 2, 8);
  for (const std::string args : {"--estimator histogram --h 0.1", "--estimator knn --k 30", "--kernel gaussian --h auto",
                                  "--kernel cone --no-edge-correction"}) {
    const BakeRun run = RunBake(scene + " -o " + dir + "/out.ply --photons 20000 --report " + dir + "/r.json " + args);
    ASSERT_EQ(run.status, 0) << args << "\n" << run.output;
    const nlohmann::json report = nlohmann::json::parse(test::ReadBytes(dir + "/r.json"));
    for (const auto& surface : report.at("surfaces")) EXPECT_GT(surface.at("h_m").get<double>(), 0.0) << args;
    if (args.find("auto") != std::string::npos) {
      EXPECT_EQ(report.at("options").at("h_m"), "auto");
    }
    EXPECT_EQ(report.at("photons").at("record_bytes"), 28);
  }
  const BakeRun bad = RunBake(scene + " -o " + dir + "/out.ply --estimator kde");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("unknown estimator 'kde'; choose one of: kernel, histogram, knn"), std::string::npos);
  EXPECT_EQ(RunBake(scene + " -o " + dir + "/out.ply --k 1").status, 2);
}

TEST(BakeCli, OneAndTwoThreadsWriteIdenticalBytes) {
  const std::string dir = test::TempDirectory("cli-determinism");
  const std::string common = PB_SOURCE_DIR "/data/box/box.obj --photons 300000 -q -o " + dir;
  ASSERT_EQ(RunBake(common + "/one.ply --seed 9 --threads 1").status, 0);
  ASSERT_EQ(RunBake(common + "/two.ply --seed 9 --threads 2").status, 0);
  ASSERT_EQ(RunBake(common + "/other-seed.ply --seed 10 --threads 2").status, 0);
  const std::string one = test::ReadBytes(dir + "/one.ply");
  EXPECT_GT(one.size(), 10000u);
  EXPECT_TRUE(one == test::ReadBytes(dir + "/two.ply")) << "thread count changed the output";
  EXPECT_FALSE(one == test::ReadBytes(dir + "/other-seed.ply")) << "the seed has no effect";
}

TEST(BakeCli, BoxBakesToAReadablePlyWithTheContractProperties) {
  const std::string dir = test::TempDirectory("cli-box");
  const BakeRun run = RunBake(PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/box.ply --photons 200000 --report " +
                          dir + "/box.json");
  ASSERT_EQ(run.status, 0) << run.output;
  for (const char* text : {"photons", "emitted", "absorbed", "escaped", "floor", "seconds", "trace"})
    EXPECT_NE(run.output.find(text), std::string::npos) << text;
  const test::PlyData ply = test::ReadPly(dir + "/box.ply");
  EXPECT_EQ(ply.format, "binary_little_endian");
  const std::vector<std::string> expected = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue",
                                             "irradiance_r", "irradiance_g", "irradiance_b", "radiance_r",
                                             "radiance_g", "radiance_b", "quality", "reflectance_r",
                                             "reflectance_g", "reflectance_b"};
  EXPECT_EQ(ply.vertexProperties, expected);
  EXPECT_GT(ply.faces.size(), 1000u);
  for (const auto& [name, values] : ply.vertex)
    for (double v : values) ASSERT_TRUE(std::isfinite(v)) << name;
  // Radiance = Le + Kd H / pi: check on floor vertices (white, Kd 0.73, y = 0, facing up).
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    if (ply.vertex.at("y")[v] != 0.0 || ply.vertex.at("ny")[v] < 0.99) continue;
    ASSERT_NEAR(ply.vertex.at("reflectance_g")[v], 0.73, 1e-6);
    ASSERT_NEAR(ply.vertex.at("radiance_g")[v], 0.73 * ply.vertex.at("irradiance_g")[v] / 3.14159265358979, 1e-6);
  }
  const std::string json = test::ReadBytes(dir + "/box.json");
  for (const char* key : {"\"photons\"", "\"emitted\"", "\"hits_stored\"", "\"seconds\"", "\"effects\"",
                          "\"surfaces\"", "\"front_hits\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
  // ASCII output holds the same numbers.
  ASSERT_EQ(RunBake(PB_SOURCE_DIR "/data/box/box.obj -q --ascii --photons 200000 -o " + dir + "/box-ascii.ply").status,
            0);
  const test::PlyData ascii = test::ReadPly(dir + "/box-ascii.ply");
  EXPECT_EQ(ascii.format, "ascii");
  ASSERT_EQ(ascii.VertexCount(), ply.VertexCount());
  for (size_t v = 0; v < ply.VertexCount(); v += 37)
    EXPECT_FLOAT_EQ(float(ascii.vertex.at("irradiance_r")[v]), float(ply.vertex.at("irradiance_r")[v]));
}


// Text from scene files in any encoding: a Latin-1 material name ("Terraind\xe6k"), object name ("Bygning\xf8")
// and scene path ("sc\xe6ne.obj") are written to the JSON report as U+FFFD, not an abort after the PLY was
// replaced.
TEST(BakeCli, ANonUtf8NameIsReplacedInTheReport) {
  const std::string dir = test::TempDirectory("cli-latin1");
  test::WriteText(dir + "/m.mtl", "newmtl Terraind\xe6k\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 1 1 1\n");
  const std::string scene = dir + "/sc\xe6ne.obj";
  test::WriteText(scene, "mtllib m.mtl\no Bygning\xf8\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nusemtl Terraind\xe6k\n"
                         "f 1 4 3 2\nv 0 1 0\nv 0.2 1 0\nv 0.2 1 0.2\nv 0 1 0.2\nusemtl lamp\nf 5 6 7 8\n");
  const BakeRun run = RunBake(scene + " -q -o " + dir + "/out.ply --photons 1000 --report " + dir + "/r.json");
  ASSERT_EQ(run.status, 0) << run.output;
  const nlohmann::json r = nlohmann::json::parse(test::ReadBytes(dir + "/r.json"));
  EXPECT_EQ(r.at("surfaces").at(0).at("material").get<std::string>(), "Terraind\xef\xbf\xbdk");
  EXPECT_EQ(r.at("surfaces").at(0).at("object").get<std::string>(), "Bygning\xef\xbf\xbd");
  EXPECT_NE(r.dump().find("sc\xef\xbf\xbdne.obj"), std::string::npos) << "the scene path, replaced";
  // So in a glTF output (issue 60: the JSON writer threw after the bake), .gltf and .glb alike.
  for (const char* name : {"/out.gltf", "/out.glb"}) {
    const BakeRun gltf = RunBake(scene + " -q -o " + dir + name + " --photons 1000");
    ASSERT_EQ(gltf.status, 0) << gltf.output;
    EXPECT_NE(test::ReadBytes(dir + name).find("Bygning\xef\xbf\xbd"), std::string::npos) << name;
  }
}

// A light named with terminal escape codes (issue 60: printed raw, they retitled and cleared the terminal) is
// printed with its control characters written out, in the summary and in warnings alike.
TEST(BakeCli, NamesWithControlCharactersArePrintedSafely) {
  const std::string dir = test::TempDirectory("cli-escapes");
  const std::string evil = "lamp\x1b]0;pwned\x07\x1b[2J";
  test::WriteText(dir + "/m.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl " + evil + "\nKe 1 1 1\n");
  test::WriteText(dir + "/s.obj", "mtllib m.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nusemtl floor\nf 1 4 3 2\n"
                                  "v 0 1 0\nv 0.2 1 0\nv 0.2 1 0.2\nv 0 1 0.2\nusemtl " + evil + "\nf 5 6 7 8\n");
  const BakeRun run = RunBake(dir + "/s.obj -o " + dir + "/out.ply --photons 1000");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_EQ(run.output.find('\x1b'), std::string::npos);
  EXPECT_EQ(run.output.find('\x07'), std::string::npos);
  EXPECT_NE(run.output.find("lamp\\x1b]0;pwned\\x07\\x1b[2J"), std::string::npos) << run.output;
}

// A glTF scene that cannot be read is refused with its file and the JSON path of the fault, exit 1, and the
// output it would have replaced is left as it was.
TEST(BakeCli, ABadGltfSceneIsRefusedAndNothingIsWritten) {
  const std::string dir = test::TempDirectory("cli-bad-gltf");
  test::WriteText(dir + "/s.gltf", R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
      "nodes": [{"mesh": 3}], "meshes": []})");
  test::WriteText(dir + "/out.glb", "earlier");
  const BakeRun run = RunBake(dir + "/s.gltf -o " + dir + "/out.glb --photons 1000");
  EXPECT_EQ(run.status, 1) << run.output;
  EXPECT_NE(run.output.find("s.gltf: error: /nodes/0: mesh 3 does not exist"), std::string::npos) << run.output;
  EXPECT_EQ(test::ReadBytes(dir + "/out.glb"), "earlier");
  size_t files = 0;
  for ([[maybe_unused]] const auto& f : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 2u) << "no temporary file is left";
}

// Ke so large that Phi = pi Ke A overflows float (1e36 on a 20 x 20 m light) is refused, not a NaN photon count.
TEST(BakeCli, ALightWhoseFluxOverflowsIsRefused) {
  const std::string dir = test::TempDirectory("cli-bright");
  for (const std::string ke : {"1e36", "3.4e38"}) {
    test::WriteText(dir + "/m.mtl", "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl sun\nKe " + ke + " " + ke + " " + ke + "\n");
    test::WriteText(dir + "/s.obj", "mtllib m.mtl\nv -10 0 -10\nv 10 0 -10\nv 10 0 10\nv -10 0 10\nusemtl grey\n"
                                    "f 1 4 3 2\nv -10 1 -10\nv 10 1 -10\nv 10 1 10\nv -10 1 10\nusemtl sun\nf 5 6 7 8\n");
    const BakeRun run = RunBake(dir + "/s.obj -o " + dir + "/out.ply --photons 1000");
    EXPECT_EQ(run.status, 1) << ke << "\n" << run.output;
    EXPECT_NE(run.output.find("the light of material 'sun' emits"), std::string::npos) << run.output;
    EXPECT_TRUE(NoOutputIn(dir));
  }
}

// A light whose share of --photons is below one photon is named in a warning, with the count that would reach it.
TEST(BakeCli, ALightThatGetsNoPhotonIsWarnedAbout) {
  const std::string dir = test::TempDirectory("cli-unlit");
  const std::string scene = test::WriteTwoLamps(dir);
  const BakeRun few = RunBake(scene + " -o " + dir + "/out.ply --photons 3");  // light a: floor(3/4) = 0
  ASSERT_EQ(few.status, 0) << few.output;
  EXPECT_NE(few.output.find("warning: the light of material 'a' (3.14 W of 12.6 W) got no photon, so its "
                            "interreflected light is missing (the direct light is sampled); raise --photons to at "
                            "least 4"), std::string::npos) << few.output;
  const BakeRun photonsOnly = RunBake(scene + " -o " + dir + "/out.ply --photons 3 --direct photons");
  EXPECT_NE(photonsOnly.output.find("(3.14 W of 12.6 W) got no photon, so its light is missing; raise --photons to "
                                    "at least 4"), std::string::npos) << photonsOnly.output;
  const BakeRun enough = RunBake(scene + " -o " + dir + "/out.ply --photons 4");
  EXPECT_EQ(enough.output.find("got no photon"), std::string::npos) << enough.output;
}

// Many such lights make one line, not one each: how many, their flux and share of it, and the brightest three.
// 100 lamps of equal area over three decades of radiance at 50 photons: a lamp gets floor(50 L / sum L) photons.
TEST(BakeCli, ManyLightsWithoutPhotonsAreSummarisedInOneLine) {
  const std::string dir = test::TempDirectory("cli-unlit-many");
  constexpr int kSide = 10;
  const std::string scene = test::WriteLampGrid(dir, kSide, 0.2f, 0.05f, 1.0f, 3.0f);
  double total = 0, dark = 0;
  int unlit = 0;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j) total += test::LampGridRadiance(i, j);
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j)
      if (std::floor(50 * test::LampGridRadiance(i, j) / total) == 0) ++unlit, dark += test::LampGridRadiance(i, j);
  const BakeRun run = RunBake(scene + " -o " + dir + "/out.ply --photons 50 --direct-samples 4");
  ASSERT_EQ(run.status, 0) << run.output;
  const size_t first = run.output.find("got no photon");
  ASSERT_NE(first, std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("got no photon", first + 1), std::string::npos) << "one line\n" << run.output;
  EXPECT_NE(run.output.find(fmt::format("warning: {} of {} lights got no photon", unlit, kSide * kSide)),
            std::string::npos) << run.output;
  EXPECT_NE(run.output.find(fmt::format("({:.2g}% of the flux)", 100 * dark / total)), std::string::npos) << run.output;
  EXPECT_TRUE(std::regex_search(run.output, std::regex("; the brightest: the light of material 'lamp_[0-9]+' "
                                                      "\\([0-9.e+-]+ W, light [0-9]+\\)")))
      << run.output;
}

// Millions of surfaces or lights keep the report small: 1,089 lamps (1,090 surfaces with the floor) list the
// 1,000 largest surfaces and the 1,000 brightest lights, each with its index, in index order, and totals over
// all; --report-all lists every one; the summary prints at most 40 lights.
TEST(BakeCli, TheReportListsTheLargestSurfacesAndBrightestLightsAndSummarisesAll) {
  const std::string dir = test::TempDirectory("cli-report-many");
  constexpr int kSide = 33;
  const std::string scene = test::WriteLampGrid(dir, kSide, 0.1f, 0.05f, 1.0f, 4.0f);
  const auto report = [&](const std::string& extra) {
    const BakeRun run = RunBake(scene + " -o " + dir + "/out.ply --photons 20000 --direct-samples 1 --report " + dir +
                                "/r.json" + extra);
    EXPECT_EQ(run.status, 0) << run.output;
    return std::pair{run.output, nlohmann::json::parse(test::ReadBytes(dir + "/r.json"))};
  };
  const auto [output, listed] = report("");
  const auto [allOutput, all] = report(" --report-all");
  EXPECT_NE(output.find("... 1049 more lights in --report"), std::string::npos) << output;
  ASSERT_EQ(all.at("lights").size(), size_t(kSide * kSide));
  ASSERT_EQ(all.at("surfaces").size(), size_t(kSide * kSide + 1));
  ASSERT_EQ(listed.at("lights").size(), kListed);
  ASSERT_EQ(listed.at("surfaces").size(), kListed);
  EXPECT_EQ(listed.at("lights_summary").at("count"), kSide * kSide);
  EXPECT_EQ(listed.at("surfaces_summary").at("count"), kSide * kSide + 1);
  nlohmann::json totals = all.at("surfaces_summary");
  totals["listed"] = kListed;
  EXPECT_EQ(listed.at("surfaces_summary"), totals) << "the same totals over all surfaces";
  // The brightest 1,000 by power, ties by index, from the full list; and the floor among the largest surfaces.
  std::vector<std::pair<double, size_t>> powers;
  for (const auto& l : all.at("lights")) powers.push_back({-l.at("power_W")[1].get<double>(), l.at("light").get<size_t>()});
  std::sort(powers.begin(), powers.end());
  std::vector<size_t> brightest;
  for (size_t i = 0; i < kListed; ++i) brightest.push_back(powers[i].second);
  std::sort(brightest.begin(), brightest.end());
  std::vector<size_t> got;
  for (const auto& l : listed.at("lights")) got.push_back(l.at("light").get<size_t>());
  EXPECT_EQ(got, brightest);
  EXPECT_EQ(listed.at("surfaces")[0].at("surface"), 0) << "the floor, the largest, first";
}

TEST(BakeCli, ResumeAndTargetNoiseAreReported) {
  const std::string dir = test::TempDirectory("cli-progressive");
  const std::string common = PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/out.ply";
  ASSERT_EQ(RunBake(common + " --photons 100000 -q --save-photons " + dir + "/s.photons").status, 0);
  const BakeRun run = RunBake(common + " --photons 100000 --resume " + dir + "/s.photons --target-noise 0.04 --report " + dir + "/r.json");
  ASSERT_EQ(run.status, 0) << run.output;
  for (const char* text : {"resumed   99999 photons from", "rounds    ", "met", "round 1: 99999 photons"})
    EXPECT_NE(run.output.find(text), std::string::npos) << text << "\n" << run.output;
  const nlohmann::json r = nlohmann::json::parse(test::ReadBytes(dir + "/r.json"));
  EXPECT_TRUE(r.at("progressive").at("target_met").get<bool>());
  EXPECT_LE(r.at("progressive").at("rounds").back().at("noise").get<double>(), 0.04);
  const BakeRun refused = RunBake(common + " --resume " + dir + "/s.photons --seed 3");
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.output.find("s.photons: error: cannot resume: the photons were traced with --seed 1, not 3"),
            std::string::npos) << refused.output;
  EXPECT_EQ(RunBake(common + " --target-noise 0").status, 2);
  const BakeRun knn = RunBake(common + " --target-noise 0.05 --estimator knn --k 50");
  EXPECT_EQ(knn.status, 2);
  EXPECT_NE(knn.output.find("knn's noise is 1/sqrt(k - 2) = 0.144 for --k 50, whatever the photon count: raise --k "
                            "to 402 or more"), std::string::npos) << knn.output;
  EXPECT_EQ(RunBake(common + " --target-noise 0.02 --photons 1000 --max-photons 10").status, 2);
}

}  // namespace
}  // namespace pb
