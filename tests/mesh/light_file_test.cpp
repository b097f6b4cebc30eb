// Lights files (mesh/light_file.h): every kind read with its units (radiometric as given, photometric over the
// luminous efficacy; an IES lamp's from its file, mesh/ies_file.h), positions moved into the scene's local coordinates, faults named by file:line, and a sidecar
// found beside an OBJ scene and baked: a sky over an open grey floor gives H = pi L at every vertex.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include <fmt/format.h>
#include <stb_image_write.h>

#include "baker/files/atomic_file.h"
#include "baker/files/image_io.h"
#include "mesh/errors.h"
#include "mesh/light_file.h"
#include "mesh/lights.h"
#include "tests/ies_text.h"
#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = test::TempDirectory(name) + "/s.lights.json";
  test::WriteText(path, text);
  return path;
}

// The lights file at `path` is refused with a message holding `fragment`.
void ExpectRefused(const std::string& path, const std::string& fragment) {
  try {
    LoadLightsFile(path, Scene{});
    ADD_FAILURE() << test::ReadBytes(path) << " was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(LightFile, ReadsEveryKindWithItsUnits) {
  Scene scene;
  scene.origin = {100, 0, 0};  // a recentred scene: positions become local
  const std::vector<AnalyticLight> lights = LoadLightsFile(Write("lights-kinds", R"({
    "luminous_efficacy_lm_per_W": 500,
    "lights": [
      {"type": "point", "name": "bulb", "position_m": [101, 2, 0], "intensity_W_sr": 5, "color": [1, 0.5, 0]},
      {"type": "spot", "position_m": [100, 2, 0], "direction": [0, -2, 0], "intensity_cd": 1000,
       "inner_cone_deg": 20, "outer_cone_deg": 40},
      {"type": "sun", "direction": [0, -3, 4], "illuminance_lux": 50000},
      {"type": "sky", "radiance_W_m2_sr": 2, "whole_sphere": true}
    ]})"), scene).lights;
  ASSERT_EQ(lights.size(), 4u);
  EXPECT_EQ(lights[0].kind, LightKind::kPoint);
  EXPECT_EQ(lights[0].name, "bulb");
  EXPECT_FLOAT_EQ(lights[0].position.x, 1.0f);
  EXPECT_FLOAT_EQ(lights[0].intensity.g, 2.5f);
  EXPECT_EQ(lights[1].kind, LightKind::kSpot);
  EXPECT_FLOAT_EQ(lights[1].intensity.r, 2.0f) << "1000 cd over 500 lm/W";
  EXPECT_FLOAT_EQ(lights[1].direction.y, -1.0f);
  EXPECT_NEAR(lights[1].cosOuter, std::cos(40 * kPi / 180), 1e-6);
  EXPECT_EQ(lights[2].kind, LightKind::kSun);
  EXPECT_FLOAT_EQ(lights[2].intensity.b, 100.0f);
  EXPECT_NEAR(lights[2].direction.z, 0.8f, 1e-6);
  EXPECT_TRUE(lights[3].wholeSphere);
  EXPECT_EQ(lights[3].source.substr(lights[3].source.size() - 2), ":8") << "the line of its type: " << lights[3].source;
}

TEST(LightFile, ReadsPortalsAsParallelogramsFacingInside) {
  Scene scene;
  scene.origin = {0, 0, 10};
  const LightsFile file = LoadLightsFile(Write("lights-portals", R"({"lights": [],
    "portals": [{"corners_m": [[1.5, 1, 14], [1.5, 2.2, 14], [3.5, 2.2, 14], [3.5, 1, 14]]}]})"), scene);
  ASSERT_EQ(file.portals.size(), 1u);
  const Portal& p = file.portals[0];
  EXPECT_FLOAT_EQ(p.origin.z, 4.0f) << "local coordinates";
  EXPECT_NEAR(p.Area(), 2.4, 1e-6);
  EXPECT_NEAR(p.Inward().z, -1, 1e-6) << "counter-clockwise seen from inside, at z < 4";
}

TEST(LightFile, FaultsNameTheLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"{\"lights\": [\n{\"type\": \"lamp\"}]}", "s.lights.json:2: error: light 0: 'type' must be"},
      {"{\"lights\": [\n{\"type\": \"point\", \"intensity_W_sr\": 1},\n{\"type\": \"point\",\n \"position_m\": [0, 1]}]}",
       "s.lights.json:2: error: light 0 has no 'position_m'"},
      {"{\"lights\": [{\"type\": \"sun\", \"direction\": [0, -1, 0]}]}", "give exactly one of 'irradiance_W_m2' and 'illuminance_lux'"},
      {"{\"lights\": [{\"type\": \"sun\", \"direction\": [0, 0, 0], \"irradiance_W_m2\": 1}]}", "'direction' must not be zero"},
      {"{\"lights\": [{\"type\": \"spot\", \"position_m\": [0, 1, 0], \"intensity_W_sr\": 1,\n \"inner_cone_deg\": 30, \"outer_cone_deg\": 30}]}",
       ":2: error: light 0: 'inner_cone_deg' must be less than"},
      {"{\"lights\": [{\"type\": \"sky\", \"radiance_W_m2_sr\": -1}]}", "'radiance_W_m2_sr' must lie in [0, 1e+30]"},
      {"{\"lights\": [{\"type\": \"sky\", \"radiance_W_m2_sr\": 1, \"whole_sphere\": 1}]}", "'whole_sphere' must be true or false"},
      {"{\"lights\": {}}", "a lights file is an object with an array 'lights'"},
      {"{\"lights\": [], \"portals\": [\n{\"corners_m\": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 2, 0]]}]}",
       ":2: error: portal 0: its corners must form a parallelogram"},
      {"{\"lights\": [], \"portals\": [{\"corners_m\": [[0, 0, 0], [1, 0, 0]]}]}", "portal 0: 'corners_m' must hold its 4 corners"},
      {"{\"lights\": [\n", "s.lights.json:2: error: malformed JSON"},
  };
  for (const auto& [text, fragment] : cases) ExpectRefused(Write("lights-fault", text), fragment);
}

