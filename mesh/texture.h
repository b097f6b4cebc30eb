// An RGB reflectance texture (MTL map_Kd), dimensionless in [0, 1] per channel. Read from PNG (grey or RGB, any
// alpha ignored; 16-bit images are reduced to 8 bits) through libpng's simplified API as sRGB-encoded bytes, then
// decoded with the exact sRGB curve (IEC 61966-2-1; libpng's own linear output uses a 2.2 power instead):
// texels are linear reflectance. Sampled bilinearly with repeat wrapping at texture coordinates (s, t), where
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
  Rgb Sample(Point2 st) const;
};

// InputError naming the file on a missing, unreadable or malformed PNG.
// The most pixels a texture may have: 8192 x 8192, about 1 GB once decoded to linear RGB.
inline constexpr uint64_t kMaxTexturePixels = uint64_t(8192) * 8192;

Texture LoadPngTexture(const std::string& path);

}  // namespace pb
