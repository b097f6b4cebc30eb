#include "estimators/sky_sampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "estimators/warps.h"

namespace pb {

std::optional<SkySample> SampleSkyImage(const Light& sky, Point2 u) {
  const auto pick = SampleDiscreteCdf(sky.texelCdf, u.u);
  if (!pick) return std::nullopt;
  const SkyImage& image = *sky.analytic.image;
  const int x = int(pick->index % uint32_t(image.width)), y = int(pick->index / uint32_t(image.width));
  const double top = image.ThetaTop(y);
  const double bottom = sky.analytic.wholeSphere ? image.ThetaBottom(y) : std::min(image.ThetaBottom(y), kPi / 2.0);
  const double cosTheta = std::cos(top) + (std::cos(bottom) - std::cos(top)) * double(u.v);
  const double phi = 2 * std::numbers::pi * (x + double(pick->uRemapped)) / image.width;
  const Vector3 from = SkyDirection(SkyFrame(sky.analytic), std::acos(std::clamp(cosTheta, -1.0, 1.0)), phi);
  return SkySample{from, SkyImagePdf(sky, from)};
}

float SkyImagePdf(const Light& sky, Vector3 from) {
  if (!(sky.skyLuminanceIntegral > 0)) return 0;
  return float(Luminance(SkyRadianceFrom(sky.analytic, from)) / sky.skyLuminanceIntegral);
}

Rgb SkyPhotonWeight(const Light& sky, Rgb radiance) {
  const double lum = Luminance(radiance);
  const Rgb& total = sky.skyIntegral;
  if (!(lum > 0)) return {};
  const auto channel = [&](float l, float t) { return t > 0 ? float(l * sky.skyLuminanceIntegral / (lum * t)) : 0.0f; };
  return {channel(radiance.r, total.r), channel(radiance.g, total.g), channel(radiance.b, total.b)};
}

}  // namespace pb
