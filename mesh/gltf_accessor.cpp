#include "mesh/gltf_accessor.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "mesh/errors.h"

namespace pb::gltf {

namespace tg = tinygltf;

int ComponentBytes(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

Accessor::Accessor(const tg::Model& model, int index, int components, std::initializer_list<int> types,
                   const std::string& where, const std::string& file) {
  auto fail = [&](const std::string& what) { throw InputError(file, 0, where + ": " + what); };
  if (index < 0 || size_t(index) >= model.accessors.size())
    fail(fmt::format("accessor {} does not exist ({} accessors)", index, model.accessors.size()));
  const tg::Accessor& a = model.accessors[size_t(index)];
  const std::string self = fmt::format("/accessors/{}", index);
  if (a.sparse.isSparse) fail(self + " is sparse, which is not read");
  if (tg::GetNumComponentsInType(uint32_t(a.type)) != components)
    fail(fmt::format("{} has {} components where {} are needed", self, tg::GetNumComponentsInType(uint32_t(a.type)),
                     components));
  if (std::find(types.begin(), types.end(), a.componentType) == types.end())
    fail(fmt::format("{} has component type {}, which is not allowed here", self, a.componentType));
  type_ = a.componentType, components_ = components, normalized_ = a.normalized, count_ = a.count;
  const size_t element = size_t(ComponentBytes(type_)) * size_t(components);
  if (a.bufferView < 0) {  // all zeros (glTF 3.6.2.4); no buffer bounds its count, so a limit does
    if (a.count > kMaxZeroElements) fail(fmt::format("{} has no buffer view and {} elements", self, a.count));
    return;
  }
  if (size_t(a.bufferView) >= model.bufferViews.size())
    fail(fmt::format("{}: buffer view {} does not exist", self, a.bufferView));
  const tg::BufferView& view = model.bufferViews[size_t(a.bufferView)];
  const std::string viewPath = fmt::format("/bufferViews/{}", a.bufferView);
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
    fail(fmt::format("{}: buffer {} does not exist", viewPath, view.buffer));
  const std::vector<unsigned char>& buffer = model.buffers[size_t(view.buffer)].data;
  if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
    fail(fmt::format("{} (bytes {} to {}) lies beyond its buffer of {} bytes", viewPath, view.byteOffset,
                     view.byteOffset + view.byteLength, buffer.size()));
  stride_ = view.byteStride ? view.byteStride : element;
  if (stride_ < element) fail(fmt::format("{}: byteStride {} is less than an element's {} bytes", viewPath, stride_, element));
  const bool fits = a.count == 0 || (a.byteOffset <= view.byteLength &&
                                     (a.count - 1) <= (view.byteLength - a.byteOffset) / stride_ &&
                                     a.byteOffset + (a.count - 1) * stride_ + element <= view.byteLength);
  if (!fits) fail(fmt::format("{}: {} elements from byte {} do not fit in {} of {} bytes", self, a.count,
                              a.byteOffset, viewPath, view.byteLength));
  data_ = buffer.data() + view.byteOffset + a.byteOffset;
}

double Accessor::Get(size_t i, int k) const {
  if (!data_) return 0;
  const unsigned char* p = data_ + i * stride_ + size_t(k) * size_t(ComponentBytes(type_));
  switch (type_) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return Read<float>(p, 1);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return Read<uint8_t>(p, 255.0);
    case TINYGLTF_COMPONENT_TYPE_BYTE: return std::max(-1.0, Read<int8_t>(p, 127.0));
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return Read<uint16_t>(p, 65535.0);
    case TINYGLTF_COMPONENT_TYPE_SHORT: return std::max(-1.0, Read<int16_t>(p, 32767.0));
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return Read<uint32_t>(p, 4294967295.0);
    default: return Read<int32_t>(p, 2147483647.0);
  }
}

template <typename T>
double Accessor::Read(const unsigned char* p, double unit) const {
  T value;
  std::memcpy(&value, p, sizeof value);
  return normalized_ ? double(value) / unit : double(value);
}

}  // namespace pb::gltf
