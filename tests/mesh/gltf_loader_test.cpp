// The glTF 2.0 loader (mesh/gltf_loader.h): node transforms, primitive modes, the material mapping, texture
// coordinates, and the errors that name the JSON path of a fault. Files are made by tests/gltf_builder.h, and two
// come from Blender 3.4's exporter (tests/data/blender, tools/blender-export.py).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "mesh/errors.h"
#include "mesh/gltf_loader.h"
#include "mesh/mtl_loader.h"
#include "tests/gltf_builder.h"
#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

using test::GltfBuilder;
using Json = nlohmann::json;

// A unit square in the plane y = 0, facing +y (counter-clockwise seen from above), as positions and two triangles.
const std::vector<std::array<float, 3>> kSquare = {{-0.5f, 0, -0.5f}, {-0.5f, 0, 0.5f}, {0.5f, 0, 0.5f}, {0.5f, 0, -0.5f}};
const std::vector<uint32_t> kSquareIndices = {0, 1, 2, 0, 2, 3};

double Area(const Scene& s) {
  double a = 0;
  for (uint32_t t = 0; t < s.triangles.size(); ++t) a += s.Area(t);
  return a;
}

Point3 Centroid(const Scene& s, uint32_t t) {
  const Point3 a = s.Corner(t, 0), b = s.Corner(t, 1), c = s.Corner(t, 2);
  return {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3, (a.z + b.z + c.z) / 3};
}

