// Writes the seed corpus of tests/fuzz/photon_file_fuzz.cpp into the directory given: valid photon files, with
// their CRC trailer cut off, for the scene that target reads them for, checked by reading each back (64 triangles, lights of 1 and 2 W per
// channel, seed 1). Written by WritePhotonFile itself, so the seeds follow the format when it changes.
// Usage: photon_file_seeds DIR (tools/fuzz.sh runs it).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <stdexcept>

#include "baker/options.h"
#include "baker/files/photon_file.h"

namespace {

// A block of light `light` covering photons [first, first + photons), holding `hits` records spread over the
// triangles; every photon ends absorbed but the first, which escapes.
void AddBlock(pb::PhotonStore& store, uint32_t light, uint64_t photons, uint32_t hits) {
  const uint64_t first = store.emitted[light];
  pb::HitBlock block;
  for (uint32_t i = 0; i < hits; ++i)
    block.emplace_back(pb::Rgb{0.5f, 0.25f, 1.0f}, pb::Vector3{0, 0, 1}, (i * 7) % 64, i % 2 == 0, 0.25f, 0.5f);
  pb::TraceStats stats;
  stats.emitted = photons;
  stats.hits = hits;
  stats.escaped = 1;
  stats.absorbed = photons - 1;
  stats.diffuseBounces = hits;
  stats.fluxEmitted = {double(photons), double(photons), double(photons)};
  stats.fluxAbsorbed = {double(photons - 1), double(photons - 1), double(photons - 1)};
  stats.fluxEscaped = {1, 1, 1};
  store.blocks.push_back(std::move(block));
  store.ranges.push_back({light, first, first + photons});
  store.blockStats.push_back(stats);
  store.emitted[light] = first + photons;
}

void WriteSeed(const std::filesystem::path& dir, const std::string& name, const pb::PhotonStore& store) {
  const std::string path = (dir / (name + ".photons")).string();
  pb::OutputFiles outputs;
  pb::WritePhotonFile(outputs, path, store, {.sceneHash = 0, .seed = 1, .maxBounces = pb::kDefaultMaxBounces});
  outputs.Commit();
  // The reader must take each seed whole, as the fuzz target reads it, or fuzzing starts from refusals.
  const pb::PhotonStore read = pb::ReadPhotonFile(path, {.sceneHash = 0, .seed = 1, .maxBounces = pb::kDefaultMaxBounces},
                                                  store.lightPower, 64);
  if (read.emitted != store.emitted) throw std::logic_error(name + " was not read back whole");
  std::ifstream in(path, std::ios::binary);
  std::string bytes{std::istreambuf_iterator<char>(in), {}};
  bytes.resize(bytes.size() - 4);  // the CRC, which the target recomputes
  std::ofstream(dir / name, std::ios::binary) << bytes;
  std::filesystem::remove(path);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: photon_file_seeds DIR\n";
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  pb::PhotonStore store;
  store.lightPower = {{1, 1, 1}, {2, 2, 2}};
  store.emitted = {0, 0};
  WriteSeed(dir, "empty", store);
  AddBlock(store, 0, 40, 3);
  AddBlock(store, 1, 20, 2);
  WriteSeed(dir, "one-block-each", store);
  store = {.lightPower = {{1, 1, 1}, {2, 2, 2}}, .emitted = {0, 0}};
  AddBlock(store, 0, pb::kBlockPhotons, 5);
  AddBlock(store, 0, 9, 1);
  AddBlock(store, 1, 3, 0);
  WriteSeed(dir, "full-then-partial", store);
  return 0;
}
