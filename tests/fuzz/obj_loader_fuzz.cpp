// libFuzzer target for the OBJ/MTL loader (mesh/obj_loader.h). The input is an OBJ file, optionally followed by
// a line "%%MTL%%" and the text of the material library that the OBJ may load as "f.mtl". A well-formed input
// loads; anything else must be refused with an InputError. Any other exception, a crash, a leak or undefined
// behaviour is a bug. Run it with tools/fuzz-loader.sh; the seed corpus is tests/fuzz/corpus.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "mesh/errors.h"
#include "mesh/obj_loader.h"

namespace {

const std::string& Directory() {
  static const std::string dir = [] {
    const auto d = std::filesystem::temp_directory_path() / ("photonbake-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d.string();
  }();
  return dir;
}

void Write(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::string separator = "\n%%MTL%%\n";
  const size_t split = input.find(separator);
  Write(Directory() + "/f.obj", input.substr(0, split));
  Write(Directory() + "/f.mtl", split == std::string::npos ? std::string() : input.substr(split + separator.size()));
  try {
    pb::LoadObj(Directory() + "/f.obj");
  } catch (const pb::InputError&) {
    // Refused with a message naming file:line: the expected outcome for malformed input.
  }
  return 0;
}
