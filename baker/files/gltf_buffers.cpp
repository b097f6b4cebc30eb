#include "baker/files/gltf_buffers.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "baker/files/json_file.h"
#include "mesh/errors.h"
#include "mesh/scene_file.h"

namespace pb {

namespace tg = tinygltf;

GltfBufferWriter::GltfBufferWriter(tg::Model& model) : model_(model) {
  if (model_.buffers.empty()) model_.buffers.emplace_back();
}

int GltfBufferWriter::Vec3(const std::vector<std::array<float, 3>>& values, bool bounds) {
  const int a = Append(values.data(), values.size() * sizeof(values[0]), TINYGLTF_TARGET_ARRAY_BUFFER,
                       TINYGLTF_COMPONENT_TYPE_FLOAT, values.size(), TINYGLTF_TYPE_VEC3);
  if (bounds) {
    std::vector<double> lo(3, INFINITY), hi(3, -INFINITY);
    for (const auto& v : values)
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], double(v[k])), hi[k] = std::max(hi[k], double(v[k]));
    model_.accessors[size_t(a)].minValues = lo;
    model_.accessors[size_t(a)].maxValues = hi;
  }
  return a;
}

int GltfBufferWriter::Vec2(const std::vector<std::array<float, 2>>& values) {
  return Append(values.data(), values.size() * sizeof(values[0]), TINYGLTF_TARGET_ARRAY_BUFFER,
                TINYGLTF_COMPONENT_TYPE_FLOAT, values.size(), TINYGLTF_TYPE_VEC2);
}

int GltfBufferWriter::Vec4(const std::vector<std::array<float, 4>>& values) {
  return Append(values.data(), values.size() * sizeof(values[0]), TINYGLTF_TARGET_ARRAY_BUFFER,
                TINYGLTF_COMPONENT_TYPE_FLOAT, values.size(), TINYGLTF_TYPE_VEC4);
}

int GltfBufferWriter::Indices(const std::vector<std::array<uint32_t, 3>>& faces) {
  return Append(faces.data(), faces.size() * sizeof(faces[0]), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER,
                TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, faces.size() * 3, TINYGLTF_TYPE_SCALAR);
}

int GltfBufferWriter::Append(const void* bytes, size_t size, int target, int componentType, size_t count, int type) {
  std::vector<unsigned char>& data = model_.buffers[0].data;
  tg::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = size;
  view.target = target;
  const auto* b = static_cast<const unsigned char*>(bytes);
  data.insert(data.end(), b, b + size);  // every element is 4-byte, so every view stays 4-byte aligned
  model_.bufferViews.push_back(view);
  tg::Accessor accessor;
  accessor.bufferView = int(model_.bufferViews.size() - 1);
  accessor.componentType = componentType;
  accessor.count = count;
  accessor.type = type;
  model_.accessors.push_back(accessor);
  return int(model_.accessors.size() - 1);
}

void WriteGltfModel(OutputFiles& outputs, const std::string& path, tg::Model model) {
  const auto valid = [](auto& named) {
    for (auto& element : named) element.name = ValidUtf8(element.name);
  };
  valid(model.materials), valid(model.meshes), valid(model.nodes), valid(model.scenes), valid(model.lights);
  valid(model.images), valid(model.textures), valid(model.cameras);
  const bool binary = IsBinaryGltfPath(path);
  outputs.Write(path, [&](std::ostream& out) {
    tg::TinyGLTF writer;
    std::ostringstream text;
    if (!writer.WriteGltfSceneToStream(&model, text, !binary, binary))
      throw InputError(path, 0, "tinygltf could not write the glTF file");
    out << text.str();
  });
}

}  // namespace pb
