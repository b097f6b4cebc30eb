// libFuzzer target for the OBJ/MTL loader (mesh/obj_loader.h), with the PNG texture reader it calls. The input
// is an OBJ file, optionally followed by a line "%%MTL%%" and the text of the material library that the OBJ may
// load as "f.mtl". Seed corpus: tests/fuzz/corpus/obj_loader. Run by tools/fuzz.sh.
#include "mesh/obj_loader.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view input = pb::fuzz::Bytes(data, size);
  const std::string_view separator = "\n%%MTL%%\n";
  const size_t split = input.find(separator);
  const std::string obj = pb::fuzz::WriteInput("f.obj", input.substr(0, split));
  pb::fuzz::WriteInput("f.mtl", split == std::string_view::npos ? std::string_view() : input.substr(split + separator.size()));
  pb::fuzz::ReadOrRefuse([&] { pb::LoadObj(obj); });
  return 0;
}