// Loading `path` throws an InputError whose text contains `fragment`.
void ExpectError(const std::string& path, const std::string& fragment) {
  try {
    LoadGltf(path);
    ADD_FAILURE() << path << " loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

// A builder holding the unit square as mesh 0.
GltfBuilder SquareMesh(int material = -1) {
  GltfBuilder b;
  const int positions = b.AddPositions(kSquare);  // accessor 0 (view 0); the indices are accessor 1 (view 1)
  b.AddMesh(positions, b.AddIndices(kSquareIndices), material);
  return b;
}

TEST(GltfLoader, NodeHierarchyComposesTranslationRotationAndScale) {
  GltfBuilder b = SquareMesh();
  // A parent moved up 1 m and turned half a turn about x (the square then faces down), its child scaled 2x in x.
  const int child = b.AddNode({{"mesh", 0}, {"scale", {2, 1, 1}}, {"name", "panel"}});
  const int parent = b.AddNode({{"translation", {0, 1, 0}}, {"rotation", {1, 0, 0, 0}}, {"children", {child}}});
  // The same square placed by a matrix (column-major): a quarter turn about z (x to y, y to -x), then 3 m along
  // x. It faces -x.
  const int matrix = b.AddNode({{"mesh", 0}, {"matrix", {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 3, 0, 0, 1}}});
  b.SetRoots({parent, matrix});
  const LoadedScene loaded = LoadGltf(b.WriteGltf(test::TempDirectory("gltf-nodes"), "s"));
  const Scene& scene = loaded.scene;
  ASSERT_EQ(scene.triangles.size(), 4u);
  for (uint32_t t = 0; t < 2; ++t) {
    EXPECT_NEAR(scene.FrontNormal(t).y, -1, 1e-6) << "the half turn makes the square face down";
    EXPECT_NEAR(Centroid(scene, t).y, 1, 1e-6);
    EXPECT_NEAR(scene.Area(t), 1.0, 1e-6) << "scaled 2x in x: area 2 over two triangles";
    EXPECT_EQ(scene.objectNames[scene.triangles[t].object], "panel");
  }
  for (uint32_t t = 2; t < 4; ++t) {
    EXPECT_NEAR(scene.FrontNormal(t).x, -1, 1e-6) << "a quarter turn about z takes +y to -x";
    EXPECT_NEAR(Centroid(scene, t).x, 3, 1e-6);
  }
}

TEST(GltfLoader, MirroredNodesKeepTheirFrontSide) {
  GltfBuilder b = SquareMesh();
  b.SetRoots({b.AddNode({{"mesh", 0}, {"scale", {-1, 1, 1}}}), b.AddNode({{"mesh", 0}, {"scale", {1, -1, 1}}})});
  const Scene scene = LoadGltf(b.WriteGltf(test::TempDirectory("gltf-mirror"), "s")).scene;
  ASSERT_EQ(scene.triangles.size(), 4u);
  // Mirrored in x the square still faces +y; mirrored in y it faces -y: its normal is mirrored with it.
  for (uint32_t t = 0; t < 2; ++t) EXPECT_NEAR(scene.FrontNormal(t).y, 1, 1e-6) << t;
  for (uint32_t t = 2; t < 4; ++t) EXPECT_NEAR(scene.FrontNormal(t).y, -1, 1e-6) << t;
}

TEST(GltfLoader, StripsFansAndUnindexedPrimitivesAreTriangles) {
  GltfBuilder b;
  const int p = b.AddPositions(kSquare);
  b.AddMesh(p, b.AddIndices({1, 2, 0, 3}), -1, 5);  // strip: (1 2 0), (0 2 3) once the second is turned back
  b.AddMesh(p, -1, -1, 6);                          // fan about corner 0
  b.AddMesh(p, -1, -1, 1);                          // lines: skipped with a warning
  b.SetRoots({b.AddNode({{"mesh", 0}}), b.AddNode({{"mesh", 1}, {"translation", {0, 1, 0}}}),
              b.AddNode({{"mesh", 2}})});
  const LoadedScene loaded = LoadGltf(b.WriteGlb(test::TempDirectory("gltf-modes"), "s"));
  ASSERT_EQ(loaded.scene.triangles.size(), 4u);
  EXPECT_NEAR(Area(loaded.scene), 2.0, 1e-6);
  for (uint32_t t = 0; t < 4; ++t) EXPECT_NEAR(loaded.scene.FrontNormal(t).y, 1, 1e-6) << "all face up: " << t;
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("s.glb: warning: /meshes/2/primitives/0: mode 1"), std::string::npos)
      << loaded.warnings[0];
}

TEST(GltfLoader, GlbAndGltfOfOneSceneLoadAlike) {
  GltfBuilder b = SquareMesh();
  b.SetRoots({b.AddNode({{"mesh", 0}, {"translation", {5, 0, 0}}}), b.AddNode({{"mesh", 0}})});
  const std::string dir = test::TempDirectory("gltf-both");
  const Scene a = LoadGltf(b.WriteGltf(dir, "s")).scene, c = LoadGltf(b.WriteGlb(dir, "s")).scene;
  ASSERT_EQ(a.positions.size(), c.positions.size());
  for (size_t i = 0; i < a.positions.size(); ++i) {
    EXPECT_EQ(a.positions[i].x, c.positions[i].x);
    EXPECT_EQ(a.positions[i].z, c.positions[i].z);
  }
  EXPECT_EQ(a.objectNames, (std::vector<std::string>{"node 0", "node 1"})) << "an instance per node";
}

TEST(GltfLoader, MaterialsMapOntoDiffuseMirrorGlassAndLights) {
  GltfBuilder b;
  b.AddMaterial({{"name", "paint"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 0.125, 1}}, {"metallicFactor", 0}}}});
  b.AddMaterial({{"name", "chrome"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.9, 0.9, 1}}, {"metallicFactor", 0.75}, {"roughnessFactor", 0.05}}}});
  b.AddMaterial({{"name", "brushed"}, {"pbrMetallicRoughness", {{"metallicFactor", 1}, {"roughnessFactor", 0.5}}}});
  b.AddMaterial({{"name", "glass"},
                 {"pbrMetallicRoughness", {{"baseColorFactor", {1, 0.5, 1, 1}}, {"roughnessFactor", 0}}},
                 {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 0.5}}}, {"KHR_materials_ior", {{"ior", 1.33}}}}}});
  b.AddMaterial({{"name", "lamp"}, {"emissiveFactor", {1, 0.5, 0.25}},
                 {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 8}}}}}});
  const int p = b.AddPositions(kSquare), i = b.AddIndices(kSquareIndices);
  std::vector<int> roots;
  for (int m = 0; m < 5; ++m) {
    b.AddMesh(p, i, m);
    roots.push_back(b.AddNode({{"mesh", m}, {"translation", {2 * m, 0, 0}}}));
  }
  b.SetRoots(roots);
  const LoadedScene loaded = LoadGltf(b.WriteGltf(test::TempDirectory("gltf-materials"), "s"));
  const std::vector<Material>& m = loaded.scene.materials;
  ASSERT_EQ(m.size(), 5u);
  EXPECT_EQ(m[0].kind, MaterialClass::kDiffuse);
  EXPECT_FLOAT_EQ(m[0].albedo.g, 0.25f);
  EXPECT_EQ(m[1].kind, MaterialClass::kMirror);
  EXPECT_FLOAT_EQ(m[1].specular.r, 0.9f * 0.75f);
  EXPECT_FLOAT_EQ(m[1].albedo.r, 0.9f * 0.25f);
  EXPECT_EQ(m[2].kind, MaterialClass::kDiffuse) << "rough metal";
  // glTF's default base colour 1 is capped as an OBJ's Kd 1 is: photons in a white room were never absorbed (the
  // Lantern stored 78M hits from 200k photons).
  EXPECT_FLOAT_EQ(m[2].albedo.r, kMaxReflectance);
  EXPECT_EQ(m[3].kind, MaterialClass::kGlass);
  EXPECT_FLOAT_EQ(m[3].ior, 1.33f);
  EXPECT_FLOAT_EQ(m[3].transmittance.g, 0.25f);
  EXPECT_FLOAT_EQ(m[4].emission.r, 8.0f);
  EXPECT_FLOAT_EQ(m[4].emission.b, 2.0f);
  std::string warnings;
  for (const std::string& w : loaded.warnings) warnings += w + "\n";
  EXPECT_NE(warnings.find("/materials/2: a rough metal"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("/materials/2: reflectance 1.000 capped at 0.99"), std::string::npos) << warnings;
}

