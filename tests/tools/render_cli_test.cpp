// The render command as a user runs it: it writes an EXR whose header names radiance and its units, whose pixels
// match the PNG's exposure-free source, and a PNG beside it; an spp sweep writes one image per count and a strip;
// bad options exit 2 and bad input exits 1 naming the file, leaving nothing behind.
#include <gtest/gtest.h>

#include <filesystem>

#include "baker/files/image_io.h"
#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

namespace fs = std::filesystem;

test::ToolRun RunRender(const std::string& arguments) { return test::RunTool(PB_RENDER_EXE, arguments); }
const std::string kBox = PB_SOURCE_DIR "/data/box/box.obj";

TEST(RenderCli, WritesRadianceExrWithUnitsAndAPng) {
  const std::string dir = test::TempDirectory("render-cli");
  const test::ToolRun run = RunRender(kBox + " -o " + dir + "/box.exr --size 16x12 --spp 4 --sampling photons "
                                      "--photons 20000 --warp inversion --regions 6x10");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("importance maps"), std::string::npos) << run.output;
  std::vector<std::pair<std::string, std::string>> attributes;
  const Image image = ReadExr(dir + "/box.exr", &attributes);
  EXPECT_EQ(image.width, 16);
  EXPECT_EQ(image.height, 12);
  const auto value = [&](const std::string& key) {
    for (const auto& [k, v] : attributes)
      if (k == key) return v;
    return std::string("<missing>");
  };
  EXPECT_EQ(value("quantity"), "radiance");
  EXPECT_EQ(value("units").rfind("W/(m^2 sr)", 0), 0u) << value("units");
  EXPECT_EQ(value("sampling"), "photons");
  EXPECT_EQ(value("regions"), "6x10");
  double sum = 0;
  for (const Rgb& p : image.pixels) sum += Luminance(p);
  EXPECT_GT(sum, 0);
  EXPECT_TRUE(fs::exists(dir + "/box.png"));
}

TEST(RenderCli, SppSweepWritesOneImagePerCountAndAStrip) {
  const std::string dir = test::TempDirectory("render-sweep");
  const test::ToolRun run = RunRender(kBox + " -o " + dir + "/box.exr --size 8x8 --spp-sweep 1,2,4 -q");
  ASSERT_EQ(run.status, 0) << run.output;
  for (const char* name : {"box_spp1.exr", "box_spp2.png", "box_spp4.exr", "box_strip.png"})
    EXPECT_TRUE(fs::exists(dir + "/" + name)) << name;
  EXPECT_EQ(ReadExr(dir + "/box_spp4.exr").width, 8);
}

TEST(RenderCli, RefusesBadOptionsAndBadInput) {
  const std::string dir = test::TempDirectory("render-bad");
  EXPECT_EQ(RunRender(kBox + " -o " + dir + "/o.exr --sampling guess").status, 2);
  EXPECT_EQ(RunRender(kBox + " -o " + dir + "/o.exr --regions 8by16").status, 2);
  const test::ToolRun odd = RunRender(kBox + " -o " + dir + "/o.exr --regions 6x10 --warp mipmap");
  EXPECT_EQ(odd.status, 2);
  EXPECT_NE(odd.output.find("power-of-two"), std::string::npos) << odd.output;
  // 65536 x 65536 regions once overflowed int inside their own check (issue 16).
  const test::ToolRun huge = RunRender(kBox + " -o " + dir + "/o.exr --regions 65536x65536");
  EXPECT_EQ(huge.status, 2);
  EXPECT_NE(huge.output.find("--regions: error: needs ROWSxCOLS with 1 <= ROWS x COLS <= 65536"), std::string::npos)
      << huge.output;
  test::WriteText(dir + "/bad.camera.json", "{\"position_m\": [0, 0, 0],\n \"look_at_m\": [0, 0],\n}");
  const test::ToolRun camera = RunRender(kBox + " -o " + dir + "/o.exr --camera " + dir + "/bad.camera.json");
  EXPECT_EQ(camera.status, 1);
  EXPECT_NE(camera.output.find("bad.camera.json:"), std::string::npos) << camera.output;
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_NE(entry.path().extension(), ".exr") << "nothing written on error: " << entry.path();
}

// Each image a render writes is checked against the scene's inputs: -o tex writes tex.png, which must not replace
// the scene's texture of that name.
TEST(RenderCli, RefusesToOverwriteAnInputWithAnImage) {
  const std::string dir = test::TempDirectory("render-overwrite");
  for (const char* file : {"box.obj", "box.mtl", "box.camera.json"})
    fs::copy_file(PB_SOURCE_DIR "/data/box/" + std::string(file), dir + "/" + file);
  const std::string texture = test::AddTexture(dir + "/box.mtl");
  const std::string before = test::ReadBytes(texture);
  const test::ToolRun run = RunRender(dir + "/box.obj -o " + dir + "/tex --size 8x8 --spp 1");
  EXPECT_EQ(run.status, 1) << run.output;
  EXPECT_NE(run.output.find("-o would overwrite the input the texture"), std::string::npos) << run.output;
  EXPECT_TRUE(test::ReadBytes(texture) == before);
  EXPECT_FALSE(fs::exists(dir + "/tex.exr"));
}

}  // namespace
}  // namespace pb
