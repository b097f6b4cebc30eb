#include "mesh/sky_image.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <numbers>
#include <optional>

#include "mesh/errors.h"
#include "mesh/input_file.h"
#include "mesh/memory_budget.h"

namespace pb {
namespace {

// What an image may hold: at most maxPixels texels, and within the memory beside what `memory` names.
struct Limits {
  uint64_t maxPixels = kMaxSkyPixels;
  SkyMemory memory;
};

void RequireSize(const std::string& path, int64_t width, int64_t height, const Limits& limits) {
  const uint64_t maxPixels = limits.maxPixels;
  const SkyMemory& memory = limits.memory;
  if (width <= 0 || height <= 0 || uint64_t(width) > maxPixels || uint64_t(width) * uint64_t(height) > maxPixels)
    throw InputError(path, 0, fmt::format("a sky image of {} x {} pixels: it must have between 1 and {} pixels",
                                          width, height, maxPixels));
  const std::string seen = memory.portals == 0 ? "" : fmt::format(" seen through {} portal{}", memory.portals,
                                                                  memory.portals == 1 ? "" : "s");
  RequireMemory(path, memory.held + SkyImageBytes(uint64_t(width) * uint64_t(height), memory.portals),
                fmt::format("a sky image of {} x {} pixels{}{}, with the tables its photons are drawn by,", width,
                            height, seen, memory.held > 0 ? " and the lights file's other sky images" : ""));
}

// How many bytes OpenEXR 3.1 reads for an attribute of `type` whose value starts at `value` and declares
// `size` bytes: it reads a known type by its own layout, not by the declared size, so a header whose sizes lie
// would have it read later attributes from other bytes than the ones walked here. Nothing for a value it would
// misread (a float declaring 0 bytes is read as 4: found by fuzz_sky_image, when 0 stood for a misread too).
std::optional<size_t> ExrValueBytes(const std::string& bytes, const std::string& type, size_t value, uint32_t size) {
  static const std::pair<const char*, uint32_t> kFixed[] = {
      {"box2i", 16}, {"box2f", 16}, {"compression", 1}, {"lineOrder", 1}, {"envmap", 1}, {"deepImageState", 1},
      {"float", 4}, {"int", 4}, {"double", 8}, {"rational", 8}, {"timecode", 8}, {"keycode", 28},
      {"chromaticities", 32}, {"tiledesc", 9}, {"v2i", 8}, {"v2f", 8}, {"v2d", 16}, {"v3i", 12}, {"v3f", 12},
      {"v3d", 24}, {"m33f", 36}, {"m33d", 72}, {"m44f", 64}, {"m44d", 128}};
  for (const auto& [name, fixed] : kFixed)
    if (type == name) return fixed == size ? std::optional<size_t>(size) : std::nullopt;
  const auto uint32At = [&](size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);  // little-endian, as EXR and this machine are
    return v;
  };
  const size_t end = value + size;  // within the file (checked by the caller)
  if (type == "chlist") {  // channels (name, 16 bytes) up to an empty name, read whatever the size says
    size_t at = value;
    for (;;) {
      const size_t nameEnd = bytes.find('\0', at);
      if (nameEnd == std::string::npos || nameEnd >= end || nameEnd - at > 255) return std::nullopt;
      if (nameEnd == at) return nameEnd + 1 == end ? std::optional<size_t>(size) : std::nullopt;
      at = nameEnd + 17;
    }
  }
  if (type == "stringvector") {  // strings, each after its length, up to the declared size
    for (size_t at = value; at < end; at += 4 + uint32At(at))
      if (end - at < 4 || uint32At(at) > end - at - 4) return std::nullopt;
    return size;
  }
  const auto whole = [&](bool reads) { return reads ? std::optional<size_t>(size) : std::nullopt; };
  if (type == "preview") return whole(size >= 8 && uint64_t(uint32At(value)) * uint32At(value + 4) * 4 == size - 8);
  if (type == "floatvector") return whole(size % 4 == 0);
  if (type == "idmanifest") return whole(size >= 8);
  return size;  // a string, or a type OpenEXR does not know (read as opaque bytes): the declared size
}

// The EXR header, walked before OpenEXR sees it (it allocates what an attribute's size field declares, so a
// hostile header could ask for gigabytes): one part, not deep; every attribute's name and type end within 31
// bytes (255 with the long-names flag) and its value within the file, and the value is as long as OpenEXR will
// read it (else it would read the next attribute from bytes not walked here: found by fuzz_sky_image); the data
// window within maxPixels.
void CheckExrHeader(const std::string& path, const std::string& bytes, const Limits& limits) {
  const auto fail = [&](const std::string& why) { throw InputError(path, 0, "cannot read the sky image as EXR: " + why); };
  const auto int32At = [&](size_t at) {
    int32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);  // little-endian, as EXR and this machine are
    return v;
  };
  if (bytes.size() < 8) fail("the file ends in its header");
  if (int32At(4) & (0x800 | 0x1000)) fail("a deep or multi-part EXR is not read as a sky image");
  const size_t maxName = (int32At(4) & 0x400) ? 255 : 31;
  bool window = false;
  for (size_t at = 8;;) {
    const size_t nameEnd = bytes.find('\0', at);
    if (nameEnd == std::string::npos || nameEnd - at > maxName) fail("an attribute's name does not end");
    if (nameEnd == at) break;  // the empty name ends the header
    const size_t typeEnd = bytes.find('\0', nameEnd + 1);
    if (typeEnd == std::string::npos || typeEnd - nameEnd - 1 > maxName || typeEnd + 5 > bytes.size()) fail("an attribute's type does not end");
    const int32_t size = int32At(typeEnd + 1);
    const size_t value = typeEnd + 5;
    if (size < 0 || uint64_t(size) > bytes.size() - value) fail("an attribute's value runs past the end of the file");
    const std::string type = bytes.substr(nameEnd + 1, typeEnd - nameEnd - 1);
    if (ExrValueBytes(bytes, type, value, uint32_t(size)) != size_t(size))
      fail(fmt::format("the attribute '{}' of type {} declares {} bytes, not what its type reads", bytes.substr(at, nameEnd - at), type, size));
    if (bytes.compare(at, nameEnd - at, "dataWindow") == 0 && type == "box2i") {
      const int64_t width = int64_t(int32At(value + 8)) - int32At(value) + 1, height = int64_t(int32At(value + 12)) - int32At(value + 4) + 1;
      RequireSize(path, width, height, limits);
      window = true;
    }
    at = value + size_t(size);
  }
  if (!window) fail("its header has no data window");
}