// An IES lamp, brighter downward and toward C = 0, as its table gives it [cd].
double Lamp(double gamma, double c) {
  return (50 + 400 * std::cos(gamma * kPi / 180) * (gamma <= 90)) * (1 + 0.6 * std::cos(c * kPi / 180));
}
std::string WriteLamp(const std::string& dir) {
  test::WriteText(dir + "/lamp.ies", test::IesText({test::Degrees(0, 180, 15), test::Degrees(0, 330, 30), Lamp}));
  return dir + "/lamp.ies";
}

TEST(LightFile, ReadsAnIesPointLight) {
  const Scene scene;
  const std::string path = Write("lights-ies", R"({"luminous_efficacy_lm_per_W": 500, "lights": [
      {"type": "point", "ies": "lamp.ies", "position_m": [0, 2, 0], "scale": 2, "color": [1, 0.5, 0.25],
       "direction": [0, 0, -3], "c0": [1, 0, 1]}]})");
  WriteLamp(path.substr(0, path.rfind('/')));
  const std::vector<AnalyticLight> lights = LoadLightsFile(path, scene).lights;
  ASSERT_EQ(lights.size(), 1u);
  const AnalyticLight& a = lights[0];
  ASSERT_TRUE(a.profile);
  EXPECT_FLOAT_EQ(a.intensity.r, 2.0f / 500) << "the candela values times scale over the efficacy: W/sr per cd";
  EXPECT_FLOAT_EQ(a.intensity.b, 0.25f * 2 / 500);
  EXPECT_NEAR(a.direction.z, -1, 1e-6);
  EXPECT_NEAR(a.c0.x, 1, 1e-6) << "c0 made perpendicular to the nadir";
  EXPECT_NEAR(a.c0.y, 0, 1e-6);
  // Toward C = 90 degrees, counter-clockwise seen from above (from +z, looking along the nadir -z): +y.
  EXPECT_NEAR(RelativeIntensity(a, Normalize(Vector3{0, 1, -1})), Lamp(45, 90), 1e-3);
  EXPECT_NEAR(RelativeIntensity(a, Normalize(Vector3{-1, 0, -1})), Lamp(45, 180), 1e-3);
}

