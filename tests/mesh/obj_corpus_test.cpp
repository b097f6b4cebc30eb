// The OBJ corpus (issue 19): real assets and other readers' regression files that nobody on this project wrote,
// in ../shared/obj-corpus beside the repository (or $PB_OBJ_CORPUS). Its README says of each file whether a
// loader users can rely on loads it or refuses it; every file is loaded here and held to that, and a few are
// baked. Skipped, saying why, where the corpus is absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include "mesh/errors.h"
#include "mesh/obj_loader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

std::string CorpusDirectory() {
  if (const char* dir = std::getenv("PB_OBJ_CORPUS")) return dir;
  return PB_SOURCE_DIR "/../shared/obj-corpus";
}

struct CorpusEntry {
  std::string file;    // relative to the corpus
  bool load = false;   // else: refuse
  std::string remark;  // the rest of the README's column, e.g. "warning at `sportsCar.mtl:336` (...)"
};

// The README's table rows: "| `FILE` | load|refuse[, remark] | tinyobj / assimp / Blender |".
std::vector<CorpusEntry> ReadCorpusTable(const std::string& dir) {
  std::ifstream in(dir + "/README.md");
  const std::regex row(R"(^\| `([^`]+)` \| (load|refuse)([^|]*)\|)");
  std::vector<CorpusEntry> entries;
  std::smatch m;
  for (std::string line; std::getline(in, line);)
    if (std::regex_search(line, m, row)) entries.push_back({m[1], m[2] == "load", m[3]});
  return entries;
}

// What each refused file's message must say: its real fault, and the line where that is.
struct Refusal {
  int line;  // 0: the whole file (it has no face at all)
  std::string fragment;
};
const std::map<std::string, Refusal>& ExpectedRefusals() {
  static const std::map<std::string, Refusal> refusals = {
      {"src/assimp/test/models/OBJ/number_formats.obj", {11, "malformed number '3.1+e2'"}},
      {"src/assimp/test/models/OBJ/point_cloud.obj", {0, "scene has no faces"}},
      {"src/assimp/test/models/OBJ/testline.obj", {15, "only lines and points"}},
      {"src/assimp/test/models/OBJ/testpoints.obj", {15, "only lines and points"}},
      {"src/assimp/test/models/invalid/empty.obj", {0, "scene has no faces"}},
      {"src/assimp/test/models/invalid/malformed.obj", {23, "vertex index 12 is out of range"}},
      {"src/tinyobj/models/invalid-face-definition.obj", {15, "faces have fewer than 3 corners"}},
      {"src/tinyobj/models/invalid-relative-texture-index.obj", {2, "is out of range"}},
      {"src/tinyobj/models/invalid-relative-vertex-index.obj", {1, "vertex index -4 is out of range"}},
      {"src/tinyobj/models/issue-140-zero-face-idx.obj", {16, "malformed face index '0/0/0'"}},
      {"src/tinyobj/models/issue-356-leading-spaces-newmtl.obj", {0, "scene has no faces"}},
      {"src/tinyobj/models/line-prim.obj", {15, "only lines and points"}},
      {"src/tinyobj/models/points-prim.obj", {15, "only lines and points"}},
      {"src/tinyobj/models/test-nan.obj", {12, "non-finite number 'nan'"}},
  };
  return refusals;
}

class ObjCorpus : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = CorpusDirectory();
    if (!std::filesystem::exists(dir_ + "/README.md"))
      GTEST_SKIP() << "the OBJ corpus is not at " << dir_ << " (set PB_OBJ_CORPUS to where it is)";
  }
  std::string dir_;
};

TEST_F(ObjCorpus, LoadsWhatItShouldAndRefusesTheRestNamingTheFault) {
  const std::vector<CorpusEntry> entries = ReadCorpusTable(dir_);
  ASSERT_GE(entries.size(), 100u) << "the README's table was not read";
  size_t loaded = 0, refused = 0;
  for (const CorpusEntry& entry : entries) {
    const std::string path = dir_ + "/" + entry.file;
    if (entry.load) {
      try {
        const LoadedScene scene = LoadObj(path);
        EXPECT_GT(scene.scene.triangles.size(), 0u) << entry.file;
        ++loaded;
        // "load, warning at `FILE:LINE`": that warning is given.
        std::smatch at;
        if (std::regex_search(entry.remark, at, std::regex("warning at `([^`]+)`"))) {
          bool found = false;
          for (const std::string& w : scene.warnings) found |= w.find(at[1].str() + ": warning") != std::string::npos;
          EXPECT_TRUE(found) << entry.file << ": no warning at " << at[1];
        }
      } catch (const InputError& e) {
        ADD_FAILURE() << entry.file << " should load: " << e.what();
      }
      continue;
    }
    const auto expected = ExpectedRefusals().find(entry.file);
    ASSERT_NE(expected, ExpectedRefusals().end()) << entry.file << " is to be refused, but no fault is listed here";
    try {
      LoadObj(path);
      ADD_FAILURE() << entry.file << " should be refused";
    } catch (const InputError& e) {
      ++refused;
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(e.line(), expected->second.line) << e.what();
      EXPECT_NE(e.message().find(expected->second.fragment), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(refused, ExpectedRefusals().size());
  std::printf("corpus: %zu files loaded, %zu refused with their fault\n", loaded, refused);
}

// Loaded is not yet baked: a few of the corpus's scenes through the whole bake, as a user runs it.
TEST_F(ObjCorpus, ItsScenesBake) {
  const std::string out = test::TempDirectory("corpus-bakes");
  // The McGuire box (a light of its own), and copies with a BOM, CRLF line ends and '\' continuations.
  for (const char* scene : {"zips/Cornell_Box/CornellBox-Original.obj", "derived/cornell_continuation.obj",
                            "derived/cornell_crlf.obj", "zips/Cornell_Box/CornellBox-Sphere.obj"}) {
    const test::ToolRun run = test::RunTool(PB_BAKE_EXE, "'" + dir_ + "/" + scene + "' -o " + out +
                                                             "/b.ply --photons 20000 --threads 2 -q");
    EXPECT_EQ(run.status, 0) << scene << ":\n" << run.output;
    EXPECT_TRUE(std::filesystem::exists(out + "/b.ply")) << scene;
    std::filesystem::remove(out + "/b.ply");
  }
  // A Blender 3.4 export whose lamp faces away from the scene: refused, saying how to fix it.
  const test::ToolRun lamp = test::RunTool(PB_BAKE_EXE, dir_ + "/derived/bl_tga.obj -o " + out + "/l.ply -q");
  EXPECT_EQ(lamp.status, 1) << lamp.output;
  EXPECT_NE(lamp.output.find("Flip the light's normals"), std::string::npos) << lamp.output;
  EXPECT_FALSE(std::filesystem::exists(out + "/l.ply"));
}

}  // namespace
}  // namespace pb
