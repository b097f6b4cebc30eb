// A glTF 2.0 file (.gltf JSON or .glb binary) as tinygltf reads it, and no more than that: only regular files, their
// names taken as they are (tinygltf's default expands them with wordexp()), nothing written, the images kept as
// their encoded bytes (mesh/texture.h decodes them, mesh/gltf_loader.h turns the model into a scene). Refused with
// an InputError naming the file: JSON nested deeper than kMaxGltfNesting levels, at the line where it goes deeper
// (tinygltf converts it recursively: 100,000 nested arrays in `extras` overflowed the stack), compressed geometry
// by its extension's name, and whatever tinygltf cannot read, with its first reason.
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace pb {

inline constexpr size_t kMaxGltfNesting = 1000;

struct GltfFile {
  tinygltf::Model model;
  std::map<int, std::string> imageBytes;  // by image index
  std::vector<std::string> warnings;      // tinygltf's, a line each
};
GltfFile ReadGltfFile(const std::string& path);

// Compressed geometry: its accessors hold no data of their own, so a file that uses one is refused by its name
// (whether or not it lists it as required), not by the first accessor that reads nothing.
inline constexpr const char* kGltfCompressions[] = {"KHR_draco_mesh_compression", "EXT_meshopt_compression"};
[[noreturn]] void RefuseGltfCompression(const std::string& path, const std::string& extension);

}  // namespace pb