TEST(LightFile, IesFaultsNameTheirFile) {
  const std::string dir = test::TempDirectory("lights-ies-fault");
  WriteLamp(dir);
  test::WriteText(dir + "/bad.ies", "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 2 1 1 2 0 0 0\n1 1 0\n0 90\n0\n10 -1\n");
  const std::string point = R"({"type": "point", "position_m": [0, 1, 0], )";
  const std::pair<std::string, std::string> cases[] = {
      {R"({"type": "spot", "position_m": [0, 1, 0],
          "ies": "lamp.ies"})", "l.json:2: error: light 0: an IES profile is a point light's"},
      {point + R"("ies": "none.ies"})", "l.json:1: error: light 0: the IES file 'none.ies' is not there"},
      {point + R"("ies": "lamp.ies", "intensity_cd": 5})", "'intensity_cd' and 'ies' both give the intensity"},
      {point + R"("ies": "lamp.ies", "c0": [0, -2, 0]})", "'c0' must not be parallel to 'direction'"},
      {point + R"("ies": "bad.ies"})", "bad.ies:7: error: candela values must lie in [0, 1e+30], not -1"},
      {point + R"("ies": 3})", "'ies' must name an IES file"},
  };
  for (const auto& [light, fragment] : cases) {
    test::WriteText(dir + "/l.json", "{\"lights\": [" + light + "]}");
    ExpectRefused(dir + "/l.json", fragment);
  }
}

// A black floor fanned about the point under an IES lamp 1 m up, its rim at 45 degrees from the nadir on the
// table's horizontal angles: each rim vertex reads I(45, C) cos(45) / 2 over the efficacy, and the IES file is an
// input no output may overwrite.
TEST(LightFile, AnIesLampBakesItsTableOnTheFloor) {
  const std::string dir = test::TempDirectory("lights-ies-bake");
  WriteLamp(dir);
  std::string obj = "mtllib f.mtl\nusemtl black\nv 0 0 0\n";
  for (int k = 0; k < 12; ++k) obj += fmt::format("v {:.9f} 0 {:.9f}\n", std::cos(k * kPi / 6), -std::sin(k * kPi / 6));
  for (int k = 0; k < 12; ++k) obj += fmt::format("f 1 {} {}\n", k + 2, (k + 1) % 12 + 2);
  test::WriteText(dir + "/f.mtl", "newmtl black\nKd 0 0 0\n");
  test::WriteText(dir + "/f.obj", obj);
  test::WriteText(dir + "/f.lights.json", R"({"lights": [{"type": "point", "ies": "lamp.ies", "position_m": [0, 1, 0]}]})");
  const test::ToolRun run = test::RunTool(PB_BAKE_EXE, dir + "/f.obj -o " + dir + "/f.ply --photons 10000 -q");
  ASSERT_EQ(run.status, 0) << run.output;
  const test::PlyData ply = test::ReadPly(dir + "/f.ply");
  ASSERT_EQ(ply.VertexCount(), 13u);
  int rim = 0;
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    const double x = ply.vertex.at("x")[v], z = ply.vertex.at("z")[v];
    if (std::hypot(x, z) < 0.5) continue;
    const double c = std::atan2(-z, x) * 180 / kPi;
    const double expected = Lamp(45, std::round(c < -1e-3 ? c + 360 : c)) / kDefaultLuminousEfficacy * std::sqrt(0.5) / 2;
    // 1e-3: a rim vertex's rays start a step (0.1 mm here) inside the floor (baker/3_surface_point.h), where H is
    // 1.5e-4 higher.
    EXPECT_NEAR(ply.vertex.at("irradiance_g")[v], expected, 1e-3 * expected) << c;
    ++rim;
  }
  EXPECT_EQ(rim, 12);
  const test::ToolRun clash = test::RunTool(PB_BAKE_EXE, dir + "/f.obj -o " + dir + "/lamp.ies --photons 1000 -q");
  EXPECT_NE(clash.status, 0);
  EXPECT_NE(clash.output.find("the IES file"), std::string::npos) << clash.output;
}

