#include "mesh/scene_file.h"

#include <sys/stat.h>

#include <cctype>
#include <cstring>
#include <fstream>

#include "mesh/gltf_loader.h"
#include "mesh/obj_loader.h"

namespace pb {

namespace {

bool EndsWith(const std::string& s, const char* suffix) {
  const size_t n = std::strlen(suffix);
  if (s.size() < n) return false;
  for (size_t i = 0; i < n; ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - n + i])) != suffix[i]) return false;
  return true;
}

bool IsRegularFile(const std::string& path) {
  struct stat s{};
  return stat(path.c_str(), &s) == 0 && S_ISREG(s.st_mode);
}

}  // namespace

bool HasGltfExtension(const std::string& path) { return EndsWith(path, ".gltf") || EndsWith(path, ".glb"); }
bool IsBinaryGltfPath(const std::string& path) { return EndsWith(path, ".glb"); }

bool IsGltfFile(const std::string& path) {
  if (HasGltfExtension(path)) return true;
  if (!IsRegularFile(path)) return false;  // never open a FIFO to sniff it
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  return in.read(magic, 4) && std::memcmp(magic, "glTF", 4) == 0;
}

LoadedScene LoadScene(const std::string& path, const LoadOptions& options) {
  return IsGltfFile(path) ? LoadGltf(path, options) : LoadObj(path, options);
}

}  // namespace pb
