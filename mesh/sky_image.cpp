#include "mesh/sky_image.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <fmt/format.h>
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "mesh/errors.h"
#include "mesh/input_file.h"

namespace pb {
namespace {

void RequireSize(const std::string& path, int64_t width, int64_t height) {
  if (width <= 0 || height <= 0 || uint64_t(width) * uint64_t(height) > kMaxSkyPixels)
    throw InputError(path, 0, fmt::format("a sky image of {} x {} pixels: it must have between 1 and {} pixels",
                                          width, height, kMaxSkyPixels));
}

// R, G and B as float slices of `image`, or Y in all three for a luminance-only file.
SkyImage ReadExr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const int64_t width = int64_t(window.max.x) - window.min.x + 1, height = int64_t(window.max.y) - window.min.y + 1;
    RequireSize(path, width, height);
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

SkyImage ReadHdr(const std::string& path, const std::string& bytes) {
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  int width = 0, height = 0, channels = 0;
  if (bytes.size() > size_t(INT32_MAX) || !stbi_info_from_memory(data, int(bytes.size()), &width, &height, &channels))
    throw InputError(path, 0, std::string("cannot read the sky image as Radiance HDR: ") + stbi_failure_reason());
  RequireSize(path, width, height);
  const std::unique_ptr<float, void (*)(void*)> pixels(
      stbi_loadf_from_memory(data, int(bytes.size()), &width, &height, &channels, 3), stbi_image_free);
  if (!pixels) throw InputError(path, 0, std::string("cannot decode the sky image: ") + stbi_failure_reason());
  SkyImage image{path, width, height, std::vector<Rgb>(size_t(width) * size_t(height))};
  for (size_t i = 0; i < image.texels.size(); ++i)
    image.texels[i] = {pixels.get()[3 * i], pixels.get()[3 * i + 1], pixels.get()[3 * i + 2]};
  return image;
}

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
  RequireSize(image.source, image.width, image.height);
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

SkyImage LoadSkyImage(const std::string& path) {
  const std::string bytes = ReadRegularFile(path, "sky image");
  const bool exr = bytes.size() >= 4 && bytes.compare(0, 4, "\x76\x2f\x31\x01") == 0;
  const bool hdr = !exr && stbi_is_hdr_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                                   int(std::min<size_t>(bytes.size(), INT32_MAX)));
  if (!exr && !hdr) throw InputError(path, 0, "a sky image must be OpenEXR (.exr) or Radiance HDR (.hdr)");
  SkyImage image = exr ? ReadExr(path) : ReadHdr(path, bytes);
  CheckSkyImage(image);
  return image;
}

}  // namespace pb
