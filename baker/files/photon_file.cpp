#include "baker/files/photon_file.h"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <type_traits>

#include "baker/files/atomic_file.h"
#include "mesh/errors.h"
#include "mesh/input_file.h"

namespace pb {
namespace {

static_assert(std::endian::native == std::endian::little, "the photon file is little-endian, as in memory");
static_assert(std::is_trivially_copyable_v<PhotonHit> && sizeof(PhotonHit) == 28, "records are the 28-byte hits");

constexpr char kMagic[8] = {'P', 'B', 'P', 'H', 'O', 'T', 'O', 'N'};
constexpr uint32_t kVersion = 1;
constexpr uint64_t kHeaderBytes = 8 + 4 + 4 + 4 + 8 + 4 + 4 + 4 + 4;  // magic .. block count
constexpr uint64_t kLightBytes = 3 * 4 + 8;
constexpr uint64_t kStatsBytes = 11 * 8 + 12 * 8;
constexpr uint64_t kBlockBytes = 4 + 3 * 8 + kStatsBytes;
constexpr uint64_t kTrailerBytes = 4;

// Every field of a block's stats, in file order: the counts, then the four RGB sums.
template <typename Stats, typename F>
void VisitStats(Stats& s, F&& field) {
  for (auto* count : {&s.emitted, &s.hits, &s.absorbed, &s.escaped, &s.forbidden, &s.truncated, &s.diffuseBounces,
                      &s.mirrorReflections, &s.fresnelReflections, &s.refractions, &s.causticHits})
    field(*count);
  for (auto* sum : {&s.fluxEmitted, &s.fluxAbsorbed, &s.fluxEscaped, &s.fluxForbidden}) {
    field(sum->r);
    field(sum->g);
    field(sum->b);
  }
}

// zlib's crc32 restarts on a null buffer (an empty vector's data()), so empty spans are skipped.
uLong Crc(uLong crc, const void* bytes, size_t count) {
  return count == 0 ? crc : crc32_z(crc, static_cast<const Bytef*>(bytes), count);
}

class Writer {
 public:
  explicit Writer(std::ostream& out) : out_(out) {}
  void Bytes(const void* bytes, size_t count) {
    crc_ = Crc(crc_, bytes, count);
    out_.write(static_cast<const char*>(bytes), std::streamsize(count));
  }
  template <typename T>
  void Put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    Bytes(&value, sizeof value);
  }
  void PutCrc() {
    const uint32_t crc = uint32_t(crc_);
    out_.write(reinterpret_cast<const char*>(&crc), sizeof crc);
  }

 private:
  std::ostream& out_;
  uLong crc_ = crc32(0, nullptr, 0);
};

class Reader {
 public:
  Reader(std::istream& in, const std::string& path) : in_(in), path_(path) {}
  void Bytes(void* bytes, size_t count) {
    if (!in_.read(static_cast<char*>(bytes), std::streamsize(count)))
      throw InputError(path_, 0, "photon file is truncated");
    crc_ = Crc(crc_, bytes, count);
  }
  template <typename T>
  T Get() {
    T value;
    Bytes(&value, sizeof value);
    return value;
  }
  void CheckCrc() {
    uint32_t stored = 0;
    if (!in_.read(reinterpret_cast<char*>(&stored), sizeof stored))
      throw InputError(path_, 0, "photon file is truncated");
    if (stored != uint32_t(crc_))
      throw InputError(path_, 0, fmt::format("photon file is corrupt: its CRC-32 is {:08x}, its contents give {:08x}",
                                             stored, uint32_t(crc_)));
  }

