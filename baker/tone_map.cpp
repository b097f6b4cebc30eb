#include "baker/tone_map.h"

#include <algorithm>
#include <cmath>

namespace pb {
namespace {

float EncodeSrgb(float linear) {
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float Reinhard(float x) { return x / (1.0f + x); }
float Display(float x) { return EncodeSrgb(Reinhard(x)); }

uint8_t ToByte(float linear) { return uint8_t(std::clamp(std::lround(EncodeSrgb(linear) * 255.0f), 0l, 255l)); }

}  // namespace

float AutoExposure(std::span<const Rgb> radiance) {
  double logSum = 0;
  size_t lit = 0;
  for (const Rgb& L : radiance)
    if (const float y = Luminance(L); y > 0) {
      logSum += std::log(double(y));
      ++lit;
    }
  return lit ? float(0.18 / std::exp(logSum / double(lit))) : 1.0f;
}

Rgb ToneMapLinear(Rgb radiance, float exposure) {
  const Rgb x = radiance * exposure;
  return {Reinhard(std::max(0.0f, x.r)), Reinhard(std::max(0.0f, x.g)), Reinhard(std::max(0.0f, x.b))};
}

std::array<uint8_t, 3> ToneMap(Rgb radiance, float exposure) {
  const Rgb c = ToneMapLinear(radiance, exposure);
  return {ToByte(c.r), ToByte(c.g), ToByte(c.b)};
}

float DisplayedLuminance(Rgb radiance, float exposure) {
  return Display(std::max(0.0f, Luminance(radiance) * exposure));
}

}  // namespace pb
