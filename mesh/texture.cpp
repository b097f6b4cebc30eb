#include "mesh/texture.h"

#include <png.h>
#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "mesh/errors.h"
#include "mesh/input_file.h"

namespace pb {
namespace {

// The exact sRGB decoding curve (IEC 61966-2-1), for 8-bit values.
const std::array<float, 256>& SrgbToLinear() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> linear{};
    for (int b = 0; b < 256; ++b) {
      const double c = b / 255.0;
      linear[size_t(b)] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return linear;
  }();
  return table;
}

// A texture from 8-bit sRGB-encoded RGB pixels, top row first.
Texture FromSrgbPixels(const std::string& path, int width, int height, const uint8_t* pixels) {
  Texture t{path, width, height, {}, {}};
  if (t.width < 1 || t.height < 1) throw InputError(path, 0, "texture has no pixels");
  const std::array<float, 256>& linear = SrgbToLinear();
  const size_t count = size_t(t.width) * size_t(t.height);
  t.texels.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    const Rgb c{linear[pixels[3 * i]], linear[pixels[3 * i + 1]], linear[pixels[3 * i + 2]]};
    t.texels.push_back(c);
    t.maximum = {std::max(t.maximum.r, c.r), std::max(t.maximum.g, c.g), std::max(t.maximum.b, c.b)};
  }
  return t;
}

void CheckPixelCount(const std::string& path, uint64_t width, uint64_t height, uint64_t fileBytes) {
  const std::string size = std::to_string(width) + " x " + std::to_string(height) + " pixels";
  if (width * height > kMaxTexturePixels)
    throw InputError(path, 0, "texture of " + size + " is larger than the 8192 x 8192 a texture may have");
  if (width * height > kMostTexturePixelsPerByte * fileBytes)
    throw InputError(path, 0, "texture of " + size + " in a file of " + std::to_string(fileBytes) + " bytes: no image "
                              "format holds that many pixels in so few bytes (the file is cut short or forged)");
}

// JPEG, TGA, BMP and the other formats stb_image reads, from the file's bytes.
Texture LoadStbTexture(const std::string& path, const std::string& bytes) {
  if (bytes.size() > size_t(INT32_MAX)) throw InputError(path, 0, "texture file is larger than 2 GB");
  // stb_image's Radiance HDR decoder loops forever on a malformed run (found by fuzz_sky_image), and an HDR image is
  // radiance, not the reflectance a texture holds: refused before stb_image sees it.
  if (stbi_is_hdr_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size())))
    throw InputError(path, 0, "an HDR image is not a reflectance texture (textures may be PNG, JPEG, TGA or BMP)");
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  int width = 0, height = 0, channels = 0;
  // The header's size, checked before the pixels are allocated.
  if (!stbi_info_from_memory(data, int(bytes.size()), &width, &height, &channels))
    throw InputError(path, 0, std::string("cannot read texture: ") + stbi_failure_reason() +
                                  " (textures may be PNG, JPEG, TGA or BMP)");
  CheckPixelCount(path, uint64_t(width), uint64_t(height), bytes.size());
  stbi_uc* pixels = stbi_load_from_memory(data, int(bytes.size()), &width, &height, &channels, 3);
  if (!pixels) throw InputError(path, 0, std::string("cannot decode texture: ") + stbi_failure_reason());
  try {
    Texture t = FromSrgbPixels(path, width, height, pixels);
    stbi_image_free(pixels);
    return t;
  } catch (...) {
    stbi_image_free(pixels);
    throw;
  }
}

// A PNG from the file's bytes, read once, by libpng's simplified API.
Texture DecodePng(const std::string& path, const std::string& bytes) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size()))
    throw InputError(path, 0, std::string("cannot read texture: ") + image.message);
  // The header's size, checked before the pixels are allocated (a 69-byte PNG may declare 65535 x 65535).
  try {
    CheckPixelCount(path, image.width, image.height, bytes.size());
  } catch (const InputError&) {
    png_image_free(&image);
    throw;
  }
  image.format = PNG_FORMAT_RGB;  // 8-bit sRGB-encoded, as most textures are stored
  std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr)) {
    png_image_free(&image);
    throw InputError(path, 0, std::string("cannot decode texture: ") + image.message);
  }
  return FromSrgbPixels(path, int(image.width), int(image.height), pixels.data());
}

}  // namespace

Texture LoadTexture(const std::string& path) { return DecodeTexture(path, ReadRegularFile(path, "texture")); }

Texture DecodeTexture(const std::string& name, const std::string& bytes) {
  if (bytes.rfind("\x89PNG\r\n\x1a\n", 0) == 0) return DecodePng(name, bytes);
  return LoadStbTexture(name, bytes);
}

Texture LoadPngTexture(const std::string& path) { return DecodePng(path, ReadRegularFile(path, "texture")); }

Rgb Texture::Mean() const {
  double r = 0, g = 0, b = 0;
  for (const Rgb& c : texels) r += c.r, g += c.g, b += c.b;
  const double n = double(std::max<size_t>(texels.size(), 1));
  return {float(r / n), float(g / n), float(b / n)};
}

Rgb Texture::Texel(int x, int y) const {
  const int wx = ((x % width) + width) % width, wy = ((y % height) + height) % height;
  return texels[size_t(wy) * size_t(width) + size_t(wx)];
}

Rgb Texture::Sample(Point2 st, bool clamp) const {
  // Texel centres sit at half-integers; row 0 is the top, so t runs from the last row up.
  float x = st.u * float(width) - 0.5f, y = (1.0f - st.v) * float(height) - 0.5f;
  if (!std::isfinite(x) || !std::isfinite(y)) return Texel(0, 0);
  if (clamp) x = std::clamp(x, 0.0f, float(width - 1)), y = std::clamp(y, 0.0f, float(height - 1));
  const float fx = std::floor(x), fy = std::floor(y);
  const float ax = x - fx, ay = y - fy;
  const int x0 = int(std::fmod(fx, float(width))), y0 = int(std::fmod(fy, float(height)));
  // Clamped, the far neighbour of the last texel is itself (its weight is 0 there, but it stays in range).
  const int x1 = clamp ? std::min(x0 + 1, width - 1) : x0 + 1, y1 = clamp ? std::min(y0 + 1, height - 1) : y0 + 1;
  return Texel(x0, y0) * ((1 - ax) * (1 - ay)) + Texel(x1, y0) * (ax * (1 - ay)) + Texel(x0, y1) * ((1 - ax) * ay) +
         Texel(x1, y1) * (ax * ay);
}

}  // namespace pb