// Sky images written as OpenEXR (float) and Radiance HDR (RGBE: 8-bit mantissas).
void WriteSkyImages(const std::string& dir, int width, int height, const std::function<Rgb(int, int)>& texel) {
  Image image(width, height);
  std::vector<float> rgb;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Rgb t = image.At(x, y) = texel(x, y);
      rgb.insert(rgb.end(), {t.r, t.g, t.b});
    }
  OutputFiles outputs;
  WriteExr(outputs, dir + "/sky.exr", image);
  outputs.Commit();
  ASSERT_NE(stbi_write_hdr((dir + "/sky.hdr").c_str(), width, height, 3, rgb.data()), 0);
}

TEST(LightFile, ReadsASkyImageFromExrOrHdr) {
  const std::string dir = test::TempDirectory("lights-sky-image");
  const auto texel = [](int x, int y) { return Rgb{float(x + 1), float(y + 1) * 0.5f, 100.0f}; };
  WriteSkyImages(dir, 8, 4, texel);
  const Scene scene;
  for (const char* file : {"sky.exr", "sky.hdr"}) {
    test::WriteText(dir + "/l.json", fmt::format(R"({{"lights": [{{"type": "sky", "image": "{}", "radiance_W_m2_sr": 2,
        "rotation_deg": 90}}]}})", file));
    const AnalyticLight a = LoadLightsFile(dir + "/l.json", scene).lights.at(0);
    ASSERT_TRUE(a.image) << file;
    EXPECT_EQ(a.image->width, 8);
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 8; ++x) {
        EXPECT_NEAR(a.image->Texel(x, y).r, texel(x, y).r, 0.01 * texel(x, y).r) << file;
        EXPECT_NEAR(a.image->Texel(x, y).b, 100, 1) << file;
      }
    EXPECT_FLOAT_EQ(a.intensity.g, 2);
    EXPECT_NEAR(a.c0.x, -1, 1e-6) << "-z turned 90 degrees counter-clockwise seen from above: -x";
  }
}

