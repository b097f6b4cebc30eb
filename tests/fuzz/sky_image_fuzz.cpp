// libFuzzer target for the sky image reader (mesh/sky_image.h): OpenEXR through Debian's OpenEXR, Radiance HDR
// through stb_image, then our checks (lat-long, size, finite non-negative texels). The input is an image file;
// what it reads must pass CheckSkyImage. Images are bounded to 2^20 pixels here (kMaxSkyPixels would let one input
// take 1.6 GB, past libFuzzer's memory limit). Seed corpus: tests/fuzz/corpus/sky_image. Run by tools/fuzz.sh.
#include "mesh/errors.h"
#include "mesh/sky_image.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = pb::fuzz::WriteInput("f.sky", pb::fuzz::Bytes(data, size));
  pb::fuzz::ReadOrRefuse([&] {
    const pb::SkyImage image = pb::LoadSkyImage(path, uint64_t(1) << 20);  // the reader's checks at a fuzzer's size
    pb::CheckSkyImage(image);  // what was read keeps the rules
    PB_CHECK_EQ(image.texels.size(), size_t(image.width) * size_t(image.height));
  });
  return 0;
}
