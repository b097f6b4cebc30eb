// --preview (baker/5_write_preview.h): each pixel shows the display colours of the vertices, interpolated across
// the triangle under it, as a viewer shows a PLY; pixels that see nothing are black.
#include "baker/5_write_preview.h"

#include <gtest/gtest.h>
#include <png.h>

#include <array>
#include <filesystem>
#include <cmath>
#include <string>
#include <vector>

#include "baker/runtime/progress.h"
#include "baker/tone_map.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

struct Png {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  std::array<int, 3> At(int x, int y) const {
    const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

Png ReadPng(const std::string& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  EXPECT_TRUE(png_image_begin_read_from_file(&image, path.c_str())) << path;
  image.format = PNG_FORMAT_RGB;
  Png png{int(image.width), int(image.height), std::vector<uint8_t>(PNG_IMAGE_SIZE(image))};
  EXPECT_TRUE(png_image_finish_read(&image, nullptr, png.rgb.data(), 0, nullptr));
  return png;
}

// A 2 x 2 m quad in the plane z = 0, facing +z, whose four corners have four radiances, seen head-on from z = 2.
BakedMesh Quad(const std::array<Rgb, 4>& radiance) {
  BakedMesh b;
  const std::array<Point3, 4> corners = {{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}};
  for (int i = 0; i < 4; ++i) {
    b.mesh.AddVertex(corners[size_t(i)], {0, 0, 1}, {}, {}, 0, 1);
    b.irradiance.push_back(radiance[size_t(i)] * float(kPi));  // L = R H / pi with R = 1
    b.albedo.push_back({1, 1, 1});
    b.emitted.push_back({});
  }
  b.mesh.faces = {{0, 1, 2}, {0, 2, 3}};
  return b;
}

TEST(Preview, PixelsInterpolateTheVertexColoursAndTheRestIsBlack) {
  const std::array<Rgb, 4> radiance = {Rgb{0.2f, 0.2f, 0.2f}, Rgb{0.8f, 0.2f, 0.2f}, Rgb{0.8f, 0.8f, 0.2f},
                                       Rgb{0.2f, 0.8f, 0.2f}};
  const BakedMesh quad = Quad(radiance);
  // 90 degrees of view from 2 m: the image spans 4 m, the quad its middle half.
  PreviewSettings s{{{0, 0, 2}, {0, 0, 0}, {0, 1, 0}, 90}, 64, 64, 1.0f};
  const std::string path = test::TempDirectory("preview") + "/p.png";
  OutputFiles outputs;
  std::vector<std::string> heard;
  const Log log(true, [&](const std::string& line) { heard.push_back(line); });
  WritePreview(outputs, path, quad, s, log);
  outputs.Commit();
  // Its BVH and its rows each show their progress (a million triangles took over a second without a line).
  EXPECT_EQ(heard, (std::vector<std::string>{"preview bvh (thousandths): done", "preview (rows): done"}));
  const Png png = ReadPng(path);
  ASSERT_EQ(png.width, 64);
  ASSERT_EQ(png.height, 64);
  EXPECT_EQ(png.At(2, 2), (std::array<int, 3>{0, 0, 0})) << "outside the quad";
  EXPECT_EQ(png.At(61, 40), (std::array<int, 3>{0, 0, 0}));
  // Red runs 0.2 -> 0.8 from left (x = -1 m, pixel 16) to right (x = 1 m, pixel 48); green from bottom to top.
  // The encoded colours are interpolated, so a pixel's red is the corners' encoded reds mixed by its position.
  const std::array<uint8_t, 3> dark = ToneMap(radiance[0], 1.0f), bright = ToneMap(radiance[1], 1.0f);
  for (int x = 17; x < 47; x += 5) {
    const double u = (x + 0.5 - 16) / 32.0;  // across the quad, 0 at its left edge
    const double expected = (1 - u) * dark[0] + u * bright[0];
    EXPECT_NEAR(png.At(x, 44)[0], expected, 1.0) << "pixel " << x;
    EXPECT_NEAR(png.At(x, 20)[0], expected, 1.0) << "pixel " << x << ", higher up";
  }
  EXPECT_GT(png.At(32, 18)[1], png.At(32, 46)[1] + 40) << "green rises toward the top (+y is up)";
  // Seen from behind, the quad shows the same colours, mirrored left to right.
  s.camera.position = {0, 0, -2};
  OutputFiles back;
  WritePreview(back, path, quad, s, Log(true));
  back.Commit();
  const Png behind = ReadPng(path);
  EXPECT_NEAR(behind.At(20, 32)[0], png.At(43, 32)[0], 1.0);
}

TEST(Preview, BakeWritesItFromTheSidecarOrRefusesWithoutACamera) {
  const std::string dir = test::TempDirectory("preview-cli");
  const std::string scene = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 2.0f, 8, 0.5f);
  const std::string common = scene + " -o " + dir + "/out.ply --photons 20000 -q ";
  const test::ToolRun none = test::RunTool(PB_BAKE_EXE, common + "--preview " + dir + "/p.png");
  EXPECT_EQ(none.status, 1) << none.output;
  EXPECT_NE(none.output.find("--preview needs a camera"), std::string::npos) << none.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.ply")) << "refused before any work";
  test::WriteText(dir + "/cam.json", R"({"position_m": [0, 0.9, 1.5], "look_at_m": [0, 0, 0], "up": [0, 1, 0],
                                         "vertical_fov_deg": 60})");
  const test::ToolRun run = test::RunTool(PB_BAKE_EXE, common + "--preview " + dir + "/p.png --preview-size 80x60 "
                                                                "--camera " + dir + "/cam.json");
  EXPECT_EQ(run.status, 0) << run.output;
  const Png png = ReadPng(dir + "/p.png");
  EXPECT_EQ(png.width, 80);
  EXPECT_EQ(png.height, 60);
  EXPECT_GT(png.At(40, 45)[0], 20) << "the lit floor below the centre";
  EXPECT_EQ(test::RunTool(PB_BAKE_EXE, common + "--preview " + dir + "/out.ply").status, 1) << "-o and --preview";
  EXPECT_EQ(test::RunTool(PB_BAKE_EXE, common + "--camera " + dir + "/cam.json").status, 2) << "--camera alone";
  EXPECT_EQ(test::RunTool(PB_BAKE_EXE, common + "--preview " + dir + "/p.png --preview-size 9000x10").status, 2);
}

}  // namespace
}  // namespace pb
