// RGB triples of one radiometric quantity: flux [W], irradiance [W/m^2], radiance [W/(m^2 sr)] or a
// dimensionless reflectance, by context. Channels are linear (no gamma) with Rec. 709 primaries.
#pragma once

#include <algorithm>
#include <cmath>

namespace pb {

struct Rgb {
  float r = 0, g = 0, b = 0;
  float Max() const { return std::max({r, g, b}); }
  float Mean() const { return (r + g + b) / 3.0f; }
  bool IsBlack() const { return r == 0 && g == 0 && b == 0; }
  bool operator==(const Rgb&) const = default;
};

inline Rgb operator+(Rgb a, Rgb b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
inline Rgb operator-(Rgb a, Rgb b) { return {a.r - b.r, a.g - b.g, a.b - b.b}; }
inline Rgb operator*(Rgb a, Rgb b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
inline Rgb operator*(Rgb a, float s) { return {a.r * s, a.g * s, a.b * s}; }
inline Rgb operator*(float s, Rgb a) { return a * s; }
inline Rgb operator/(Rgb a, float s) { return a * (1.0f / s); }
inline Rgb& operator+=(Rgb& a, Rgb b) { return a = a + b; }

// Rec. 709 luminance weights: the photometric weight of each linear channel.
inline float Luminance(Rgb c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// A double-precision RGB accumulator, for sums of many small float terms (flux tallies, kernel sums).
struct RgbSum {
  double r = 0, g = 0, b = 0;
  void Add(Rgb c, double w = 1.0) { r += w * c.r; g += w * c.g; b += w * c.b; }
  void Add(const RgbSum& o) { r += o.r; g += o.g; b += o.b; }
  Rgb ToRgb() const { return {float(r), float(g), float(b)}; }
  double Mean() const { return (r + g + b) / 3.0; }
};

}  // namespace pb
