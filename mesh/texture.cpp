#include "mesh/texture.h"

#include <png.h>

#include <array>
#include <cmath>
#include <cstdint>

#include "mesh/errors.h"
#include "mesh/input_file.h"

namespace pb {

Texture LoadPngTexture(const std::string& path) {
  RequireRegularFile(path, "texture");
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    throw InputError(path, 0, std::string("cannot read texture: ") + image.message);
  // The header's size, checked before the pixels are allocated (a 69-byte PNG may declare 65535 x 65535).
  if (uint64_t(image.width) * image.height > kMaxTexturePixels) {
    png_image_free(&image);
    throw InputError(path, 0, "texture of " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                                  " pixels is larger than the 8192 x 8192 a texture may have");
  }
  image.format = PNG_FORMAT_RGB;  // 8-bit sRGB-encoded, as most textures are stored
  std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr)) {
    png_image_free(&image);
    throw InputError(path, 0, std::string("cannot decode texture: ") + image.message);
  }
  Texture t{path, int(image.width), int(image.height), {}, {}};
  if (t.width < 1 || t.height < 1) throw InputError(path, 0, "texture has no pixels");
  t.texels.reserve(size_t(t.width) * size_t(t.height));
  std::array<float, 256> linear{};  // the exact sRGB decoding curve (IEC 61966-2-1)
  for (int b = 0; b < 256; ++b) {
    const double c = b / 255.0;
    linear[size_t(b)] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
  }
  for (size_t i = 0; i + 2 < pixels.size(); i += 3) {
    const Rgb c{linear[pixels[i]], linear[pixels[i + 1]], linear[pixels[i + 2]]};
    t.texels.push_back(c);
    t.maximum = {std::max(t.maximum.r, c.r), std::max(t.maximum.g, c.g), std::max(t.maximum.b, c.b)};
  }
  return t;
}

Rgb Texture::Texel(int x, int y) const {
  const int wx = ((x % width) + width) % width, wy = ((y % height) + height) % height;
  return texels[size_t(wy) * size_t(width) + size_t(wx)];
}

Rgb Texture::Sample(Point2 st) const {
  // Texel centres sit at half-integers; row 0 is the top, so t runs from the last row up.
  const float x = st.u * float(width) - 0.5f, y = (1.0f - st.v) * float(height) - 0.5f;
  if (!std::isfinite(x) || !std::isfinite(y)) return Texel(0, 0);
  const float fx = std::floor(x), fy = std::floor(y);
  const float ax = x - fx, ay = y - fy;
  const int x0 = int(std::fmod(fx, float(width))), y0 = int(std::fmod(fy, float(height)));
  return Texel(x0, y0) * ((1 - ax) * (1 - ay)) + Texel(x0 + 1, y0) * (ax * (1 - ay)) +
         Texel(x0, y0 + 1) * ((1 - ax) * ay) + Texel(x0 + 1, y0 + 1) * (ax * ay);
}

}  // namespace pb
