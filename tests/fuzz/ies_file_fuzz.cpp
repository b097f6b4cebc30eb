// libFuzzer target for the IES LM-63 reader (mesh/ies_file.h). The input is an .ies file; what it reads must also
// make a profile whose intensity and flux are finite and sampling-ready. Seed corpus: tests/fuzz/corpus/ies_file.
// Run by tools/fuzz.sh.
#include <cmath>

#include "mesh/errors.h"
#include "mesh/ies_file.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = pb::fuzz::WriteInput("f.ies", pb::fuzz::Bytes(data, size));
  pb::fuzz::ReadOrRefuse([&] {
    const pb::IntensityProfile profile = pb::LoadIesFile(path);
    PB_CHECK(std::isfinite(profile.Flux()) && profile.Flux() >= 0, "a profile's flux is finite");
    PB_CHECK(std::isfinite(profile.Intensity(0.5, 1.0)), "a profile's intensity is finite");
  });
  return 0;
}
