// tools/scene-to-gltf: an OBJ scene written as a glTF input scene reads back as the same scene (every triangle's
// corners and material: class, Kd, Ks, Tf, Ni, Ke), with its lights as KHR_lights_punctual and its sky in a
// lights sidecar; and the bundled glTF office with daylight (data/office_books/office_books_daylight.glb) loads
// cleanly with its sun and sky.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <tuple>

#include "baker/0_prepare_scene.h"
#include "baker/files/atomic_file.h"
#include "baker/files/image_io.h"
#include "mesh/gltf_loader.h"
#include "mesh/light_file.h"
#include "mesh/obj_loader.h"
#include "tests/ies_text.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

// Every triangle as its corners, rotated to start at the smallest, with its material's name, sorted.
using Corners = std::array<std::array<float, 3>, 3>;
std::vector<std::pair<Corners, std::string>> Triangles(const Scene& s) {
  std::vector<std::pair<Corners, std::string>> out;
  for (uint32_t t = 0; t < s.triangles.size(); ++t) {
    Corners c;
    for (int k = 0; k < 3; ++k) {
      const Point3 p = s.Corner(t, k);
      c[size_t(k)] = {p.x, p.y, p.z};
    }
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    out.emplace_back(c, s.MaterialOf(t).name);
  }
  std::sort(out.begin(), out.end());
  return out;
}

const Material& Named(const Scene& s, const std::string& name) {
  for (const Material& m : s.materials)
    if (m.name == name) return m;
  ADD_FAILURE() << "no material " << name;
  return s.materials.front();
}

void ExpectSameMaterial(const Material& a, const Material& b) {
  EXPECT_EQ(a.kind, b.kind) << a.name;
  for (const auto& [x, y] : {std::pair{a.albedo, b.albedo}, {a.specular, b.specular}, {a.emission, b.emission},
                             {a.transmittance, b.transmittance}}) {
    EXPECT_NEAR(x.r, y.r, 1e-5 * std::max(1.0f, y.r)) << a.name;
    EXPECT_NEAR(x.b, y.b, 1e-5 * std::max(1.0f, y.b)) << a.name;
  }
  if (a.kind == MaterialClass::kGlass) {
    EXPECT_FLOAT_EQ(a.ior, b.ior) << a.name;
  }
}

TEST(SceneToGltf, AnObjSceneReadsBackAsTheSameScene) {
  const std::string dir = test::TempDirectory("scene-to-gltf");
  for (const std::string name : {"box_glass", "office_books"}) {
    const std::string obj = std::string(PB_SOURCE_DIR "/data/") + name + "/" + name + ".obj";
    const std::string glb = dir + "/" + name + ".glb";
    const test::ToolRun run = test::RunTool(PB_SCENE_TO_GLTF_EXE, obj + " -o " + glb);
    ASSERT_EQ(run.status, 0) << run.output;
    const LoadedScene a = LoadObj(obj), b = LoadGltf(glb);
    EXPECT_TRUE(b.warnings.empty()) << b.warnings.front();
    EXPECT_EQ(Triangles(a.scene), Triangles(b.scene)) << name;
    for (const Material& m : a.scene.materials) ExpectSameMaterial(Named(b.scene, m.name), m);
  }
}

TEST(SceneToGltf, LightsBecomeKhrLightsAndTheSkyAndIesLampsASidecar) {
  const std::string dir = test::TempDirectory("scene-to-gltf-lights");
  const std::string obj = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 2);
  test::WriteText(dir + "/l.json", R"({"lights": [
      {"type": "spot", "name": "s", "position_m": [0.5, 2, 0], "direction": [0.3, -1, 0.2], "intensity_W_sr": 3,
       "inner_cone_deg": 10, "outer_cone_deg": 30},
      {"type": "sun", "name": "sun", "direction": [0, -1, 1], "irradiance_W_m2": 100},
      {"type": "sky", "name": "sky", "radiance_W_m2_sr": 2, "color": [1, 0.5, 0.25], "image": "sky.exr",
       "rotation_deg": 30},
      {"type": "point", "name": "lamp", "ies": "lamp.ies", "position_m": [0.2, 1.5, 0], "direction": [0, -1, 0.2],
       "c0": [0, 0, 1], "scale": 3}]})");
  Image sky(4, 2);
  sky.At(1, 0) = {3, 2, 1};
  OutputFiles images;
  WriteExr(images, dir + "/sky.exr", sky);
  images.Commit();
  test::WriteText(dir + "/lamp.ies", test::IesText({{0, 45, 90}, {0, 90}, [](double g, double c) { return 100 + g + c; }}));
  const test::ToolRun run = test::RunTool(PB_SCENE_TO_GLTF_EXE, obj + " -o " + dir + "/out.gltf --lights " + dir + "/l.json");
  ASSERT_EQ(run.status, 0) << run.output;
  const Scene original = [&] {
    Scene s = LoadObj(obj).scene;
    s.analyticLights = LoadLightsFile(dir + "/l.json", s).lights;
    return s;
  }();
  Scene back = LoadGltf(dir + "/out.gltf").scene;
  ASSERT_TRUE(std::filesystem::exists(dir + "/out.lights.json"));
  for (const AnalyticLight& l : LoadLightsFile(dir + "/out.lights.json", back).lights) back.analyticLights.push_back(l);
  ASSERT_EQ(back.analyticLights.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    const AnalyticLight &a = original.analyticLights[i], &b = back.analyticLights[i];
    EXPECT_EQ(a.kind, b.kind) << i;
    EXPECT_EQ(a.name, b.name) << i;
    EXPECT_NEAR(b.intensity.g / a.intensity.g, 1, 1e-5) << i;
    EXPECT_NEAR(Dot(a.direction, b.direction), 1, 1e-5) << i;
    if (a.kind == LightKind::kSpot) {
      EXPECT_NEAR(b.position.y, 2, 1e-5);
      EXPECT_NEAR(b.cosOuter, a.cosOuter, 1e-5);
    }
    EXPECT_EQ(!a.profile, !b.profile) << i;
    EXPECT_EQ(!a.image, !b.image) << i;
    if (a.image) {
      EXPECT_EQ(b.image->texels, a.image->texels) << "the sky image goes to the sidecar, named, with its front";
      EXPECT_NEAR(Dot(a.c0, b.c0), 1, 1e-6);
    }
    if (a.profile) {
      EXPECT_NEAR(b.position.x, 0.2, 1e-6) << "the IES lamp goes to the sidecar, naming its file";
      EXPECT_NEAR(Dot(a.c0, b.c0), 1, 1e-6);
      EXPECT_EQ(b.profile->Flux(), a.profile->Flux());
    }
  }
}

TEST(SceneToGltf, TheBundledDaylightOfficeLoadsWithItsSunAndSky) {
  const std::string glb = PB_SOURCE_DIR "/data/office_books/office_books_daylight.glb";
  StageClock clock;
  const PreparedScene p = PrepareScene(SceneSettings{glb}, clock);
  EXPECT_TRUE(p.warnings.empty()) << p.warnings.front();
  std::vector<std::string> kinds;
  for (const Light& l : p.lights) kinds.push_back(LightKindName(l.kind));
  EXPECT_EQ(kinds, (std::vector<std::string>{"area", "area", "sun", "sky"})) << "the two lamps, the sun, the sky";
  EXPECT_TRUE(std::filesystem::exists(PB_SOURCE_DIR "/data/office_books/office_books_daylight.camera.json"));
}

}  // namespace
}  // namespace pb
