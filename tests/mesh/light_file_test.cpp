// Lights files (mesh/light_file.h): every kind read with its units (radiometric as given, photometric over the
// luminous efficacy), positions moved into the scene's local coordinates, faults named by file:line, and a sidecar
// found beside an OBJ scene and baked: a sky over an open grey floor gives H = pi L at every vertex.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "mesh/errors.h"
#include "mesh/light_file.h"
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
  const Scene scene;
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
  for (const auto& [text, fragment] : cases) {
    try {
      LoadLightsFile(Write("lights-fault", text), scene);
      ADD_FAILURE() << text << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
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
