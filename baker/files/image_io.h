// Images of the path tracer: linear RGB radiance L [W/(m^2 sr)] per pixel, written as
//   OpenEXR: 32-bit float channels R, G, B, with header attributes naming the quantity and its units;
//   PNG: 8-bit sRGB of Reinhard(exposure * L) (baker/tone_map.h), for viewing.
// Both are staged in the run's OutputFiles (baker/files/atomic_file.h): a reader never sees a half-written image.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "baker/files/atomic_file.h"
#include "mesh/color.h"

namespace pb {

struct Image {
  int width = 0, height = 0;
  std::vector<Rgb> pixels;  // row-major, top row first
  Image() = default;
  Image(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h)) {}
  Rgb& At(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
  const Rgb& At(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

// A float channel of an EXR image besides R, G, B and A: one value per pixel, row-major, top row first.
struct ExrChannel {
  std::string name;
  std::vector<float> values;
};

// Extra string attributes go into the EXR header beside "quantity" and "units" (radiance unless the attributes
// name another). With `alpha` (one value per pixel) the image also gets an A channel, and `channels` after it.
void WriteExr(OutputFiles& outputs, const std::string& path, const Image& image,
              const std::vector<std::pair<std::string, std::string>>& attributes = {},
              const std::vector<float>* alpha = nullptr, const std::vector<ExrChannel>& channels = {});
// For tests and tools; InputError on failure. With `attributes`, also returns the header's string attributes;
// with `alpha`, the A channel (one value per pixel, row-major; 1 where the file has none); with `channels`, the
// channels of those names (0 where the file has none).
Image ReadExr(const std::string& path, std::vector<std::pair<std::string, std::string>>* attributes = nullptr,
              std::vector<float>* alpha = nullptr, std::vector<ExrChannel>* channels = nullptr);
void WritePng(OutputFiles& outputs, const std::string& path, const Image& image, float exposure);
// An 8-bit RGB PNG of display colours as they are (`rgb`: 3 bytes per pixel, row-major, top row first).
void WritePngRgb8(OutputFiles& outputs, const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

}  // namespace pb