 private:
  std::istream& in_;
  const std::string& path_;
  uLong crc_ = crc32(0, nullptr, 0);
};

struct Header {
  PhotonOrigin origin;
  uint32_t lights = 0, blocks = 0;
};

void WriteHeader(Writer& w, const PhotonOrigin& o, const PhotonStore& store) {
  w.Bytes(kMagic, sizeof kMagic);
  w.Put(kVersion);
  w.Put(uint32_t(sizeof(PhotonHit)));
  w.Put(o.sceneHash);
  w.Put(o.seed);
  w.Put(o.maxBounces);
  w.Put(o.effects);
  w.Put(uint32_t(store.emitted.size()));
  w.Put(uint32_t(store.blocks.size()));
}

Header ReadHeader(Reader& r, const std::string& path) {
  char magic[sizeof kMagic];
  r.Bytes(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    throw InputError(path, 0, "not a photon file (it does not start with PBPHOTON)");
  if (const uint32_t version = r.Get<uint32_t>(); version != kVersion)
    throw InputError(path, 0, fmt::format("photon file version {} is not the version {} this bake reads", version, kVersion));
  if (const uint32_t record = r.Get<uint32_t>(); record != sizeof(PhotonHit))
    throw InputError(path, 0, fmt::format("photon records of {} bytes, not {}", record, sizeof(PhotonHit)));
  Header h;
  h.origin.sceneHash = r.Get<uint32_t>();
  h.origin.seed = r.Get<uint64_t>();
  h.origin.maxBounces = r.Get<uint32_t>();
  h.origin.effects = r.Get<uint32_t>();
  h.lights = r.Get<uint32_t>();
  h.blocks = r.Get<uint32_t>();
  return h;
}

[[noreturn]] void Truncated(const std::string& path, uint64_t actual, uint64_t expected) {
  throw InputError(path, 0, fmt::format("photon file is truncated: {} bytes of the {} its header describes", actual,
                                        expected));
}

// The bytes up to the first record, from the header's counts; checked against the file's length before the
// light and block tables are allocated. Counts are 32-bit, so nothing here overflows.
uint64_t TableBytes(const std::string& path, const Header& h, uint64_t actual) {
  const uint64_t bytes = kHeaderBytes + uint64_t(h.lights) * kLightBytes + uint64_t(h.blocks) * kBlockBytes;
  if (bytes + kTrailerBytes > actual) Truncated(path, actual, bytes + kTrailerBytes);
  return bytes;
}

// Refuses a file whose length is not what its header promises, before the records are read. The hit counts come
// from the file, so their sum is bounded as it goes, never allowed to wrap.
void CheckLength(const std::string& path, uint64_t tableBytes, const std::vector<uint64_t>& blockHits, uint64_t actual) {
  uint64_t expected = tableBytes + kTrailerBytes;
  for (uint64_t n : blockHits) {
    if (n > (actual - std::min(actual, expected)) / sizeof(PhotonHit))
      throw InputError(path, 0, fmt::format("photon file is truncated: its blocks declare more records than its {} "
                                            "bytes hold", actual));
    expected += n * sizeof(PhotonHit);
  }
  if (actual < expected) Truncated(path, actual, expected);
  if (actual > expected)
    throw InputError(path, 0, fmt::format("photon file has {} bytes past the {} its header describes", actual - expected, expected));
}

[[noreturn]] void Corrupt(const std::string& path, const std::string& what) {
  throw InputError(path, 0, "photon file is corrupt: " + what);
}

// A block's statistics, in attenuation units: its photons each end once (absorbed, escaped, forbidden or
// truncated), its hits are its records, and its flux sums are finite and non-negative.
void CheckBlockStats(const std::string& path, const BlockRange& range, uint64_t hits, const TraceStats& s) {
  const uint64_t photons = range.end - range.first;
  if (s.emitted != photons || s.hits != hits)
    Corrupt(path, fmt::format("a block of {} photons and {} hits counts {} and {}", photons, hits, s.emitted, s.hits));
  const uint64_t ends[] = {s.absorbed, s.escaped, s.forbidden, s.truncated};
  uint64_t ended = 0;
  for (uint64_t e : ends) ended = e > photons - std::min(photons, ended) ? ~uint64_t(0) : ended + e;
  if (ended != photons) Corrupt(path, "a block's photons do not each end once");
  // Each photon's flux sums to at most kMostPhotonAttenuation per channel in each tally.
  const double most = double(photons) * kMostPhotonAttenuation;
  bool finite = true;
  for (const RgbSum* sum : {&s.fluxEmitted, &s.fluxAbsorbed, &s.fluxEscaped, &s.fluxForbidden})
    for (double c : {sum->r, sum->g, sum->b}) finite = finite && c >= 0 && c <= most;  // false for NaN
  if (!finite) Corrupt(path, "a block's flux sums are not finite and non-negative, or more than its photons carry");
}

// A record names a triangle of this scene, with an attenuation the tracer can give (in [0, kMostPhotonAttenuation]
// per channel) and barycentrics inside it (to float rounding).
bool ValidHit(const PhotonHit& hit, size_t triangles) {
  constexpr float kSlack = 1e-4f;
  const Rgb& a = hit.attenuation;
  const auto traceable = [](float c) { return c >= 0 && c <= kMostPhotonAttenuation; };  // false for NaN
  const bool attenuation = traceable(a.r) && traceable(a.g) && traceable(a.b);
  const bool inside = hit.b1 >= -kSlack && hit.b2 >= -kSlack && hit.b1 + hit.b2 <= 1 + kSlack;  // false for NaN
  return hit.Triangle() < triangles && attenuation && inside;
}

void CheckHits(const std::string& path, const PhotonStore& store, size_t triangles) {
  for (const HitBlock& block : store.blocks)
    for (const PhotonHit& hit : block)
      if (!ValidHit(hit, triangles))
        Corrupt(path, fmt::format("a hit on triangle {} of {}, attenuation ({}, {}, {}), barycentrics ({}, {})",
                                  hit.Triangle(), triangles, hit.attenuation.r, hit.attenuation.g, hit.attenuation.b,
                                  hit.b1, hit.b2));
}

void CheckOrigin(const std::string& path, const PhotonOrigin& file, const PhotonOrigin& bake) {
  const auto refuse = [&](const std::string& what) {
    throw InputError(path, 0, "cannot resume: " + what + "; bake again without --resume, or with the original inputs");
  };
  if (file.sceneHash != bake.sceneHash)
    refuse(fmt::format("the photons were traced in a different scene (scene hash {:08x}, this scene {:08x})",
                       file.sceneHash, bake.sceneHash));
  if (file.seed != bake.seed) refuse(fmt::format("the photons were traced with --seed {}, not {}", file.seed, bake.seed));
  if (file.maxBounces != bake.maxBounces)
    refuse(fmt::format("the photons were traced with at most {} bounces, not {}", file.maxBounces, bake.maxBounces));
  const uint32_t direct = 1u << uint32_t(Effect::kDirect);
  if ((file.effects ^ bake.effects) == direct)
    refuse(fmt::format("the photons were traced with --direct {}, not {}", file.effects & direct ? "photons" : "sampled",
                       bake.effects & direct ? "photons" : "sampled"));
  if (file.effects != bake.effects)
    refuse(fmt::format("the photons were traced with other effects (--effects; bits {:05b}, this bake {:05b})",
                       file.effects, bake.effects));
}

// Each light's blocks cover photons [0, N_l) of its stream, in order, in aligned blocks all full but the last: a
// file that passed its CRC but not this was not written by WritePhotonFile. (A short block before a full one
// would let a resume skip photons of the stream.)
void CheckBlocks(const std::string& path, const PhotonStore& store) {
  std::vector<uint64_t> next(store.emitted.size(), 0);
  uint32_t previousLight = 0;
  for (const BlockRange& r : store.ranges) {
    if (r.light >= next.size() || r.light < previousLight || r.first != next[r.light] || r.end <= r.first ||
        r.end - r.first > kBlockPhotons || r.first % kBlockPhotons != 0)
      Corrupt(path, "its blocks do not cover each light's photons in order, in aligned blocks");
    next[r.light] = r.end;
    previousLight = r.light;
  }
  if (next != store.emitted) Corrupt(path, "its blocks and light counts disagree");
}

template <typename T>
void HashVector(uLong& crc, const std::vector<T>& values) {
  static_assert(std::is_trivially_copyable_v<T>);
  crc = Crc(crc, values.data(), values.size() * sizeof(T));
}

// What a light that is not a surface sends where: its kind, strength, place, aim, cone, sky and the tables of
// its profile or image (not its name or where it was declared).
void HashLight(uLong& crc, const AnalyticLight& light) {
  const float values[] = {float(light.kind), light.intensity.r, light.intensity.g, light.intensity.b, light.position.x,
                          light.position.y, light.position.z, light.direction.x, light.direction.y, light.direction.z,
                          light.cosInner, light.cosOuter, light.up.x, light.up.y, light.up.z, float(light.wholeSphere),
                          light.c0.x, light.c0.y, light.c0.z};
  crc = Crc(crc, values, sizeof values);
  if (light.profile) {
    HashVector(crc, light.profile->VerticalAngles());
    HashVector(crc, light.profile->HorizontalAngles());
    HashVector(crc, light.profile->Candela());
  }
  if (light.image) HashVector(crc, light.image->texels);
}

}  // namespace

uint32_t SceneHash(const Scene& scene) {
  uLong crc = crc32(0, nullptr, 0);
  HashVector(crc, scene.positions);
  crc = Crc(crc, scene.origin.data(), sizeof scene.origin);
  for (const Triangle& t : scene.triangles) {
    crc = Crc(crc, t.v.data(), sizeof t.v);
    crc = Crc(crc, t.vt.data(), sizeof t.vt);
    crc = Crc(crc, &t.material, sizeof t.material);
  }
  for (const Material& m : scene.materials) {
    const float values[] = {float(m.kind), m.albedo.r, m.albedo.g, m.albedo.b, m.emission.r, m.emission.g, m.emission.b,
                            m.specular.r, m.specular.g, m.specular.b, m.transmittance.r, m.transmittance.g,
                            m.transmittance.b, m.ior, float(m.albedoTexture)};
    crc = Crc(crc, values, sizeof values);
    if (m.HasTextureTransform()) {  // only then, so that scenes without one keep the hash they had before it
      const float transform[] = {m.textureScale.u, m.textureScale.v, m.textureOffset.u, m.textureOffset.v,
                                 float(m.textureClamp)};
      crc = Crc(crc, transform, sizeof transform);
    }
  }
  HashVector(crc, scene.texcoords);
  for (const Texture& t : scene.textures) HashVector(crc, t.texels);
  for (const AnalyticLight& light : scene.analyticLights) HashLight(crc, light);
  for (const Portal& p : scene.portals) {
    const float corners[] = {p.origin.x, p.origin.y, p.origin.z, p.u.x, p.u.y, p.u.z, p.v.x, p.v.y, p.v.z};
    crc = Crc(crc, corners, sizeof corners);
  }
  return uint32_t(crc);
}

uint32_t SimulatedEffects(const TransportPlan& plan) {
  uint32_t bits = 0;
  for (Effect e : kAllEffects)
    if (plan.On(e)) bits |= 1u << uint32_t(e);
  return bits;
}

void WritePhotonFile(OutputFiles& outputs, const std::string& path, const PhotonStore& store, const PhotonOrigin& origin) {
  outputs.Write(path, [&](std::ostream& out) {
    Writer w(out);
    WriteHeader(w, origin, store);
    for (size_t l = 0; l < store.emitted.size(); ++l) {
      for (float c : {store.lightPower[l].r, store.lightPower[l].g, store.lightPower[l].b}) w.Put(c);
      w.Put(store.emitted[l]);
    }
    for (size_t b = 0; b < store.blocks.size(); ++b) {
      w.Put(store.ranges[b].light);
      w.Put(store.ranges[b].first);
      w.Put(store.ranges[b].end);
      w.Put(uint64_t(store.blocks[b].size()));
      VisitStats(store.blockStats[b], [&](auto value) { w.Put(value); });
    }
    for (const HitBlock& block : store.blocks) w.Bytes(block.data(), block.size() * sizeof(PhotonHit));
    w.PutCrc();
  });
}

PhotonStore ReadPhotonFile(const std::string& path, const PhotonOrigin& expected, const std::vector<Rgb>& lightPower,
                           size_t triangles) {
  const uint64_t actual = RequireRegularFile(path, "photon file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open photon file: " + std::string(std::strerror(errno)));
  Reader r(in, path);
  const Header h = ReadHeader(r, path);
  const uint64_t tableBytes = TableBytes(path, h, actual);
  PhotonStore store;
  store.lightPower.resize(h.lights);
  store.emitted.resize(h.lights);
  for (uint32_t l = 0; l < h.lights; ++l) {
    store.lightPower[l] = {r.Get<float>(), r.Get<float>(), r.Get<float>()};
    store.emitted[l] = r.Get<uint64_t>();
  }
  std::vector<uint64_t> blockHits(h.blocks);
  store.ranges.resize(h.blocks);
  store.blockStats.resize(h.blocks);
  for (uint32_t b = 0; b < h.blocks; ++b) {
    store.ranges[b] = {r.Get<uint32_t>(), r.Get<uint64_t>(), r.Get<uint64_t>()};
    blockHits[b] = r.Get<uint64_t>();
    VisitStats(store.blockStats[b], [&](auto& value) { value = r.Get<std::remove_reference_t<decltype(value)>>(); });
  }
  CheckLength(path, tableBytes, blockHits, actual);
  for (uint32_t b = 0; b < h.blocks; ++b) {
    store.blocks.emplace_back(blockHits[b]);
    r.Bytes(store.blocks.back().data(), blockHits[b] * sizeof(PhotonHit));
  }
  r.CheckCrc();
  CheckBlocks(path, store);
  for (uint32_t b = 0; b < h.blocks; ++b) CheckBlockStats(path, store.ranges[b], blockHits[b], store.blockStats[b]);
  CheckHits(path, store, triangles);
  CheckOrigin(path, h.origin, expected);
  if (store.lightPower != lightPower)
    throw InputError(path, 0, fmt::format("cannot resume: the photon file has {} lights, or lights of other power, "
                                          "than this scene's {}", h.lights, lightPower.size()));
  store.Summarise();
  return store;
}

}  // namespace pb
