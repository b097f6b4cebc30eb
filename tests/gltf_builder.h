// Hand-made glTF 2.0 files for the loader's tests: buffers, accessors, meshes, materials and nodes added one by
// one (nlohmann::json), written as a .gltf with an external .bin or as a binary .glb. Each Add returns the index
// of what it added, so a test can also break a file on purpose (an index out of range, a short buffer).
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pb::test {

class GltfBuilder {
 public:
  GltfBuilder();
  nlohmann::json& json() { return json_; }

  // Appends raw bytes to the one buffer as a new buffer view (4-byte aligned); returns the view's index.
  int AddView(const void* bytes, size_t size, int stride = 0);
  int AddAccessor(int view, int componentType, size_t count, const std::string& type, size_t offset = 0);
  int AddPositions(const std::vector<std::array<float, 3>>& p);  // VEC3 float, with min and max
  int AddTexcoords(const std::vector<std::array<float, 2>>& uv);
  int AddIndices(const std::vector<uint32_t>& i);                 // SCALAR unsigned int
  // A mesh of one primitive; material -1 for none, mode 4 (TRIANGLES) unless given.
  int AddMesh(int positions, int indices, int material = -1, int mode = 4, int texcoords = -1);
  int AddMaterial(const nlohmann::json& material);
  int AddNode(const nlohmann::json& node);  // e.g. {{"mesh", 0}, {"translation", {0, 1, 0}}}
  // The scene's root nodes (scene 0).
  void SetRoots(const std::vector<int>& nodes);

  // dir/name.gltf with dir/name.bin beside it; returns the .gltf's path.
  std::string WriteGltf(const std::string& dir, const std::string& name) const;
  // dir/name.glb; returns its path.
  std::string WriteGlb(const std::string& dir, const std::string& name) const;

 private:
  nlohmann::json json_;
  std::string bin_;
};

}  // namespace pb::test