// A 2 x 1 texture, red then green, under KHR_texture_transform: texture coordinates are transformed as they are
// read and turned to our (s, t) = (u, 1 - v), so that the albedo at each corner is the texel the transform names.
TEST(GltfLoader, TextureCoordinatesFollowKhrTextureTransform) {
  const std::string dir = test::TempDirectory("gltf-texture");
  test::WritePngRgb8(dir + "/rg.png", 2, 1, {255, 0, 0, 0, 255, 0});
  GltfBuilder b;
  b.json()["images"] = {{{"uri", "rg.png"}}};
  b.json()["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33071}}};
  b.json()["textures"] = {{{"source", 0}, {"sampler", 0}}};
  // u' = 0.5 u + 0.5: every u lands in the right (green) half.
  b.AddMaterial(Json::parse(R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
      "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "scale": [0.5, 1]}}}}})"));
  const int uv = b.AddTexcoords({{0, 0}, {0, 1}, {1, 1}, {1, 0}});
  const int positions = b.AddPositions(kSquare);
  b.AddMesh(positions, b.AddIndices(kSquareIndices), 0, 4, uv);
  b.SetRoots({b.AddNode({{"mesh", 0}})});
  const Scene scene = LoadGltf(b.WriteGltf(dir, "s")).scene;
  ASSERT_EQ(scene.textures.size(), 1u);
  EXPECT_EQ(scene.textures[0].path, dir + "/rg.png");
  EXPECT_TRUE(scene.materials[0].textureClamp);
  ASSERT_EQ(scene.texcoords.size(), 4u);
  EXPECT_FLOAT_EQ(scene.texcoords[1].u, 0.5f);
  EXPECT_FLOAT_EQ(scene.texcoords[1].v, 0.0f) << "glTF v = 1 is the image's bottom: t = 0";
  EXPECT_FLOAT_EQ(scene.texcoords[2].u, 1.0f);
  // Bilinear between the texel centres s = 1/4 (red) and 3/4 (green), clamped: corner 0 (u = 0) reads s = 1/2,
  // half of each (untransformed it would read red); corner 2 (u = 1) reads s = 1, green. A full texel under base
  // colour 1 is capped at kMaxReflectance.
  EXPECT_NEAR(scene.AlbedoAt(0, 0, 0).r, 0.5f * kMaxReflectance, 1e-5);
  EXPECT_NEAR(scene.AlbedoAt(0, 0, 0).g, 0.5f * kMaxReflectance, 1e-5);
  EXPECT_NEAR(scene.AlbedoAt(0, 0, 1).r, 0.0f, 1e-5);
  EXPECT_NEAR(scene.AlbedoAt(0, 0, 1).g, kMaxReflectance, 1e-5);
}

// A textured material on a primitive without the texture coordinates it names (no TEXCOORD_0 for the base colour,
// no TEXCOORD_1 for an emissive texture read with texCoord 1) once crashed the bake, which read coordinates that did
// not exist (issue 60). As in an OBJ, such a primitive takes the colour times the image's mean, with a warning, and
// the bake runs through.
TEST(GltfLoader, ATextureWithoutItsCoordinatesReadsTheImagesMean) {
  const std::string dir = test::TempDirectory("gltf-no-texcoords");
  test::WritePngRgb8(dir + "/rg.png", 2, 1, {255, 0, 0, 0, 255, 0});
  GltfBuilder b;
  b.json()["images"] = {{{"uri", "rg.png"}}};
  b.json()["textures"] = {{{"source", 0}}};
  b.AddMaterial(Json::parse(R"({"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
      "baseColorTexture": {"index": 0}}})"));
  b.AddMaterial(Json::parse(R"({"emissiveFactor": [4, 4, 4], "emissiveTexture": {"index": 0, "texCoord": 1}})"));
  const int positions = b.AddPositions(kSquare), indices = b.AddIndices(kSquareIndices);
  b.AddMesh(positions, indices, 0);
  b.AddMesh(positions, indices, 1);
  b.SetRoots({b.AddNode({{"mesh", 0}}), b.AddNode({{"mesh", 1}, {"translation", {0, 1, 0}}, {"rotation", {1, 0, 0, 0}}})});
  const std::string file = b.WriteGltf(dir, "s");
  const LoadedScene loaded = LoadGltf(file);
  const Scene& scene = loaded.scene;
  ASSERT_EQ(scene.triangles.size(), 4u);
  const Material& floor = scene.MaterialOf(0);
  EXPECT_EQ(floor.albedoTexture, -1);
  EXPECT_NEAR(floor.albedo.r, 0.8f * 0.5f, 1e-5) << "the image's mean: half red, half green";
  EXPECT_NEAR(floor.albedo.g, 0.8f * 0.5f, 1e-5);
  EXPECT_NEAR(floor.albedo.b, 0.0f, 1e-6);
  EXPECT_NEAR(scene.MaterialOf(2).emission.r, 4 * 0.5f, 1e-5);
  std::string warnings;
  for (const std::string& w : loaded.warnings) warnings += w + "\n";
  // One warning of each kind, counting the rest: the base colour's and the emissive texture's.
  EXPECT_NE(warnings.find("no TEXCOORD_0; the texture's mean is used instead (2 in all)"), std::string::npos) << warnings;
  const test::ToolRun run = test::RunBake("'" + file + "' -o '" + dir + "/s.ply' --photons 20000 --h 0.2 --threads 2");
  EXPECT_EQ(run.status, 0) << run.output;
}

