// libFuzzer target for the camera file reader (mesh/camera.h). The input is a camera JSON file. Seed corpus:
// tests/fuzz/corpus/camera. Run by tools/fuzz.sh.
#include "mesh/camera.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = pb::fuzz::WriteInput("f.camera.json", pb::fuzz::Bytes(data, size));
  pb::fuzz::ReadOrRefuse([&] { pb::LoadCamera(path); });
  return 0;
}
