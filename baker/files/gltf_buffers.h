// glTF 2.0 files as the glTF writers build them (baker/5_write_gltf.h, tools/scene-to-gltf.cpp), through
// tinygltf's model types: one buffer, each array appended as its own 4-byte aligned buffer view with an accessor;
// the file staged as an output (baker/files/atomic_file.h), binary for .glb, else JSON with the buffer as a data URI.
#pragma once

#include <tiny_gltf.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "baker/files/atomic_file.h"

namespace pb {

class GltfBufferWriter {
 public:
  // Appends to the model's first buffer, which it adds if there is none.
  explicit GltfBufferWriter(tinygltf::Model& model);
  // float VEC3 values (with their min and max when `bounds`, as POSITION needs); returns the accessor's index.
  int Vec3(const std::vector<std::array<float, 3>>& values, bool bounds);
  // float VEC2 and VEC4 values.
  int Vec2(const std::vector<std::array<float, 2>>& values);
  int Vec4(const std::vector<std::array<float, 4>>& values);
  // Triangles as unsigned int indices.
  int Indices(const std::vector<std::array<uint32_t, 3>>& faces);

 private:
  int Append(const void* bytes, size_t size, int target, int componentType, size_t count, int type);
  tinygltf::Model& model_;
};

// Stages `model` as `path` in `outputs`, its names made valid UTF-8 (ValidUtf8: a Latin-1 name from a Windows
// exporter would make the JSON writer throw after the bake).
void WriteGltfModel(OutputFiles& outputs, const std::string& path, tinygltf::Model model);

}  // namespace pb
