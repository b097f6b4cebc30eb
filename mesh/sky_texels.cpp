#include "mesh/sky_texels.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pb {
namespace {

constexpr int kParts = 8;  // per side, where the cosine changes sign over a texel

// The integral over `span` of f = a sin(theta) cos(phi) + b sin(theta) sin(phi) + c cos(theta), times
// sin(theta) dtheta dphi: integral sin^2 = (theta - sin theta cos theta) / 2, integral sin cos = sin^2 / 2.
double Integral(const TexelSpan& span, double a, double b, double c) {
  const auto s2 = [](double t) { return 0.5 * (t - std::sin(t) * std::cos(t)); };
  const auto sc = [](double t) { return 0.5 * std::sin(t) * std::sin(t); };
  const double sin2 = s2(span.theta1) - s2(span.theta0), sinCos = sc(span.theta1) - sc(span.theta0);
  return a * sin2 * (std::sin(span.phi1) - std::sin(span.phi0)) + b * sin2 * (std::cos(span.phi0) - std::cos(span.phi1)) +
         c * sinCos * (span.phi1 - span.phi0);
}

double F(double theta, double phi, double a, double b, double c) {
  return a * std::sin(theta) * std::cos(phi) + b * std::sin(theta) * std::sin(phi) + c * std::cos(theta);
}

// The integral of max(0, f) over the span: exact where f keeps its sign at the corners and centre.
double Clipped(const TexelSpan& s, double a, double b, double c, int depth) {
  int positive = 0;
  for (double t : {s.theta0, 0.5 * (s.theta0 + s.theta1), s.theta1})
    for (double p : {s.phi0, 0.5 * (s.phi0 + s.phi1), s.phi1}) positive += F(t, p, a, b, c) > 0;
  if (positive == 0) return 0;
  if (positive == 9 || depth == 0) return std::max(0.0, Integral(s, a, b, c));
  double sum = 0;
  for (int i = 0; i < kParts; ++i)
    for (int j = 0; j < kParts; ++j) {
      const TexelSpan part{s.theta0 + (s.theta1 - s.theta0) * i / kParts, s.theta0 + (s.theta1 - s.theta0) * (i + 1) / kParts,
                           s.phi0 + (s.phi1 - s.phi0) * j / kParts, s.phi0 + (s.phi1 - s.phi0) * (j + 1) / kParts};
      sum += Clipped(part, a, b, c, depth - 1);
    }
  return sum;
}

// Cumulative sums of `weights` normalised to end at 1; empty when they sum to 0. Returns the sum.
double ToCdf(std::vector<double>& weights) {
  double sum = 0;
  for (double& w : weights) w = sum += w;
  if (!(sum > 0)) {
    weights.clear();
    return 0;
  }
  for (double& w : weights) w /= sum;
  weights.back() = 1;
  return sum;
}

void WeighThroughDiscs(Light& light) {
  const AnalyticLight& a = light.analytic;
  const SkyImage& image = *a.image;
  RgbSum integral;
  light.texelCdf.reserve(image.texels.size());
  for (int y = 0; y < image.height; ++y) {
    const double omega = SpanOf(a, 0, y).SolidAngle();
    for (int x = 0; x < image.width; ++x) {
      const Rgb radiance = a.intensity * image.Texel(x, y);
      integral.Add(radiance, omega);
      light.texelCdf.push_back(Luminance(radiance) * omega);
    }
  }
  light.skyIntegral = integral.ToRgb();
  light.skyLuminanceIntegral = ToCdf(light.texelCdf);
}

void WeighThroughPortals(Light& light) {
  const AnalyticLight& a = light.analytic;
  const SkyImage& image = *a.image;
  RgbSum integral;
  light.portalCdf.clear();
  for (const Portal& portal : light.portals) {
    std::vector<double> cdf;
    cdf.reserve(image.texels.size());
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        const double c = TexelCosineSolidAngle(a, x, y, portal.Inward());
        const Rgb radiance = a.intensity * image.Texel(x, y);
        integral.Add(radiance, c * portal.Area());
        cdf.push_back(Luminance(radiance) * c);
      }
    const double sum = ToCdf(cdf);
    light.portalTexelCdf.push_back(std::move(cdf));
    light.portalTexelSum.push_back(sum);
    light.portalCdf.push_back(sum * portal.Area());
  }
  light.portalFlux = integral.ToRgb();
  light.portalLuminanceFlux = ToCdf(light.portalCdf);
}

}  // namespace

TexelSpan SpanOf(const AnalyticLight& sky, int x, int y) {
  const SkyImage& image = *sky.image;
  const double top = image.ThetaTop(y);
  const double bottom = sky.wholeSphere ? image.ThetaBottom(y) : std::max(top, std::min(image.ThetaBottom(y), std::numbers::pi / 2));
  const double width = 2 * std::numbers::pi / image.width;
  return {top, bottom, width * x, width * (x + 1)};
}

double TexelCosineSolidAngle(const AnalyticLight& sky, int x, int y, Normal3 inward) {
  // In the sky's frame w = (-sin cos phi, -sin sin phi, cos) (SkyDirection), so n . (-w) = a sin cos phi + b sin
  // sin phi + c cos with (a, b, c) = (n . s, n . t, -n . up).
  const Vector3 n = SkyFrame(sky).ToLocal(AsVector(inward));
  return Clipped(SpanOf(sky, x, y), n.x, n.y, -n.z, 1);
}

void WeighSkyTexels(Light& light) {
  WeighThroughDiscs(light);
  if (!light.portals.empty()) WeighThroughPortals(light);
}

}  // namespace pb
