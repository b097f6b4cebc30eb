// libFuzzer target for the glTF 2.0 loader (mesh/gltf_loader.h), through tinygltf, with the image decoding it
// calls. The input is one file, a .glb or a .gltf whose buffers and images are data URIs (told apart by its first
// bytes). Seed corpus: tests/fuzz/corpus/gltf_loader. Run by tools/fuzz.sh.
#include "mesh/gltf_loader.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = pb::fuzz::WriteInput("f.gltf", pb::fuzz::Bytes(data, size));
  pb::fuzz::ReadOrRefuse([&] { pb::LoadGltf(path); });
  return 0;
}
