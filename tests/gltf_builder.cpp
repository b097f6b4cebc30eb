#include "tests/gltf_builder.h"

#include <algorithm>
#include <cstring>
#include <fstream>

namespace pb::test {

GltfBuilder::GltfBuilder() {
  json_ = {{"asset", {{"version", "2.0"}, {"generator", "photonbake tests"}}},
           {"scenes", {{{"nodes", nlohmann::json::array()}}}},
           {"scene", 0},
           {"nodes", nlohmann::json::array()},
           {"meshes", nlohmann::json::array()},
           {"accessors", nlohmann::json::array()},
           {"bufferViews", nlohmann::json::array()}};
}

int GltfBuilder::AddView(const void* bytes, size_t size, int stride) {
  while (bin_.size() % 4) bin_ += '\0';
  nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", size}};
  if (stride) view["byteStride"] = stride;
  bin_.append(static_cast<const char*>(bytes), size);
  json_["bufferViews"].push_back(view);
  return int(json_["bufferViews"].size() - 1);
}

int GltfBuilder::AddAccessor(int view, int componentType, size_t count, const std::string& type, size_t offset) {
  nlohmann::json a = {{"componentType", componentType}, {"count", count}, {"type", type}};
  if (view >= 0) a["bufferView"] = view;
  if (offset) a["byteOffset"] = offset;
  json_["accessors"].push_back(a);
  return int(json_["accessors"].size() - 1);
}

int GltfBuilder::AddPositions(const std::vector<std::array<float, 3>>& p) {
  const int a = AddAccessor(AddView(p.data(), p.size() * 12), 5126, p.size(), "VEC3");
  std::array<float, 3> lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
  for (const auto& q : p)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], q[k]), hi[k] = std::max(hi[k], q[k]);
  json_["accessors"][size_t(a)]["min"] = lo;
  json_["accessors"][size_t(a)]["max"] = hi;
  return a;
}

int GltfBuilder::AddTexcoords(const std::vector<std::array<float, 2>>& uv) {
  return AddAccessor(AddView(uv.data(), uv.size() * 8), 5126, uv.size(), "VEC2");
}

int GltfBuilder::AddIndices(const std::vector<uint32_t>& i) {
  return AddAccessor(AddView(i.data(), i.size() * 4), 5125, i.size(), "SCALAR");
}

int GltfBuilder::AddMesh(int positions, int indices, int material, int mode, int texcoords) {
  nlohmann::json primitive = {{"attributes", {{"POSITION", positions}}}, {"mode", mode}};
  if (indices >= 0) primitive["indices"] = indices;
  if (material >= 0) primitive["material"] = material;
  if (texcoords >= 0) primitive["attributes"]["TEXCOORD_0"] = texcoords;
  json_["meshes"].push_back({{"primitives", {primitive}}});
  return int(json_["meshes"].size() - 1);
}

int GltfBuilder::AddMaterial(const nlohmann::json& material) {
  json_["materials"].push_back(material);
  return int(json_["materials"].size() - 1);
}

int GltfBuilder::AddNode(const nlohmann::json& node) {
  json_["nodes"].push_back(node);
  return int(json_["nodes"].size() - 1);
}

void GltfBuilder::SetRoots(const std::vector<int>& nodes) { json_["scenes"][0]["nodes"] = nodes; }

std::string GltfBuilder::WriteGltf(const std::string& dir, const std::string& name) const {
  nlohmann::json j = json_;
  j["buffers"] = {{{"uri", name + ".bin"}, {"byteLength", bin_.size()}}};
  std::ofstream(dir + "/" + name + ".bin", std::ios::binary) << bin_;
  std::ofstream(dir + "/" + name + ".gltf") << j.dump(1);
  return dir + "/" + name + ".gltf";
}

std::string GltfBuilder::WriteGlb(const std::string& dir, const std::string& name) const {
  nlohmann::json j = json_;
  std::string bin = bin_;
  while (bin.size() % 4) bin += '\0';
  j["buffers"] = {{{"byteLength", bin.size()}}};
  std::string text = j.dump();
  while (text.size() % 4) text += ' ';
  auto u32 = [](std::string& out, uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  std::string glb = "glTF";
  u32(glb, 2);
  u32(glb, uint32_t(12 + 8 + text.size() + 8 + bin.size()));
  u32(glb, uint32_t(text.size()));
  glb += "JSON" + text;
  u32(glb, uint32_t(bin.size()));
  glb += std::string("BIN\0", 4) + bin;
  std::ofstream(dir + "/" + name + ".glb", std::ios::binary) << glb;
  return dir + "/" + name + ".glb";
}

}  // namespace pb::test
