// An RGB reflectance texture (MTL map_Kd), dimensionless in [0, 1] per channel. Read from PNG through libpng's
// simplified API, or from JPEG, TGA or BMP through stb_image (grey or RGB, any alpha ignored; 16-bit images are
// reduced to 8 bits), as sRGB-encoded bytes, then decoded with the exact sRGB curve (IEC 61966-2-1; libpng's own
// linear output uses a 2.2 power instead): texels are linear reflectance. Sampled bilinearly with repeat wrapping at texture coordinates (s, t), where
// t = 0 is the bottom row of the image and t = 1 the top (the OBJ 'vt' convention).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/color.h"
#include "mesh/geometry.h"

namespace pb {

struct Texture {
  std::string path;
  int width = 0, height = 0;
  std::vector<Rgb> texels;  // row-major, top row first, as stored in the file
  Rgb maximum;              // largest value per channel

  Rgb Texel(int x, int y) const;  // wraps x and y
  Rgb Mean() const;                // over all texels
  // Bilinear at texture coordinates st, repeating (or with `clamp`, st clamped to [0, 1]).
  Rgb Sample(Point2 st, bool clamp = false) const;
};

// The most pixels a texture may have: 8192 x 8192, about 1 GB once decoded to linear RGB. Checked from the
// file's header, before its pixels are allocated.
inline constexpr uint64_t kMaxTexturePixels = uint64_t(8192) * 8192;
// The most pixels a byte of a texture file can hold: twice the most any format reaches (deflate's 1032:1 on a PNG
// of one bit a pixel, 8,256; a TGA or BMP run, 128 in 2 bytes; a JPEG block, 64 in a bit), so that a header that
// declares more than its file could hold (a 24-byte TGA declaring 29186 x 1538 pixels, which stb_image fills in
// seconds) is refused before decoding, with the figure.
inline constexpr uint64_t kMostTexturePixelsPerByte = 16384;

// A texture from a PNG (libpng), or a JPEG, TGA or BMP (stb_image; it also reads GIF, PSD and PNM), told apart by
// the file's first bytes, not its name. A Radiance HDR image is refused: it holds radiance, not reflectance (and
// stb_image's decoder of it hangs on a malformed run). InputError naming the file
// when it is missing, unreadable, malformed or too large.
Texture LoadTexture(const std::string& path);
// The same from a file's bytes already read (a glTF image, in a buffer or a data URI); `name` is the texture's
// path in messages and in Texture::path.
Texture DecodeTexture(const std::string& name, const std::string& bytes);
// The same for a file that must be a PNG.
Texture LoadPngTexture(const std::string& path);

}  // namespace pb
