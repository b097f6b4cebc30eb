#include "mesh/lights.h"

#include "mesh/sky_texels.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pb {
namespace {

// Each portal's flux per unit E (sun) or L (sky): A_p max(0, d . n_p), or pi A_p.
std::vector<double> PortalWeights(const AnalyticLight& a, const std::vector<Portal>& portals) {
  std::vector<double> w;
  for (const Portal& p : portals)
    w.push_back(a.kind == LightKind::kSun ? p.Area() * std::max(0.0f, Dot(a.direction, p.Inward())) : kPi * p.Area());
  return w;
}

// The sphere about the positions' bounding box centre that holds them all, grown by 1% so that the discs sun and
// sky photons leave from lie clear of every surface.
void BoundingSphere(const Scene& scene, Point3& centre, float& radius) {
  Point3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Point3& p : scene.positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  centre = {0.5f * (lo.x + hi.x), 0.5f * (lo.y + hi.y), 0.5f * (lo.z + hi.z)};
  float r2 = 0;
  for (const Point3& p : scene.positions) r2 = std::max(r2, LengthSquared(p - centre));
  radius = 1.01f * std::sqrt(r2) + 1e-6f;
}

// Portals that pass none of the light (a sun parallel to them) are kept with weight 0; when all do, the light
// keeps its bounding discs.
void AimAtPortals(Light& light, const std::vector<Portal>& portals) {
  double sum = 0;
  std::vector<double> cdf;
  for (double w : PortalWeights(light.analytic, portals)) cdf.push_back(sum += w);
  if (!(sum > 0)) return;
  for (double& c : cdf) c /= sum;
  cdf.back() = 1;
  light.portals = portals;
  light.portalCdf = std::move(cdf);
}

}  // namespace

Frame SkyFrame(const AnalyticLight& sky) {
  const Normal3 up = NormalFrom(sky.up);
  return {sky.c0, Cross(sky.c0, AsVector(up)), up};
}

Vector3 SkyDirection(const Frame& frame, double theta, double phi) {
  const double sinTheta = std::sin(theta);
  return frame.ToWorld({float(-sinTheta * std::cos(phi)), float(-sinTheta * std::sin(phi)), float(std::cos(theta))});
}

Rgb SkyRadianceFrom(const AnalyticLight& sky, Vector3 from) {
  if (!sky.wholeSphere && !(Dot(from, sky.up) > 0)) return {};
  if (!sky.image) return sky.intensity;
  const Vector3 local = SkyFrame(sky).ToLocal(from);
  const double phi = std::atan2(-double(local.y), -double(local.x));
  const double theta = std::acos(std::clamp(double(local.z), -1.0, 1.0));
  const SkyImage& image = *sky.image;
  return sky.intensity * image.Texel(image.ColumnOf(phi < 0 ? phi + 2 * std::numbers::pi : phi), image.RowOf(theta));
}

double SpotSolidAngle(float cosInner, float cosOuter) {
  return 2 * kPi * ((1.0 - double(cosInner)) + (double(cosInner) - double(cosOuter)) / 3);
}

float SpotFalloff(const AnalyticLight& spot, float cosAngle) {
  if (cosAngle >= spot.cosInner) return 1;
  const float t = std::clamp((cosAngle - spot.cosOuter) / (spot.cosInner - spot.cosOuter), 0.0f, 1.0f);
  return t * t;
}

Frame ProfileFrame(const AnalyticLight& light) {
  const Normal3 nadir = NormalFrom(light.direction);
  return {light.c0, Cross(light.c0, AsVector(nadir)), nadir};
}

float RelativeIntensity(const AnalyticLight& light, Vector3 w) {
  if (light.kind == LightKind::kSpot) return SpotFalloff(light, Dot(w, light.direction));
  if (!light.profile) return 1;
  const Vector3 local = ProfileFrame(light).ToLocal(w);
  const double c = std::atan2(double(local.y), double(local.x));
  return float(light.profile->Intensity(std::acos(std::clamp(double(local.z), -1.0, 1.0)), c < 0 ? c + 2 * std::numbers::pi : c));
}

Rgb Light::Power() const {
  const AnalyticLight& a = analytic;
  if (a.image) return portals.empty() ? skyIntegral * float(kPi * double(boundsRadius) * boundsRadius) : portalFlux;
  if (!portals.empty()) {
    double sum = 0;
    for (double w : PortalWeights(a, portals)) sum += w;
    return a.intensity * float(sum);
  }
  const double disc = kPi * double(boundsRadius) * boundsRadius;
  switch (kind) {
    case LightKind::kArea: return radiance * float(kPi * area);
    case LightKind::kPoint: return a.intensity * float(a.profile ? a.profile->Flux() : 4 * kPi);
    case LightKind::kSpot: return a.intensity * float(SpotSolidAngle(a.cosInner, a.cosOuter));
    case LightKind::kSun: return a.intensity * float(disc);
    case LightKind::kSky: return a.intensity * float(disc * (a.wholeSphere ? 4 : 2) * kPi);
  }
  return {};
}

const char* LightKindName(LightKind kind) {
  switch (kind) {
    case LightKind::kArea: return "area";
    case LightKind::kPoint: return "point";
    case LightKind::kSpot: return "spot";
    case LightKind::kSun: return "sun";
    case LightKind::kSky: return "sky";
  }
  return "?";
}

std::string LightName(const Scene& scene, const Light& light) {
  if (light.IsArea()) return scene.materials[scene.triangles[light.triangles.front()].material].name;
  return light.analytic.name.empty() ? LightKindName(light.kind) : light.analytic.name;
}

std::vector<Light> CollectLights(const Scene& scene, const SurfaceSet& surfaces) {
  std::vector<Light> lights;
  size_t emissive = 0;  // reserved: growing 100,000 lights by doubling moved each about twice
  for (const Surface& surface : surfaces.surfaces) emissive += scene.materials[surface.material].IsEmissive();
  lights.reserve(emissive + scene.analyticLights.size());
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
    const Surface& surface = surfaces.surfaces[s];
    const Material& material = scene.materials[surface.material];
    if (!material.IsEmissive()) continue;
    Light light{LightKind::kArea, s, material.emission, surface.triangles, {}, 0.0};
    for (uint32_t t : light.triangles) {
      light.area += scene.Area(t);
      light.triangleCdf.push_back(light.area);
    }
    for (double& c : light.triangleCdf) c /= light.area;
    light.triangleCdf.back() = 1.0;
    lights.push_back(std::move(light));
  }
  Point3 centre;
  float radius = 0;
  if (!scene.analyticLights.empty()) BoundingSphere(scene, centre, radius);
  for (const AnalyticLight& a : scene.analyticLights) {
    Light light;
    light.kind = a.kind;
    light.analytic = a;
    light.boundsCentre = centre, light.boundsRadius = radius;
    if (a.kind == LightKind::kSun || a.kind == LightKind::kSky) AimAtPortals(light, scene.portals);
    if (a.image) WeighSkyTexels(light);
    lights.push_back(std::move(light));
  }
  return lights;
}

}  // namespace pb