TEST(LightFile, SkyImageFaultsNameTheirFile) {
  const std::string dir = test::TempDirectory("lights-sky-image-fault");
  WriteSkyImages(dir, 8, 8, [](int, int) { return Rgb{1, 1, 1}; });
  std::filesystem::rename(dir + "/sky.exr", dir + "/square.exr");
  WriteSkyImages(dir, 4, 2, [](int x, int) { return Rgb{x == 1 ? -1.0f : 1.0f, 1, 1}; });
  std::filesystem::rename(dir + "/sky.exr", dir + "/negative.exr");
  test::WriteText(dir + "/text.exr", "not an image");
  // A run-length scanline whose first run is empty, on which stb_image's decoder looped forever (fuzz_sky_image).
  test::WriteText(dir + "/empty-run.hdr", std::string("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n\x02\x02\x00\x08\x00", 50));
  test::WriteText(dir + "/short.hdr", "#?RADIANCE\n\n-Y 4 +X 8\n\x01\x02");
  test::WriteText(dir + "/sideways.hdr", "#?RADIANCE\n\n+X 8 -Y 4\n");
  // An EXR whose attribute declares a value longer than the file: OpenEXR would have allocated it (fuzz_sky_image).
  std::filesystem::copy_file(PB_SOURCE_DIR "/tests/fuzz/corpus/sky_image/huge-attribute-oom.exr", dir + "/huge.exr");
  // An EXR whose v2f attribute declares 21 bytes: OpenEXR reads 8 and takes the next 13 for a string attribute of
  // 1.9 GB, which it allocated (fuzz_sky_image, out of memory in CI).
  std::filesystem::copy_file(PB_SOURCE_DIR "/tests/fuzz/corpus/sky_image/desynced-attribute-oom.exr", dir + "/desynced.exr");
  // The same through a float declaring 0 bytes, which OpenEXR reads as 4 (the walk had taken 0 for "misread").
  std::filesystem::copy_file(PB_SOURCE_DIR "/tests/fuzz/corpus/sky_image/zero-size-float-oom.exr", dir + "/zero.exr");
  const std::pair<std::string, std::string> cases[] = {
      {R"({"lights": [{"type": "sky", "image": "square.exr"}]})", "square.exr: error: a sky image of 8 x 8 pixels is not latitude-longitude"},
      {R"({"lights": [{"type": "sky", "image": "negative.exr"}]})", "negative.exr: error: the sky image's pixel (1, 0) holds (-1, 1, 1)"},
      {R"({"lights": [{"type": "sky", "image": "text.exr"}]})", "text.exr: error: a sky image must be OpenEXR (.exr) or Radiance HDR (.hdr)"},
      {R"({"lights": [{"type": "sky", "image": "none.exr"}]})", "l.json:1: error: light 0: the sky image 'none.exr' is not there"},
      {R"({"lights": [{"type": "sky", "image": "empty-run.hdr"}]})", "empty-run.hdr: error: a run-length scanline's run is empty"},
      {R"({"lights": [{"type": "sky", "image": "short.hdr"}]})", "short.hdr: error: the pixels end early"},
      {R"({"lights": [{"type": "sky", "image": "sideways.hdr"}]})", "sideways.hdr: error: only the resolution layout '-Y H +X W'"},
      {R"({"lights": [{"type": "sky", "image": "huge.exr"}]})", "huge.exr: error: cannot read the sky image as EXR: an attribute's value runs past the end"},
      {R"({"lights": [{"type": "sky", "image": "desynced.exr"}]})", "desynced.exr: error: cannot read the sky image as EXR: the attribute 'a' of type v2f declares 21 bytes"},
      {R"({"lights": [{"type": "sky", "image": "zero.exr"}]})", "zero.exr: error: cannot read the sky image as EXR: the attribute 'screenWinfowWidth' of type float declares 0 bytes"},
      {R"({"lights": [{"type": "sky", "image": "sky.hdr", "front": [0, 2, 0]}]})", "'front' must not be parallel to 'up'"},
  };
  for (const auto& [text, fragment] : cases) {
    test::WriteText(dir + "/l.json", text);
    ExpectRefused(dir + "/l.json", fragment);
  }
}

// A constant image is the constant sky: the bake of a grey floor under one (0.25 everywhere, strength 2) is the
// bake under "radiance_W_m2_sr": 0.5, vertex for vertex and bit for bit.
TEST(LightFile, AConstantSkyImageIsTheConstantSky) {
  const std::string dir = test::TempDirectory("lights-sky-constant");
  WriteSkyImages(dir, 16, 8, [](int, int) { return Rgb{0.25f, 0.25f, 0.25f}; });
  test::WriteText(dir + "/f.mtl", "newmtl grey\nKd 0.5 0.5 0.5\n");
  test::WriteText(dir + "/f.obj", "mtllib f.mtl\nusemtl grey\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nf 1 4 3 2\n"
                                  "v -2 0 -2\nv -2 1 -2\nv -2 1 2\nv -2 0 2\nf 5 6 7 8\n");
  const auto bake = [&](const std::string& sky, const std::string& out) {
    test::WriteText(dir + "/l.json", R"({"lights": [)" + sky + "]}");
    const test::ToolRun run = test::RunTool(PB_BAKE_EXE, dir + "/f.obj --lights " + dir + "/l.json -o " + dir + "/" + out + " --photons 20000 -q");
    EXPECT_EQ(run.status, 0) << run.output;
    return test::ReadPly(dir + "/" + out).vertex.at("irradiance_g");
  };
  const std::vector<double> image = bake(R"({"type": "sky", "image": "sky.exr", "radiance_W_m2_sr": 2})", "image.ply");
  const std::vector<double> constant = bake(R"({"type": "sky", "radiance_W_m2_sr": 0.5})", "constant.ply");
  EXPECT_EQ(image, constant);
  EXPECT_GT(image.front(), 0);
}

