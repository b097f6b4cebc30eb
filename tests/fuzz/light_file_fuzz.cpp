// libFuzzer target for the lights file reader (mesh/light_file.h). The input is a lights JSON file, read for an
// empty scene. Seed corpus: tests/fuzz/corpus/light_file. Run by tools/fuzz.sh.
#include "mesh/light_file.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = pb::fuzz::WriteInput("f.lights.json", pb::fuzz::Bytes(data, size));
  const pb::Scene scene;
  pb::fuzz::ReadOrRefuse([&] { pb::LoadLightsFile(path, scene); });
  return 0;
}
