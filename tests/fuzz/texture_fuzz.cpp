// libFuzzer target for the texture readers (mesh/texture.h): libpng for PNG, stb_image for JPEG, TGA, BMP and
// the rest. The input is an image file of any of those formats. Seed corpus: tests/fuzz/corpus/texture. Run by
// tools/fuzz.sh.
#include "mesh/texture.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = pb::fuzz::WriteInput("f.img", pb::fuzz::Bytes(data, size));
  pb::fuzz::ReadOrRefuse([&] { pb::LoadTexture(path); });
  return 0;
}