// What the loader does not read is said, never dropped in silence (issue 39): vertex colours (a vertex-coloured
// box baked grey), a double-sided light, a glass ior glass cannot have (read as 1.5); and Draco-compressed geometry is refused by
// its extension's name, not as "accessor[0] invalid bufferView".
TEST(GltfLoader, WhatIsNotReadIsSaidByName) {
  const std::string dir = test::TempDirectory("gltf-unread");
  GltfBuilder b;
  b.AddMaterial({{"name", "lamp"}, {"emissiveFactor", {1, 1, 1}}, {"doubleSided", true}});
  b.AddMaterial({{"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}, {"KHR_materials_ior", {{"ior", 0}}}}}});
  const int positions = b.AddPositions(kSquare);
  b.AddMesh(positions, b.AddIndices(kSquareIndices), 0);
  b.json()["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = positions;  // a VEC3 float accessor
  b.AddMesh(positions, b.AddIndices(kSquareIndices), 1);
  b.SetRoots({b.AddNode({{"mesh", 0}}), b.AddNode({{"mesh", 1}, {"translation", {0, 1, 0}}})});
  const LoadedScene loaded = LoadGltf(b.WriteGltf(dir, "unread"));
  std::string warnings;
  for (const std::string& w : loaded.warnings) warnings += w + "\n";
  for (const char* said : {"/meshes/0/primitives/0/attributes/COLOR_0: vertex colours are not read",
                           "/materials/0: doubleSided is not read",
                           "/materials/1/extensions/KHR_materials_ior/ior: ior 0 is outside (0, 10]: baked as 1.5"})
    EXPECT_NE(warnings.find(said), std::string::npos) << said << "\n" << warnings;
  GltfBuilder draco = SquareMesh();
  draco.json()["extensionsUsed"] = {"KHR_draco_mesh_compression"};  // used, not listed as required
  draco.json()["accessors"][0].erase("bufferView");
  draco.json()["meshes"][0]["primitives"][0]["extensions"] = {
      {"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", {{"POSITION", 0}}}}}};
  draco.SetRoots({draco.AddNode({{"mesh", 0}})});
  ExpectError(draco.WriteGltf(dir, "draco"), "uses extension 'KHR_draco_mesh_compression' (compressed geometry)");
}

// EXT_mesh_gpu_instancing (issue 39: 1 of 125 instances was baked): each instance is the node's mesh at the node's
// transform times the instance's own T R S.
TEST(GltfLoader, GpuInstancesAreEachBakedAtTheirOwnTransform) {
  const std::string dir = test::TempDirectory("gltf-instances");
  GltfBuilder b = SquareMesh();
  const std::vector<float> translation = {0, 0, 0, 2, 0, 0, 4, 0, 0};
  const float h = float(std::sqrt(0.5));
  const std::vector<float> rotation = {0, 0, 0, 1, h, 0, 0, h, 0, 0, 0, 1};  // the second turned 90 deg about x
  const std::vector<float> scale = {1, 1, 1, 1, 1, 1, 2, 1, 1};
  const auto attribute = [&](const std::vector<float>& v, const char* type) {
    return b.AddAccessor(b.AddView(v.data(), v.size() * sizeof(float)), 5126, 3, type);
  };
  const Json attributes = {{"TRANSLATION", attribute(translation, "VEC3")},
                           {"ROTATION", attribute(rotation, "VEC4")}, {"SCALE", attribute(scale, "VEC3")}};
  b.SetRoots({b.AddNode({{"mesh", 0}, {"translation", {0, 1, 0}},
                         {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attributes}}}}}})});
  const Scene s = LoadGltf(b.WriteGltf(dir, "instances")).scene;
  ASSERT_EQ(s.triangles.size(), 6u);
  EXPECT_NEAR(Area(s), 1 + 1 + 2, 1e-5);
  for (uint32_t t = 0; t < 6; ++t) {
    const Point3 c = Centroid(s, t);
    const Normal3 n = s.FrontNormal(t);
    EXPECT_NEAR(c.y, 1, 0.5) << t;  // the node's translation applies to every instance
    if (t / 2 == 1) EXPECT_NEAR(n.z, 1, 1e-5) << "turned about x, the square faces +z";
    else EXPECT_NEAR(n.y, 1, 1e-5) << t;
    EXPECT_NEAR(c.x, 2 * (t / 2), 0.7) << t;
  }
}

