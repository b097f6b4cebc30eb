// libFuzzer target for the PNG texture reader (mesh/texture.h). The input is a PNG file. Seed corpus:
// tests/fuzz/corpus/png. Run by tools/fuzz.sh.
#include "mesh/texture.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = pb::fuzz::WriteInput("f.png", pb::fuzz::Bytes(data, size));
  pb::fuzz::ReadOrRefuse([&] { pb::LoadPngTexture(path); });
  return 0;
}
