#include "estimators/emission.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "estimators/sky_sampling.h"
#include "estimators/warps.h"
#include "mesh/errors.h"

namespace pb {

namespace {

EmissionSample FromArea(const Scene& scene, const Light& light, Rng& rng) {
  const auto pick = SampleDiscreteCdf(light.triangleCdf, rng.Uniform());
  PB_CHECK(pick.has_value(), "a light has at least one triangle");
  const uint32_t triangle = light.triangles[pick->index];
  const Barycentrics b = SampleUniformTriangle(rng.Uniform2());
  const Normal3 n = scene.FrontNormal(triangle);
  const DirectionSample d = SampleCosineHemisphere(rng.Uniform2());
  return {scene.PointAt(triangle, b.b1, b.b2), n, true, Frame::FromNormal(n).ToWorld(d.direction), triangle,
          float(1.0 / light.area), d.pdf};
}

// From a point: `d` in `frame`.
EmissionSample FromPoint(Point3 position, const Frame& frame, const DirectionSample& d) {
  const Vector3 w = frame.ToWorld(d.direction);
  return {position, NormalFrom(w), false, w, 0, 0, d.pdf};
}

// Travelling along `w` from the disc of radius R that faces along w, R behind the bounding sphere's centre.
EmissionSample FromDisc(const Light& light, Vector3 w, Point2 u, float pdfDirection) {
  const Frame frame = Frame::FromNormal(NormalFrom(w));
  const Point2 p = SampleUniformDiskConcentric(u);
  const float r = light.boundsRadius;
  const Point3 position = light.boundsCentre + (frame.s * p.u + frame.t * p.v - AsVector(frame.n)) * r;
  return {position, frame.n, false, AsVector(frame.n), 0, float(1.0 / (kPi * double(r) * r)), pdfDirection};
}

// From a point uniform on a portal picked by its share of the light's flux.
EmissionSample FromPortal(const Light& light, Rng& rng) {
  const auto pick = SampleDiscreteCdf(light.portalCdf, rng.Uniform());
  PB_CHECK(pick.has_value(), "a light aimed at portals has one");
  const Portal& portal = light.portals[pick->index];
  const Point2 ab = rng.Uniform2();
  const Point3 position = portal.origin + portal.u * ab.u + portal.v * ab.v;
  const AnalyticLight& a = light.analytic;
  if (light.kind == LightKind::kSun) return {position, NormalFrom(a.direction), false, a.direction, 0, 0, 0};
  if (a.image) {
    Vector3 from;
    const std::optional<Rgb> weight = SampleSkyThroughPortal(light, pick->index, rng.Uniform2(), from);
    PB_CHECK(weight.has_value(), "a portal picked by its share lets light in");
    EmissionSample e{position, NormalFrom(-from), false, -from, 0, float(1 / portal.Area()), 0};
    e.weight = *weight, e.carriesLight = !weight->IsBlack();
    return e;
  }
  const DirectionSample d = SampleCosineHemisphere(rng.Uniform2());
  const Vector3 w = Frame::FromNormal(portal.Inward()).ToWorld(d.direction);  // the way the light travels
  EmissionSample e{position, NormalFrom(w), false, w, 0, float(1 / portal.Area()), d.pdf};
  e.carriesLight = a.wholeSphere || Dot(-w, a.up) > 0;
  return e;
}

// A point light's photon: by its profile when it has one (in the profile's frame), else uniform over the sphere.
EmissionSample FromPointLight(const AnalyticLight& a, Rng& rng) {
  if (!a.profile) return FromPoint(a.position, Frame::FromNormal({0, 0, 1}), SampleUniformSphere(rng.Uniform2()));
  const std::optional<DirectionSample> d = SampleProfile(*a.profile, rng);
  PB_CHECK(d.has_value(), "a light that emits photons has flux");
  return FromPoint(a.position, ProfileFrame(a), *d);
}

// Toward the scene from a direction of the sky's image, drawn by its luminance, from a disc facing it.
EmissionSample FromSkyImage(const Light& light, Rng& rng) {
  const std::optional<SkySample> from = SampleSkyImage(light, rng.Uniform2());
  PB_CHECK(from.has_value(), "a sky that emits photons has flux");
  EmissionSample e = FromDisc(light, -from->from, rng.Uniform2(), from->pdf);
  e.weight = SkyPhotonWeight(light, SkyRadianceFrom(light.analytic, from->from));
  return e;
}

}  // namespace

std::optional<DirectionSample> SampleProfile(const IntensityProfile& profile, Rng& rng) {
  const auto pick = SampleDiscreteCdf(profile.CellCdf(), rng.Uniform());
  if (!pick) return std::nullopt;
  const IntensityProfile::Cell cell = profile.CellAt(pick->index);
  const double cos0 = std::cos(cell.gamma0), cos1 = std::cos(cell.gamma1);
  double gamma = 0, c = 0;
  for (int i = 0; i < kProfileTries; ++i) {
    const Point2 u = rng.Uniform2();
    gamma = std::acos(std::clamp(cos0 + (cos1 - cos0) * double(u.u), -1.0, 1.0));  // uniform in solid angle
    c = cell.c0 + (cell.c1 - cell.c0) * double(u.v);
    if (double(rng.Uniform()) * cell.maxIntensity < profile.Intensity(gamma, c)) break;
  }
  const double sinGamma = std::sin(gamma);
  const Vector3 local{float(sinGamma * std::cos(c)), float(sinGamma * std::sin(c)), float(std::cos(gamma))};
  return DirectionSample{local, float(profile.Intensity(gamma, c) / profile.Flux())};
}

EmissionSample SampleEmission(const Scene& scene, const Light& light, Rng& rng) {
  const AnalyticLight& a = light.analytic;
  if (!light.portals.empty()) return FromPortal(light, rng);
  switch (light.kind) {
    case LightKind::kArea: return FromArea(scene, light, rng);
    case LightKind::kPoint: return FromPointLight(a, rng);
    case LightKind::kSpot:
      return FromPoint(a.position, Frame::FromNormal(NormalFrom(a.direction)), SampleSpotCone(rng.Uniform2(), a.cosInner, a.cosOuter));
    case LightKind::kSun: return FromDisc(light, a.direction, rng.Uniform2(), 0);
    case LightKind::kSky: {
      if (a.image) return FromSkyImage(light, rng);
      const DirectionSample from = a.wholeSphere ? SampleUniformSphere(rng.Uniform2()) : SampleUniformHemisphere(rng.Uniform2());
      const Vector3 w = Frame::FromNormal(NormalFrom(a.up)).ToWorld(from.direction);  // where the light comes from
      return FromDisc(light, -w, rng.Uniform2(), from.pdf);
    }
  }
  PB_CHECK(false, "every light kind emits");
  return {};
}

std::vector<uint64_t> AllocatePhotons(const std::vector<Light>& lights, uint64_t n,
                                      const std::vector<bool>& eligible) {
  std::vector<double> power(lights.size());
  for (size_t i = 0; i < lights.size(); ++i) power[i] = eligible.empty() || eligible[i] ? lights[i].Power().Mean() : 0.0;
  const double total = std::accumulate(power.begin(), power.end(), 0.0);
  std::vector<uint64_t> count(lights.size(), 0);
  if (!(total > 0)) return count;
  for (size_t i = 0; i < lights.size(); ++i) count[i] = uint64_t(std::floor(double(n) * (power[i] / total)));
  return count;
}

}  // namespace pb
