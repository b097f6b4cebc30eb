// libFuzzer target for the photon file reader (baker/files/photon_file.h). The input is a photon file without its
// 4-byte CRC-32 trailer: the target appends the right CRC, so that mutations reach the checks behind it (a CRC
// guards only against accidents; a hostile file carries a valid one). The scene it is read for has 64 triangles
// and two lights, of the power the seed corpus was written with, so the seeds are read in full. Seed corpus:
// written by tests/fuzz/photon_file_seeds.cpp. Run by tools/fuzz.sh.
#include <zlib.h>

#include "baker/options.h"
#include "baker/files/photon_file.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string file(pb::fuzz::Bytes(data, size));
  const uint32_t crc = uint32_t(crc32_z(crc32(0, nullptr, 0), data, size));
  file.append(reinterpret_cast<const char*>(&crc), sizeof crc);
  const std::string path = pb::fuzz::WriteInput("f.photons", file);
  const pb::PhotonOrigin origin{.sceneHash = 0, .seed = 1, .maxBounces = pb::kDefaultMaxBounces, .effects = 0};
  pb::fuzz::ReadOrRefuse([&] { pb::ReadPhotonFile(path, origin, {{1, 1, 1}, {2, 2, 2}}, 64); });
  return 0;
}
