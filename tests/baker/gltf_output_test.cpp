// The glTF output (baker/5_write_gltf.h): a bake written as .glb and .gltf carries the same light per vertex as the
// PLY of the same bake, COLOR_0 is the linear tone curve of the radiance, the input's objects and materials keep
// their names, the materials are unlit, and the Khronos glTF Validator finds no error and no warning; with --sh, the
// _SH_R, _SH_G and _SH_B attributes carry the PLY's sh_* properties.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "baker/tone_map.h"
#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

namespace tg = tinygltf;

tg::Model Read(const std::string& path) {
  tg::TinyGLTF loader;
  tg::Model model;
  std::string err, warn;
  const bool binary = path.substr(path.size() - 4) == ".glb";
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                         : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  EXPECT_TRUE(ok) << path << ": " << err;
  return model;
}

// Element i of a float VEC3 accessor.
std::array<float, 3> Vec3(const tg::Model& m, int accessor, size_t i) {
  const tg::Accessor& a = m.accessors[size_t(accessor)];
  const tg::BufferView& v = m.bufferViews[size_t(a.bufferView)];
  std::array<float, 3> out{};
  std::memcpy(out.data(), m.buffers[size_t(v.buffer)].data.data() + v.byteOffset + a.byteOffset + i * 12, 12);
  return out;
}

// Element i of a float VEC4 accessor.
std::array<float, 4> Vec4(const tg::Model& m, int accessor, size_t i) {
  const tg::Accessor& a = m.accessors[size_t(accessor)];
  EXPECT_EQ(a.type, TINYGLTF_TYPE_VEC4);
  const tg::BufferView& v = m.bufferViews[size_t(a.bufferView)];
  std::array<float, 4> out{};
  std::memcpy(out.data(), m.buffers[size_t(v.buffer)].data.data() + v.byteOffset + a.byteOffset + i * 16, 16);
  return out;
}

// Calls f(primitive, i, world position) for every vertex i of every primitive (through the root's translation).
template <typename F>
void ForEachVertex(const tg::Model& m, F f) {
  const tg::Node& root = m.nodes[size_t(m.scenes[0].nodes[0])];
  const std::vector<double> t = root.translation.empty() ? std::vector<double>{0, 0, 0} : root.translation;
  for (int child : root.children)
    for (const tg::Primitive& p : m.meshes[size_t(m.nodes[size_t(child)].mesh)].primitives)
      for (size_t i = 0; i < m.accessors[size_t(p.attributes.at("POSITION"))].count; ++i) {
        const auto x = Vec3(m, p.attributes.at("POSITION"), i);
        f(p, i, std::array<float, 3>{float(t[0] + x[0]), float(t[1] + x[1]), float(t[2] + x[2])});
      }
}

// Every vertex of every primitive: position (world), then H, L, COLOR_0, R.
using Row = std::array<float, 15>;
std::vector<Row> Rows(const tg::Model& m) {
  std::vector<Row> rows;
  ForEachVertex(m, [&](const tg::Primitive& p, size_t i, std::array<float, 3> x) {
    const auto h = Vec3(m, p.attributes.at("_IRRADIANCE"), i), l = Vec3(m, p.attributes.at("_RADIANCE"), i),
               c = Vec3(m, p.attributes.at("COLOR_0"), i), r = Vec3(m, p.attributes.at("_REFLECTANCE"), i);
    rows.push_back({x[0], x[1], x[2], h[0], h[1], h[2], l[0], l[1], l[2], c[0], c[1], c[2], r[0], r[1], r[2]});
  });
  std::sort(rows.begin(), rows.end());
  return rows;
}

std::vector<Row> Rows(const test::PlyData& ply) {
  std::vector<Row> rows;
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    Row r{};
    const char* names[] = {"x", "y", "z", "irradiance_r", "irradiance_g", "irradiance_b", "radiance_r", "radiance_g",
                           "radiance_b"};
    for (int k = 0; k < 9; ++k) r[size_t(k)] = float(ply.vertex.at(names[k])[v]);
    r[12] = float(ply.vertex.at("reflectance_r")[v]), r[13] = float(ply.vertex.at("reflectance_g")[v]),
    r[14] = float(ply.vertex.at("reflectance_b")[v]);
    rows.push_back(r);
  }
  std::sort(rows.begin(), rows.end());
  return rows;
}

std::string ValidatorModule() {
  if (const char* m = std::getenv("PB_GLTF_VALIDATOR_MODULE")) return m;
  return PB_SOURCE_DIR "/.cache/gltf-validator/node_modules/gltf-validator";
}

class GltfOutput : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::TempDirectory("gltf-output");
    const std::string scene = test::WriteClosedBox(dir_, 1.0f, 0.6f, 0.3f, 5.0f);
    for (const char* out : {"b.ply", "b.glb", "b.gltf", "sh.ply", "sh.glb"}) {
      const std::string sh = std::string(out).starts_with("sh") ? " --sh" : "";
      const test::ToolRun run = test::RunTool(PB_BAKE_EXE, scene + " -o " + dir_ + "/" + out +
                                                               " --photons 20000 --threads 2 --seed 3 -q --report " +
                                                               dir_ + "/" + out + ".json" + sh);
      ASSERT_EQ(run.status, 0) << run.output;
    }
  }
  static std::string dir_;
};
std::string GltfOutput::dir_;

TEST_F(GltfOutput, CarriesTheLightOfThePlyOfTheSameBake) {
  const std::vector<Row> ply = Rows(test::ReadPly(dir_ + "/b.ply"));
  for (const char* name : {"b.glb", "b.gltf"}) {
    const std::vector<Row> gltf = Rows(Read(dir_ + "/" + name));
    ASSERT_EQ(gltf.size(), ply.size()) << name;
    for (size_t v = 0; v < ply.size(); ++v) {
      for (int k : {0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 13, 14}) ASSERT_EQ(gltf[v][size_t(k)], ply[v][size_t(k)]) << name << " " << v << " " << k;
    }
  }
}

