#include "mesh/gltf_file.h"

#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstring>
#include <string_view>

#include "mesh/errors.h"
#include "mesh/input_file.h"
#include "mesh/json_input.h"

namespace pb {
namespace {

namespace tg = tinygltf;

bool RegularFileExists(const std::string& path, void*) {
  struct stat s{};
  return stat(path.c_str(), &s) == 0 && S_ISREG(s.st_mode);
}
// No expansion: tinygltf's default runs wordexp() on names from the file.
std::string SamePath(const std::string& path, void*) { return path; }
bool ReadWhole(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  try {
    const std::string bytes = ReadRegularFile(path, "glTF resource");
    out->assign(bytes.begin(), bytes.end());
    return true;
  } catch (const InputError& e) {
    if (err) *err += e.what();
    return false;
  }
}
bool NoWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "the glTF loader writes no file";
  return false;
}

// The images' encoded bytes, kept by tinygltf's image callback and decoded by mesh/texture.h afterwards.
using ImageBytes = std::map<int, std::string>;
bool KeepImageBytes(tg::Image*, const int index, std::string*, std::string*, int, int, const unsigned char* bytes,
                    int size, void* user) {
  (*static_cast<ImageBytes*>(user))[index].assign(reinterpret_cast<const char*>(bytes), size_t(std::max(size, 0)));
  return true;
}

std::string Folder(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

bool IsBinary(const std::string& bytes) { return bytes.rfind("glTF", 0) == 0; }

// The JSON (a .glb's first chunk), refused past kMaxGltfNesting levels.
void RefuseDeepNesting(const std::string& path, const std::string& bytes) {
  std::string_view json = bytes;
  if (IsBinary(bytes) && bytes.size() >= 20) {
    uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4);  // the first chunk's length, little-endian as the file's byte order
    json = json.substr(20, length);
  }
  if (const int line = LineNestedDeeperThan(json, kMaxGltfNesting))
    throw InputError(path, line, fmt::format("the JSON nests arrays and objects deeper than {} levels", kMaxGltfNesting));
}

std::vector<std::string> SplitLines(const std::string& text) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = std::min(text.find('\n', start), text.size());
    if (end > start) lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

}  // namespace

void RefuseGltfCompression(const std::string& path, const std::string& extension) {
  throw InputError(path, 0, "the file uses extension '" + extension + "' (compressed geometry), which photonbake "
                            "does not read; export it without compression");
}

GltfFile ReadGltfFile(const std::string& path) {
  const std::string bytes = ReadRegularFile(path, "scene file");
  RefuseDeepNesting(path, bytes);
  GltfFile file;
  tg::TinyGLTF gltf;
  gltf.SetFsCallbacks({&RegularFileExists, &SamePath, &ReadWhole, &NoWrite, nullptr});
  gltf.SetImageLoader(&KeepImageBytes, &file.imageBytes);
  std::string err, warn;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const bool ok = IsBinary(bytes)
                      ? gltf.LoadBinaryFromMemory(&file.model, &err, &warn, data, unsigned(bytes.size()), Folder(path))
                      : gltf.LoadASCIIFromString(&file.model, &err, &warn, bytes.data(), unsigned(bytes.size()),
                                                 Folder(path));
  file.warnings = SplitLines(warn);
  if (!ok) {
    for (const char* compression : kGltfCompressions)  // tinygltf may fail first
      if (bytes.find(compression) != std::string::npos) RefuseGltfCompression(path, compression);
    const std::vector<std::string> lines = SplitLines(err);
    throw InputError(path, 0, std::string("not a glTF 2.0 file that can be read: ") +
                                  (lines.empty() ? "tinygltf gave no reason" : lines.front()));
  }
  return file;
}

}  // namespace pb
