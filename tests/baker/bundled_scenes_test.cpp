// The scenes in data/: each loads without a warning, has a README and a camera sidecar, and simulates the
// transport its materials call for (event counters from a short bake).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "baker/bake.h"
#include "mesh/obj_loader.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> BundledScenes() {
  std::vector<fs::path> scenes;
  for (const auto& folder : fs::directory_iterator(PB_SOURCE_DIR "/data"))
    for (const auto& file : fs::directory_iterator(folder.path()))
      if (file.path().extension() == ".obj") scenes.push_back(file.path());
  std::sort(scenes.begin(), scenes.end());
  return scenes;
}

TEST(BundledScenes, LoadCleanlyWithAReadmeAndACamera) {
  const std::vector<fs::path> scenes = BundledScenes();
  ASSERT_GE(scenes.size(), 7u);  // box, box_glass, office_empty, office_books, door_ajar, uplit_room, window_sun
  for (const fs::path& obj : scenes) {
    SCOPED_TRACE(obj.string());
    EXPECT_TRUE(LoadObj(obj.string()).warnings.empty());
    EXPECT_TRUE(fs::exists(obj.parent_path() / "README.md"));
    fs::path camera = obj;
    camera.replace_extension(".camera.json");
    std::ifstream in(camera);
    ASSERT_TRUE(in) << camera;
    const nlohmann::json j = nlohmann::json::parse(in);
    const auto position = j.at("position_m").get<std::array<float, 3>>();
    const auto target = j.at("look_at_m").get<std::array<float, 3>>();
    EXPECT_NE(position, target);
    const auto up = j.at("up").get<std::array<float, 3>>();
    EXPECT_GT(up[0] * up[0] + up[1] * up[1] + up[2] * up[2], 0.0f);
    const float fov = j.at("vertical_fov_deg").get<float>();
    EXPECT_TRUE(fov > 0 && fov < 180) << fov;
  }
  EXPECT_EQ(std::count_if(scenes.begin(), scenes.end(),
                          [](const fs::path& p) { return p.string().find("office") != std::string::npos; }),
            2);
}

TraceStats ShortBake(const std::string& name) {
  BakeOptions o;
  o.scenePath = std::string(PB_SOURCE_DIR "/data/") + name + "/" + name + ".obj";
  o.outputPath = test::TempDirectory("bundled-" + name) + "/out.ply";
  o.photons = 100'000;
  return Bake(o, Log(true)).trace;
}

TEST(BundledScenes, EachSimulatesTheEffectsItsMaterialsCallFor) {
  const TraceStats box = ShortBake("box");
  EXPECT_EQ(box.SpecularEvents(), 0u);
  const TraceStats office = ShortBake("office_empty");
  EXPECT_EQ(office.SpecularEvents(), 0u);
  const TraceStats books = ShortBake("office_books");
  EXPECT_GT(books.mirrorReflections, 0u);
  EXPECT_EQ(books.refractions + books.fresnelReflections, 0u);
  EXPECT_GT(books.causticHits, 0u);
  const TraceStats glass = ShortBake("box_glass");
  EXPECT_GT(glass.refractions, 0u);
  EXPECT_GT(glass.fresnelReflections, 0u);
  EXPECT_GT(glass.causticHits, 0u);
  EXPECT_EQ(glass.mirrorReflections, 0u);
  // The three lit from a few directions (issue 63): diffuse, the rooms closed but for the window.
  const TraceStats door = ShortBake("door_ajar"), uplit = ShortBake("uplit_room"), window = ShortBake("window_sun");
  for (const TraceStats* t : {&door, &uplit, &window}) EXPECT_EQ(t->SpecularEvents(), 0u);
  EXPECT_EQ(door.escaped, 0u);
  EXPECT_EQ(uplit.escaped, 0u);
  EXPECT_GT(window.escaped, 0u) << "light that the room throws back out of its window";
  for (const TraceStats* t : {&box, &office, &books, &glass, &door, &uplit, &window}) {
    EXPECT_EQ(t->truncated, 0u);
    EXPECT_EQ(t->absorbed + t->escaped + t->forbidden, t->emitted);
  }
}

}  // namespace
}  // namespace pb
