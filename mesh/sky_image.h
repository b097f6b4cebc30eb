// An environment's radiance over the sphere of directions, L [W/(m^2 sr)] per texel of an equirectangular
// (latitude-longitude) image, constant over each texel:
//   row y (0 the top) holds the polar angle theta from the sky's up in [y, y + 1) pi / H: the top row the zenith,
//   the middle the horizon, the bottom the nadir;
//   column x holds the azimuth phi in [x, x + 1) 2 pi / W about up, from the image's left edge, turning clockwise
//   seen from above (left to right across the image is left to right seen from inside); the image's centre
//   column (phi = pi) looks along the sky's "front".
// A texel's solid angle is (2 pi / W) (cos theta_top - cos theta_bottom) [sr].
// Read from OpenEXR (.exr, its R, G and B channels, or Y, as linear radiance) or Radiance RGBE (.hdr, read here:
// stb_image's decoder hangs on a malformed run), told apart by their first bytes. Refused with an InputError naming the file: an image that is not
// lat-long (width twice its height), larger than kMaxSkyPixels, or with a negative or non-finite value.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/color.h"
#include "mesh/geometry.h"

namespace pb {

inline constexpr uint64_t kMaxSkyPixels = uint64_t(16384) * 8192;

struct SkyImage {
  std::string source;       // the file, for messages and reports
  int width = 0, height = 0;
  std::vector<Rgb> texels;  // row-major, top row first [W/(m^2 sr)]

  const Rgb& Texel(int x, int y) const { return texels[size_t(y) * size_t(width) + size_t(x)]; }
  // The texel holding (theta, phi) [rad], theta in [0, pi], phi in [0, 2 pi] (clamped).
  int RowOf(double theta) const;
  int ColumnOf(double phi) const;
  // The polar angles bounding row y [rad].
  double ThetaTop(int y) const;
  double ThetaBottom(int y) const { return ThetaTop(y + 1); }
  // True when every texel holds the same value: the sky is then a constant one.
  bool IsConstant() const;
};

// InputError naming the file when it is missing, not .exr or .hdr, malformed, or breaks a rule above; `maxPixels`
// bounds the size before anything is allocated (the fuzz target lowers it).
// The memory a sky image of `pixels` texels holds once weighed for its photons (mesh/sky_texels.h): its texels, the
// CDF over them, and one CDF more per portal [bytes].
double SkyImageBytes(uint64_t pixels, size_t portals);
// What the image shares the memory with: the scene's portals, each a table per texel, and what the lights file's
// earlier sky images hold [bytes]. An image whose SkyImageBytes, added to `held`, passes the memory a run may use
// (mesh/memory_budget.h) is refused from its header, naming the file and the figure, before its texels are read.
struct SkyMemory {
  size_t portals = 0;
  double held = 0;
};
SkyImage LoadSkyImage(const std::string& path, uint64_t maxPixels = kMaxSkyPixels, SkyMemory memory = {});
// The rules above for an image already in memory (a test's, or one read), with `source` naming it.
void CheckSkyImage(const SkyImage& image);

}  // namespace pb