TEST(LightFile, ASidecarSkyBakesPiLOverAnOpenFloor) {
  const std::string dir = test::TempDirectory("lights-sidecar");
  test::WriteText(dir + "/f.mtl", "newmtl grey\nKd 0.5 0.5 0.5\n");
  test::WriteText(dir + "/f.obj", "mtllib f.mtl\nusemtl grey\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nf 1 4 3 2\n");
  test::WriteText(dir + "/f.lights.json", R"({"lights": [{"type": "sky", "radiance_W_m2_sr": 0.5}]})");
  const test::ToolRun run = test::RunTool(PB_BAKE_EXE, dir + "/f.obj -o " + dir + "/f.ply --photons 10000 -q");
  ASSERT_EQ(run.status, 0) << run.output;
  const test::PlyData ply = test::ReadPly(dir + "/f.ply");
  ASSERT_EQ(ply.VertexCount(), 4u);
  for (double h : ply.vertex.at("irradiance_g")) EXPECT_NEAR(h, kPi * 0.5, 1e-5) << "nothing blocks the sky";
  // The sidecar is an input: no output may overwrite it.
  const test::ToolRun clash = test::RunTool(PB_BAKE_EXE, dir + "/f.obj -o " + dir + "/f.lights.json --photons 1000 -q");
  EXPECT_NE(clash.status, 0);
  EXPECT_NE(clash.output.find("the lights file"), std::string::npos) << clash.output;
}

// Lights that light nothing are said (issue 39: each gave a black PLY with exit 0, or "raise --photons to at least
// -nan"): a scene whose every light emits nothing is refused; a dark light beside a bright one is not blamed for
// missing light; a sun from below an open floor, which reaches no front side, is warned about.
TEST(LightFile, LightsThatLightNothingAreSaid) {
  const std::string dir = test::TempDirectory("lights-dark");
  test::WriteText(dir + "/f.mtl", "newmtl grey\nKd 0.5 0.5 0.5\n");
  test::WriteText(dir + "/f.obj", "mtllib f.mtl\nusemtl grey\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nf 1 4 3 2\n");
  const auto bake = [&](const std::string& lights) {
    test::WriteText(dir + "/l.json", lights);
    return test::RunTool(PB_BAKE_EXE, dir + "/f.obj --lights " + dir + "/l.json -o " + dir + "/f.ply --photons 10000");
  };
  const std::string dark = R"({"type": "point", "position_m": [0, 1, 0], "intensity_W_sr": 1, "color": [0, 0, 0]})";
  const test::ToolRun none = bake(R"({"lights": [)" + dark + "]}");
  EXPECT_EQ(none.status, 1);
  EXPECT_NE(none.output.find("f.obj: error: the scene's lights emit nothing: each of its 1 emits less than 1e-30 W"),
            std::string::npos) << none.output;
  const test::ToolRun beside = bake(R"({"lights": [)" + dark + R"(, {"type": "point", "position_m": [0, 1, 0],
                                    "intensity_W_sr": 1}]})");
  ASSERT_EQ(beside.status, 0) << beside.output;
  EXPECT_EQ(beside.output.find("got no photon"), std::string::npos) << beside.output;
  EXPECT_EQ(beside.output.find("every vertex reads 0"), std::string::npos) << beside.output;
  const test::ToolRun below = bake(R"({"lights": [{"type": "sun", "direction": [0, 1, 0], "irradiance_W_m2": 100}]})");
  ASSERT_EQ(below.status, 0) << below.output;
  EXPECT_NE(below.output.find("f.obj: warning: every vertex reads 0 W/m^2: no light reached the front side"),
            std::string::npos) << below.output;
}

}  // namespace
}  // namespace pb