// A small file whose shared nodes or instances multiply into more than the bake could hold is refused by what it
// would expand to, at once (a chain of 40 nodes, each the child of the one before twice, filled 8 GB before).
TEST(GltfLoader, HierarchiesThatMultiplyBeyondTheLimitsAreRefused) {
  const std::string dir = test::TempDirectory("gltf-bombs");
  {
    GltfBuilder b = SquareMesh();
    int child = b.AddNode({{"mesh", 0}});
    for (int depth = 0; depth < 40; ++depth) child = b.AddNode({{"children", {child, child}}});
    b.SetRoots({child});
    ExpectError(b.WriteGltf(dir, "shared"), "the scene's hierarchy visits more than 1048576 nodes");
  }
  {
    GltfBuilder b = SquareMesh();
    const int zeros = b.AddAccessor(-1, 5126, size_t(1) << 24, "VEC3");  // 2^24 instances, all at the node
    const int node = b.AddNode(
        {{"mesh", 0}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", zeros}}}}}}}});
    b.SetRoots({b.AddNode({{"children", {node, node, node}}})});
    ExpectError(b.WriteGltf(dir, "instanced"), "the scene expands to more than 67108864 triangles");
  }
  {
    GltfBuilder b = SquareMesh();
    const std::vector<float> two = {0, 0, 0, 1, 0, 0}, three = {1, 1, 1, 1, 1, 1, 1, 1, 1};
    const int t = b.AddAccessor(b.AddView(two.data(), two.size() * sizeof(float)), 5126, 2, "VEC3");
    const int s = b.AddAccessor(b.AddView(three.data(), three.size() * sizeof(float)), 5126, 3, "VEC3");
    b.SetRoots({b.AddNode({{"mesh", 0}, {"extensions", {{"EXT_mesh_gpu_instancing",
                                                          {{"attributes", {{"TRANSLATION", t}, {"SCALE", s}}}}}}}})});
    ExpectError(b.WriteGltf(dir, "counts"), "/nodes/0/extensions/EXT_mesh_gpu_instancing/attributes: SCALE has 3 "
                                            "instances where the others have 2");
  }
}

// Depth that costs the stack or the clock (issue 60): `extras` nesting 100,000 arrays overflowed tinygltf's
// recursive conversion (refused, .gltf and .glb alike, naming the line); a chain of 100,000 nodes is legal and is
// walked in linear time (each visit once searched all its ancestors), composing every step.
TEST(GltfLoader, DeepNestingIsRefusedAndDeepChainsLoad) {
  const std::string dir = test::TempDirectory("gltf-deep");
  {
    GltfBuilder b = SquareMesh();
    b.SetRoots({b.AddNode({{"mesh", 0}})});
    b.json()["extras"] = "NESTED";
    for (const bool binary : {false, true}) {
      const std::string path = binary ? b.WriteGlb(dir, "nested") : b.WriteGltf(dir, "nested");
      std::string text = test::ReadBytes(path);
      const size_t at = text.find("\"NESTED\"");
      ASSERT_NE(at, std::string::npos);
      const std::string nested = std::string(100'000, '[') + std::string(100'000, ']');
      text.replace(at, 8, nested);
      if (binary) {  // the JSON chunk grows by a multiple of 4: its length and the file's are rewritten (little-endian)
        uint32_t chunk = 0;
        std::memcpy(&chunk, text.data() + 12, 4);
        const uint32_t lengths[2] = {uint32_t(text.size()), uint32_t(chunk - 8 + nested.size())};
        std::memcpy(text.data() + 8, lengths, 8);
      }
      test::WriteText(path, text);
      ExpectError(path, "error: the JSON nests arrays and objects deeper than 1000 levels");
    }
  }
  GltfBuilder b = SquareMesh();
  int child = b.AddNode({{"mesh", 0}});
  constexpr int kDepth = 100'000;
  for (int depth = 0; depth < kDepth; ++depth) child = b.AddNode({{"children", {child}}, {"translation", {0, 1e-5, 0}}});
  b.SetRoots({child});
  const Scene scene = LoadGltf(b.WriteGltf(dir, "chain")).scene;
  ASSERT_EQ(scene.triangles.size(), 2u);
  EXPECT_NEAR(Centroid(scene, 0).y, kDepth * 1e-5, 1e-6) << "every node's translation composed";
}

TEST(GltfLoader, FaultsNameTheJsonPath) {
  const std::string dir = test::TempDirectory("gltf-faults");
  {
    GltfBuilder b;
    const int positions = b.AddPositions(kSquare);
    b.AddMesh(positions, b.AddIndices({0, 1, 7}));
    b.SetRoots({b.AddNode({{"mesh", 0}})});
    ExpectError(b.WriteGltf(dir, "index"), "index.gltf: error: /meshes/0/primitives/0/indices: index 2 is 7, "
                                                        "out of range (4 vertices)");
  }
  {
    GltfBuilder b = SquareMesh();
    b.json()["accessors"][0]["count"] = 40;  // more positions than the buffer view holds
    b.SetRoots({b.AddNode({{"mesh", 0}})});
    ExpectError(b.WriteGlb(dir, "short"), "/accessors/0: 40 elements from byte 0 do not fit in "
                                                       "/bufferViews/0 of 48 bytes");
  }
  {
    GltfBuilder b = SquareMesh();
    b.json()["bufferViews"][1]["byteOffset"] = 4000;
    b.SetRoots({b.AddNode({{"mesh", 0}})});
    ExpectError(b.WriteGltf(dir, "view"), "/bufferViews/1 (bytes 4000 to 4024) lies beyond its buffer");
  }
  {
    GltfBuilder b = SquareMesh();
    const int a = b.AddNode({{"mesh", 0}});
    b.json()["nodes"][size_t(a)]["children"] = {1};
    b.AddNode({{"children", {a}}});
    b.SetRoots({a});
    ExpectError(b.WriteGltf(dir, "cycle"), "/nodes/0: the node is its own ancestor");
  }
  {
    GltfBuilder b = SquareMesh();
    b.json()["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    b.json()["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    b.SetRoots({b.AddNode({{"mesh", 0}})});
    ExpectError(b.WriteGltf(dir, "draco"), "the file uses extension 'KHR_draco_mesh_compression' (compressed "
                                           "geometry)");
  }
  {
    GltfBuilder b = SquareMesh();
    b.SetRoots({b.AddNode({{"mesh", 0}, {"translation", {1.7e308, 0, 0}}, {"scale", {1e308, 1, 1}}})});
    ExpectError(b.WriteGltf(dir, "huge"), "/meshes/0/primitives/0/attributes/POSITION: position 2 is not "
                                                       "finite");
  }
  {
    GltfBuilder b;
    b.AddMesh(b.AddPositions(kSquare), -1, -1, 0);
    b.SetRoots({b.AddNode({{"mesh", 0}})});
    ExpectError(b.WriteGltf(dir, "points"), "/meshes/0/primitives/0: scene has no triangles to bake");
  }
  {
    GltfBuilder b = SquareMesh();
    b.json()["accessors"][0].erase("bufferView");  // zeros, of a count no buffer bounds
    b.json()["accessors"][0]["count"] = 4000000000u;
    b.SetRoots({b.AddNode({{"mesh", 0}})});
    ExpectError(b.WriteGlb(dir, "zeros"), "/accessors/0 has no buffer view and 4000000000 elements");
  }
  // Factors out of glTF's bounds that would make light (issue 39: each baked, a negative colour into negative flux).
  for (const auto& [material, fault] :
       {std::pair{Json{{"pbrMetallicRoughness", {{"baseColorFactor", {-1, 0.5, 0.5, 1}}}}},
                  "/materials/0/pbrMetallicRoughness/baseColorFactor: must not be negative"},
        std::pair{Json{{"pbrMetallicRoughness", {{"metallicFactor", 2}}}},
                  "/materials/0/pbrMetallicRoughness/metallicFactor: 2 must lie in [0, 1]"},
        std::pair{Json{{"emissiveFactor", {-1, 1, 1}}}, "/materials/0/emissiveFactor: must not be negative"},
        std::pair{Json{{"emissiveFactor", {1, 1, 1}},
                       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", -3}}}}}},
                  "/materials/0/extensions/KHR_materials_emissive_strength/emissiveStrength: must not be negative"}}) {
    GltfBuilder b = SquareMesh(0);
    b.AddMaterial(material);
    b.SetRoots({b.AddNode({{"mesh", 0}})});
    ExpectError(b.WriteGltf(dir, "factors"), fault);
  }
  test::WriteText(dir + "/broken.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [");
  ExpectError(dir + "/broken.gltf", "broken.gltf: error: not a glTF 2.0 file that can be read");
  test::WriteText(dir + "/missing-bin.gltf", R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "none.bin", "byteLength": 4}]})");
  ExpectError(dir + "/missing-bin.gltf", "missing-bin.gltf: error: not a glTF 2.0 file");
}

// KHR_lights_punctual: a point light and a spot turned to point down by its node, both 1 m over a black floor;
// candela become W/sr over the luminous efficacy, and the baked floor's corners read I cos / r^2.
TEST(GltfLoader, PunctualLightsAreReadAndBaked) {
  const std::string dir = test::TempDirectory("gltf-lights");
  GltfBuilder b;
  b.AddMaterial({{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}}});
  const int positions = b.AddPositions({{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}});
  b.AddMesh(positions, b.AddIndices(kSquareIndices), 0);
  b.json()["extensionsUsed"] = {"KHR_lights_punctual"};
  b.json()["extensions"]["KHR_lights_punctual"]["lights"] = Json::parse(R"([
      {"type": "point", "name": "bulb", "intensity": 683, "color": [1, 0.5, 0.25]},
      {"type": "spot", "intensity": 1366, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}, "range": 10}])");
  const int bulb = b.AddNode({{"translation", {0, 1, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  const int spot = b.AddNode({{"translation", {5, 1, 0}}, {"rotation", {-std::sqrt(0.5), 0, 0, std::sqrt(0.5)}},
                              {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  b.SetRoots({b.AddNode({{"mesh", 0}}), bulb, spot});
  const std::string path = b.WriteGltf(dir, "s");
  const LoadedScene loaded = LoadGltf(path);
  const std::vector<AnalyticLight>& lights = loaded.scene.analyticLights;
  ASSERT_EQ(lights.size(), 2u);
  EXPECT_EQ(lights[0].kind, LightKind::kPoint);
  EXPECT_EQ(lights[0].name, "bulb");
  EXPECT_FLOAT_EQ(lights[0].intensity.r, 1.0f) << "683 cd over 683 lm/W";
  EXPECT_FLOAT_EQ(lights[0].intensity.b, 0.25f);
  EXPECT_FLOAT_EQ(lights[0].position.y, 1.0f);
  EXPECT_EQ(lights[1].kind, LightKind::kSpot);
  EXPECT_NEAR(lights[1].direction.y, -1.0f, 1e-6) << "-z turned a quarter about x points down";
  EXPECT_NEAR(lights[1].cosOuter, std::cos(0.5), 1e-6);
  EXPECT_NE(loaded.warnings.back().find("range is ignored"), std::string::npos) << loaded.warnings.back();
  const test::ToolRun run = test::RunTool(PB_BAKE_EXE, path + " -o " + dir + "/s.ply --photons 20000 -q");
  ASSERT_EQ(run.status, 0) << run.output;
  const test::PlyData ply = test::ReadPly(dir + "/s.ply");
  // Every corner is 1 m below and sqrt(2) m beside the bulb. Its light is sampled 0.2 mm inside the floor (the
  // rays' start, baker/3_irradiance_field.h), which raises it by 3e-4 of itself here.
  for (size_t v = 0; v < ply.VertexCount(); ++v)
    EXPECT_NEAR(ply.vertex.at("irradiance_r")[v] / (1 / (3 * std::sqrt(3.0))), 1, 1e-3) << v;
}

// A light placed where the ray tracer cannot go (issue 60: Embree aborted on it): at 1e300 m, or under nodes whose
// scales multiply past a double, is refused naming the node, as a lights file's position beyond 1e9 m is; a spot
// under a huge but finite scale keeps its direction.
TEST(GltfLoader, LightsBeyondTheSceneBoundsAreRefused) {
  const std::string dir = test::TempDirectory("gltf-far-lights");
  const auto withLight = [&](const std::string& name, const std::string& type, const std::vector<Json>& chain) {
    GltfBuilder b = SquareMesh();
    b.json()["extensionsUsed"] = {"KHR_lights_punctual"};
    Json light = {{"type", type}, {"intensity", 10}};
    if (type == "spot") light["spot"] = {{"outerConeAngle", 0.5}};
    b.json()["extensions"]["KHR_lights_punctual"]["lights"] = Json::array({light});  // {light} copies under clang
    int child = -1;
    for (size_t k = chain.size(); k-- > 0;) {
      Json node = chain[k];
      if (child >= 0) node["children"] = Json::array({child});
      if (k + 1 == chain.size()) node["extensions"] = {{"KHR_lights_punctual", {{"light", 0}}}};
      child = b.AddNode(node);
    }
    b.SetRoots({b.AddNode({{"mesh", 0}}), child});
    return b.WriteGltf(dir, name);
  };
  ExpectError(withLight("far", "point", {{{"translation", {0, 1e300, 0}}}}),
              "KHR_lights_punctual/light: the light lies at (0, 1e+300, 0) m after the nodes' transforms");
  const Json huge = {{"scale", {1e200, 1e200, 1e200}}};
  ExpectError(withLight("overflow", "spot", {huge, huge, {{"translation", {0, 1, 0}}}}), "beyond 1e+09 m");
  const LoadedScene scaled = LoadGltf(withLight("scaled", "spot", {huge, {{"scale", {1, 1e-200, 1}}}}));
  ASSERT_EQ(scaled.scene.analyticLights.size(), 1u);
  EXPECT_NEAR(scaled.scene.analyticLights[0].direction.z, -1.0f, 1e-6);
}

// Blender 3.4's glTF exporter writes the scene of tools/blender-export.py as a .glb (images inside) and as a
// .gltf with a .bin and images beside it: both load alike, with the materials Blender meant, and bake.
TEST(GltfLoader, Blender34ExportsLoadAndBake) {
  const std::string dir = PB_SOURCE_DIR "/tests/data/blender/";
  const LoadedScene glb = LoadGltf(dir + "scene.glb"), separate = LoadGltf(dir + "scene_separate.gltf");
  EXPECT_EQ(glb.scene.triangles.size(), separate.scene.triangles.size());
  EXPECT_NEAR(Area(glb.scene), Area(separate.scene), 1e-6);
  EXPECT_EQ(glb.scene.textures.size(), 2u);
  EXPECT_EQ(separate.scene.textures.size(), 2u);
  std::map<std::string, const Material*> byName;
  for (const Material& m : glb.scene.materials) byName[m.name] = &m;
  ASSERT_TRUE(byName.count("Glass") && byName.count("Lamp") && byName.count("Metal"));
  EXPECT_EQ(byName["Glass"]->kind, MaterialClass::kGlass);
  EXPECT_NEAR(byName["Glass"]->ior, 1.45f, 1e-6);
  EXPECT_FLOAT_EQ(byName["Lamp"]->emission.g, 10.0f) << "Emission Strength 10 as KHR_materials_emissive_strength";
  EXPECT_EQ(byName["Metal"]->kind, MaterialClass::kDiffuse) << "roughness 0.3";
  double lArea = 0;
  for (uint32_t t = 0; t < glb.scene.triangles.size(); ++t)
    if (glb.scene.objectNames[glb.scene.triangles[t].object] == "LShape") lArea += glb.scene.Area(t);
  EXPECT_NEAR(lArea, 0.75, 1e-5);
  const std::string out = test::TempDirectory("gltf-blender-bake") + "/b.ply";
  const test::ToolRun run = test::RunTool(PB_BAKE_EXE, dir + "scene.glb -o " + out + " --photons 20000 --threads 2 -q");
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_TRUE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace pb
