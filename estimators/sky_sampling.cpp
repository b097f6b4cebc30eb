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

// Per channel c, radiance_c x scale / total_c: a photon's share of each channel's flux (0 where a channel has none).
Rgb ChannelShares(Rgb radiance, double scale, Rgb total) {
  const auto channel = [&](float l, float t) { return t > 0 ? float(l * scale / t) : 0.0f; };
  return {channel(radiance.r, total.r), channel(radiance.g, total.g), channel(radiance.b, total.b)};
}

}  // namespace

std::optional<SkySample> SampleSkyImage(const Light& sky, Point2 u) {
  const auto pick = SampleDiscreteCdf(sky.texelCdf, u.u);
  if (!pick) return std::nullopt;
  const Vector3 from = InTexel(sky.analytic, pick->index, {pick->uRemapped, u.v});
  const Rgb radiance = sky.analytic.intensity * sky.analytic.image->texels[pick->index];
  return SkySample{from, float(Luminance(radiance) / sky.skyLuminanceIntegral)};  // the texel's, as drawn
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
  return ChannelShares(a.intensity * a.image->texels[pick->index], scale, sky.portalFlux);
}

std::optional<SkySample> SampleTowardPortals(const Light& sky, Point3 p, Point2 u) {
  const auto pick = SampleDiscreteCdf(sky.portalCdf, u.u);
  if (!pick) return std::nullopt;
  const Portal& portal = sky.portals[pick->index];
  const Vector3 toward = portal.origin + portal.u * pick->uRemapped + portal.v * u.v - p;
  const float d2 = LengthSquared(toward);
  if (!(d2 > 0)) return std::nullopt;
  const Vector3 w = toward * (1 / std::sqrt(d2));
  const float cosPortal = -Dot(w, portal.Inward());  // out through it: against its inward normal
  if (!(cosPortal > 0)) return std::nullopt;
  return SkySample{w, TowardPortalsPdf(sky, p, w)};
}

float TowardPortalsPdf(const Light& sky, Point3 p, Vector3 w) {
  double pdf = 0, previous = 0;
  for (size_t i = 0; i < sky.portals.size(); ++i) {
    const Portal& portal = sky.portals[i];
    const double share = sky.portalCdf[i] - previous;
    previous = sky.portalCdf[i];
    const Vector3 n = Cross(portal.u, portal.v);
    const float along = -Dot(w, n);  // > 0 going out
    if (!(along > 0) || !(share > 0)) continue;
    const float t = -Dot(portal.origin - p, n) / along;
    if (!(t > 0)) continue;
    const Vector3 q = p + w * t - portal.origin;
    const float nn = Dot(n, n), a = Dot(Cross(q, portal.v), n) / nn, b = Dot(Cross(portal.u, q), n) / nn;
    if (a < 0 || a > 1 || b < 0 || b > 1) continue;
    const double area = std::sqrt(double(nn)), cosPortal = along / area;
    pdf += share * double(t) * t / (area * cosPortal);
  }
  return float(pdf);
}

float SkyImagePdf(const Light& sky, Vector3 from) {
  if (!(sky.skyLuminanceIntegral > 0)) return 0;
  return float(Luminance(SkyRadianceFrom(sky.analytic, from)) / sky.skyLuminanceIntegral);
}

Rgb SkyPhotonWeight(const Light& sky, Rgb radiance) {
  const double lum = Luminance(radiance);
  return lum > 0 ? ChannelShares(radiance, sky.skyLuminanceIntegral / lum, sky.skyIntegral) : Rgb{};
}

}  // namespace pb