// R, G and B as float slices of `image`, or Y in all three for a luminance-only file.
SkyImage ReadExr(const std::string& path, const std::string& bytes, const Limits& limits) {
  CheckExrHeader(path, bytes, limits);
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const int64_t width = int64_t(window.max.x) - window.min.x + 1, height = int64_t(window.max.y) - window.min.y + 1;
    RequireSize(path, width, height, limits);
    SkyImage image{path, int(width), int(height), std::vector<Rgb>(size_t(width) * size_t(height))};
    const Imf::ChannelList& channels = file.header().channels();
    const bool rgb = channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B");
    if (!rgb && !channels.findChannel("Y"))
      throw InputError(path, 0, "a sky image needs R, G and B channels (or Y), and this EXR has neither");
    // The frame buffer addresses pixel (x, y) of the data window at base + x * xStride + y * yStride.
    char* base = reinterpret_cast<char*>(image.texels.data()) -
                 (int64_t(window.min.x) + int64_t(window.min.y) * width) * int64_t(sizeof(Rgb));
    Imf::FrameBuffer frame;
    for (size_t c = 0; c < 3; ++c)
      frame.insert(rgb ? (c == 0 ? "R" : c == 1 ? "G" : "B") : "Y",
                   Imf::Slice(Imf::FLOAT, base + c * sizeof(float), sizeof(Rgb), sizeof(Rgb) * size_t(width)));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return image;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path, 0, std::string("cannot read the sky image as EXR: ") + e.what());
  }
}

// Radiance RGBE (Ward, "Real Pixels", Graphics Gems II, 1991), read here rather than by stb_image, whose decoder
// loops forever on a run of length 0 (found by fuzz_sky_image): a "#?RADIANCE" or "#?RGBE" header of lines up to
// an empty one, the resolution "-Y H +X W" (top row first, the layout every writer uses), then each scanline
// either flat (4 bytes a pixel) or, for widths 8 to 32767, run-length encoded per channel after the bytes 2 2 W.
class RgbeReader {
 public:
  RgbeReader(const std::string& path, const std::string& bytes, const Limits& limits)
      : path_(path), bytes_(bytes), limits_(limits) {}

  SkyImage Read() {
    const std::string magic = Line();
    if (magic != "#?RADIANCE" && magic != "#?RGBE") Fail("not a Radiance HDR file: it must start with #?RADIANCE");
    for (std::string line = Line(); !line.empty(); line = Line())
      if (line.rfind("FORMAT=", 0) == 0 && line != "FORMAT=32-bit_rle_rgbe") Fail("only 32-bit_rle_rgbe is read, not " + line.substr(7));
    int height = 0, width = 0;
    char extra = 0;
    if (std::sscanf(Line().c_str(), "-Y %d +X %d%c", &height, &width, &extra) != 2)
      Fail("only the resolution layout '-Y H +X W' (top row first) is read");
    RequireSize(path_, width, height, limits_);
    SkyImage image{path_, width, height, std::vector<Rgb>(size_t(width) * size_t(height))};
    std::vector<uint8_t> rgbe(size_t(width) * 4);
    for (int y = 0; y < height; ++y) {
      Scanline(rgbe, width);
      for (int x = 0; x < width; ++x) image.texels[size_t(y) * size_t(width) + size_t(x)] = Decode(&rgbe[size_t(x) * 4]);
    }
    return image;
  }