// Every vertex: position (world), then sh_r0..sh_r3, sh_g0..sh_g3, sh_b0..sh_b3.
using ShRow = std::array<float, 15>;
std::vector<ShRow> ShRows(const tg::Model& m) {
  std::vector<ShRow> rows;
  ForEachVertex(m, [&](const tg::Primitive& p, size_t i, std::array<float, 3> x) {
    ShRow r{x[0], x[1], x[2]};
    int k = 3;
    for (const char* channel : {"_SH_R", "_SH_G", "_SH_B"})
      for (float c : Vec4(m, p.attributes.at(channel), i)) r[size_t(k++)] = c;
    rows.push_back(r);
  });
  std::sort(rows.begin(), rows.end());
  return rows;
}

std::vector<ShRow> ShRows(const test::PlyData& ply) {
  std::vector<ShRow> rows;
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    ShRow r{float(ply.vertex.at("x")[v]), float(ply.vertex.at("y")[v]), float(ply.vertex.at("z")[v])};
    int k = 3;
    for (const char* channel : {"r", "g", "b"})
      for (int c = 0; c < 4; ++c) r[size_t(k++)] = float(ply.vertex.at(std::string("sh_") + channel + std::to_string(c))[v]);
    rows.push_back(r);
  }
  std::sort(rows.begin(), rows.end());
  return rows;
}

TEST_F(GltfOutput, CarriesTheShOfThePlyOfTheSameBake) {
  const std::vector<ShRow> ply = ShRows(test::ReadPly(dir_ + "/sh.ply")), gltf = ShRows(Read(dir_ + "/sh.glb"));
  ASSERT_EQ(gltf.size(), ply.size());
  EXPECT_EQ(gltf, ply);
  EXPECT_GT(std::count_if(ply.begin(), ply.end(), [](const ShRow& r) { return r[5] != 0; }), 0) << "some light";
  EXPECT_FALSE(Read(dir_ + "/b.glb").meshes[0].primitives[0].attributes.count("_SH_R")) << "only with --sh";
}

TEST_F(GltfOutput, Color0IsTheLinearToneCurveOfTheRadiance) {
  std::ifstream report(dir_ + "/b.glb.json");
  const float exposure = nlohmann::json::parse(report)["output"]["display_exposure"].get<float>();
  const std::vector<Row> rows = Rows(Read(dir_ + "/b.glb"));
  float brightest = 0;
  for (const Row& r : rows) {
    const Rgb c = ToneMapLinear({r[6], r[7], r[8]}, exposure);
    EXPECT_FLOAT_EQ(r[9], c.r);
    EXPECT_FLOAT_EQ(r[11], c.b);
    for (int k = 9; k < 12; ++k) EXPECT_TRUE(r[size_t(k)] >= 0 && r[size_t(k)] < 1) << r[size_t(k)];
    brightest = std::max(brightest, r[10]);
  }
  EXPECT_GT(brightest, 0.5f) << "the light itself shows bright";
}

TEST_F(GltfOutput, KeepsNamesAndMarksMaterialsUnlit) {
  const tg::Model m = Read(dir_ + "/b.glb");
  EXPECT_EQ(m.extensionsUsed, std::vector<std::string>{"KHR_materials_unlit"});
  ASSERT_EQ(m.scenes.size(), 1u);
  EXPECT_EQ(m.nodes[size_t(m.scenes[0].nodes[0])].name, "box");
  std::vector<std::string> materials;
  for (const tg::Material& x : m.materials) {
    materials.push_back(x.name);
    EXPECT_TRUE(x.extensions.count("KHR_materials_unlit")) << x.name;
    EXPECT_EQ(x.pbrMetallicRoughness.baseColorFactor, (std::vector<double>{1, 1, 1, 1}));
  }
  EXPECT_NE(std::find(materials.begin(), materials.end(), "light"), materials.end());
}

TEST_F(GltfOutput, PassesTheKhronosValidator) {
  if (!std::filesystem::exists(ValidatorModule() + "/package.json")) {
    if (std::getenv("PB_REQUIRE_GLTF_VALIDATOR")) FAIL() << "the glTF Validator is not installed: bash tools/install-gltf-validator.sh";
    GTEST_SKIP() << "the glTF Validator is not installed; bash tools/install-gltf-validator.sh installs it "
                    "(tools/run-tests.sh does, and then requires it)";
  }
  const test::ToolRun run = test::RunTool("PB_GLTF_VALIDATOR_MODULE=" + ValidatorModule() + " node",
                                          PB_SOURCE_DIR "/tools/gltf-validate.js " + dir_ + "/b.glb " + dir_ +
                                              "/b.gltf " + dir_ + "/sh.glb");
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("sh.glb: 0 errors, 0 warnings"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("b.glb: 0 errors, 0 warnings"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("b.gltf: 0 errors, 0 warnings"), std::string::npos) << run.output;
}

TEST(GltfOutputCli, AsciiIsForPly) {
  const std::string dir = test::TempDirectory("gltf-ascii");
  const std::string scene = test::WriteClosedBox(dir, 1.0f, 0.6f, 0.3f, 5.0f);
  const test::ToolRun run = test::RunTool(PB_BAKE_EXE, scene + " -o " + dir + "/b.glb --ascii --photons 1000 -q");
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("--ascii"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/b.glb"));
}

}  // namespace
}  // namespace pb
