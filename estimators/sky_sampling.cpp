#include "estimators/sky_sampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "estimators/warps.h"
#include "mesh/sky_texels.h"

namespace pb {

namespace {

// A direction uniform over the solid angle of texel `index`, with u in [0, 1)^2.
Vector3 InTexel(const AnalyticLight& sky, uint32_t index, Point2 u) {
  const uint32_t width = uint32_t(sky.image->width);
  const TexelSpan span = SpanOf(sky, int(index % width), int(index / width));
  const double cosTheta = std::cos(span.theta0) + (std::cos(span.theta1) - std::cos(span.theta0)) * double(u.v);
  const double phi = span.phi0 + (span.phi1 - span.phi0) * double(u.u);
  return SkyDirection(SkyFrame(sky), std::acos(std::clamp(cosTheta, -1.0, 1.0)), phi);
}

}  // namespace

std::optional<SkySample> SampleSkyImage(const Light& sky, Point2 u) {
  const auto pick = SampleDiscreteCdf(sky.texelCdf, u.u);
  if (!pick) return std::nullopt;
  const Vector3 from = InTexel(sky.analytic, pick->index, {pick->uRemapped, u.v});
  return SkySample{from, SkyImagePdf(sky, from)};
}

std::optional<Rgb> SampleSkyThroughPortal(const Light& sky, uint32_t portal, Point2 u, Vector3& from) {
  const auto pick = SampleDiscreteCdf(sky.portalTexelCdf[portal], u.u);
  if (!pick) return std::nullopt;
  const AnalyticLight& a = sky.analytic;
  from = InTexel(a, pick->index, {pick->uRemapped, u.v});
  const float cosIn = -Dot(from, sky.portals[portal].Inward());
  const uint32_t width = uint32_t(a.image->width);
  const TexelSpan span = SpanOf(a, int(pick->index % width), int(pick->index / width));
  if (!(cosIn > 0) || !(sky.portalLuminanceFlux > 0)) return Rgb{};
  // L cos Omega / (pmf Z_p) per unit of the portal's share, over the channel's flux per unit of luminous flux.
  const double scale = cosIn * span.SolidAngle() * sky.portalLuminanceFlux / (pick->pmf * sky.portalTexelSum[portal]);
  const Rgb radiance = a.intensity * a.image->texels[pick->index], total = sky.portalFlux;
  const auto channel = [&](float l, float t) { return t > 0 ? float(l * scale / t) : 0.0f; };
  return Rgb{channel(radiance.r, total.r), channel(radiance.g, total.g), channel(radiance.b, total.b)};
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