 private:
  [[noreturn]] void Fail(const std::string& message) const { throw InputError(path_, 0, message); }

  std::string Line() {
    const size_t end = bytes_.find('\n', at_);
    if (end == std::string::npos) Fail("the header ends before its resolution line");
    std::string line = bytes_.substr(at_, end - at_);
    at_ = end + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
  }

  uint8_t Byte() {
    if (at_ >= bytes_.size()) Fail("the pixels end early");
    return uint8_t(bytes_[at_++]);
  }

  // One scanline into rgbe (R, G, B, E per pixel).
  void Scanline(std::vector<uint8_t>& rgbe, int width) {
    const bool encoded = width >= 8 && width <= 0x7fff && at_ + 4 <= bytes_.size() && uint8_t(bytes_[at_]) == 2 &&
                         uint8_t(bytes_[at_ + 1]) == 2 && (uint8_t(bytes_[at_ + 2]) & 0x80) == 0;
    if (!encoded) {
      for (uint8_t& b : rgbe) b = Byte();
      return;
    }
    at_ += 2;
    if (((int(Byte()) << 8) | Byte()) != width) Fail("a run-length scanline's width is not the image's");
    for (int c = 0; c < 4; ++c) {
      for (int x = 0; x < width;) {
        const int count = Byte();
        const bool run = count > 128;
        const int n = run ? count - 128 : count;
        if (n == 0 || x + n > width) Fail("a run-length scanline's run is empty or overruns its width");
        const uint8_t value = run ? Byte() : 0;
        for (int k = 0; k < n; ++k, ++x) rgbe[size_t(x) * 4 + size_t(c)] = run ? value : Byte();
      }
    }
  }

  static Rgb Decode(const uint8_t* p) {
    if (p[3] == 0) return {};
    const float f = std::ldexp(1.0f, int(p[3]) - (128 + 8));
    return {float(p[0]) * f, float(p[1]) * f, float(p[2]) * f};
  }

  const std::string& path_;
  const std::string& bytes_;
  Limits limits_;
  size_t at_ = 0;
};

}  // namespace

int SkyImage::RowOf(double theta) const {
  return std::clamp(int(theta / std::numbers::pi * height), 0, height - 1);
}

int SkyImage::ColumnOf(double phi) const {
  return std::clamp(int(phi / (2 * std::numbers::pi) * width), 0, width - 1);
}

double SkyImage::ThetaTop(int y) const { return std::numbers::pi * double(y) / double(height); }

bool SkyImage::IsConstant() const {
  return std::all_of(texels.begin(), texels.end(), [&](const Rgb& t) { return t == texels.front(); });
}

void CheckSkyImage(const SkyImage& image) {
  RequireSize(image.source, image.width, image.height, {});
  if (image.width != 2 * image.height)
    throw InputError(image.source, 0, fmt::format("a sky image of {} x {} pixels is not latitude-longitude: its "
                                                  "width must be twice its height", image.width, image.height));
  for (size_t i = 0; i < image.texels.size(); ++i) {
    const Rgb& t = image.texels[i];
    if (!(t.r >= 0 && t.g >= 0 && t.b >= 0 && std::isfinite(t.r) && std::isfinite(t.g) && std::isfinite(t.b)))
      throw InputError(image.source, 0, fmt::format("the sky image's pixel ({}, {}) holds ({:g}, {:g}, {:g}): "
                                                    "radiance must be finite and not negative", i % size_t(image.width),
                                                    i / size_t(image.width), t.r, t.g, t.b));
  }
}

double SkyImageBytes(uint64_t pixels, size_t portals) {
  return double(pixels) * double(sizeof(Rgb) + sizeof(double) * (1 + portals));
}

SkyImage LoadSkyImage(const std::string& path, uint64_t maxPixels, SkyMemory memory) {
  const Limits limits{maxPixels, memory};
  const std::string bytes = ReadRegularFile(path, "sky image");
  const bool exr = bytes.size() >= 4 && bytes.compare(0, 4, "\x76\x2f\x31\x01") == 0;
  const bool hdr = bytes.rfind("#?RADIANCE", 0) == 0 || bytes.rfind("#?RGBE", 0) == 0;
  if (!exr && !hdr) throw InputError(path, 0, "a sky image must be OpenEXR (.exr) or Radiance HDR (.hdr)");
  SkyImage image = exr ? ReadExr(path, bytes, limits) : RgbeReader(path, bytes, limits).Read();
  CheckSkyImage(image);
  return image;
}

}  // namespace pb
