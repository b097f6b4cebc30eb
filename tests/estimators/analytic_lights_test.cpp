// Point (plain and with an IES profile), spot, sun and sky lights (mesh/scene.h, mesh/lights.h): their photon
// emission against chi-square, their
// flux on a floor against the closed form (the photons' count on it is binomial, so its tolerance is), and their
// direct light sampled at points (estimators/light_sampler.h) against the closed forms
//   point: H = I cos(theta) / r^2;  spot: times glTF's falloff;  IES: I(gamma, C) from its table;
//   sun: H = E cos(theta);
//   sky over an open floor: H = pi L;  sky through a square window: Lambert's polygon formula with radiance L.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <memory>

#include "estimators/emission.h"
#include "estimators/light_sampler.h"
#include "estimators/sky_sampling.h"
#include "mesh/sky_texels.h"
#include "estimators/warps.h"
#include "mesh/ies_file.h"
#include "mesh/obj_loader.h"
#include "tests/chi2.h"
#include "tests/ies_text.h"
#include "tests/lambert.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

constexpr double kFloorHalf = 2;  // the floor spans [-2, 2] x [-2, 2] at y = 0, facing up

// A black floor, and optionally a black box over it open at the bottom (a ceiling 1 m up with a 0.5 x 0.5 m
// window over the origin and four walls), so that light reaches the floor under it only through the window.
Scene FloorScene(const std::string& name, bool room = false) {
  const std::string dir = test::TempDirectory(name);
  test::WriteText(dir + "/f.mtl", "newmtl black\nKd 0 0 0\n");
  std::string obj = "mtllib f.mtl\nusemtl black\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nf 1 4 3 2\n";
  if (room) {
    // The ceiling (facing down) as four panels around the window [-0.25, 0.25]^2, and walls down to the floor.
    obj += "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\nv -0.25 1 -0.25\nv 0.25 1 -0.25\nv 0.25 1 0.25\nv -0.25 1 0.25\n"
           "f 5 6 10 9\nf 6 7 11 10\nf 7 8 12 11\nf 8 5 9 12\n"
           "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
           "f 13 14 6 5\nf 14 15 7 6\nf 15 16 8 7\nf 16 13 5 8\n";
  }
  test::WriteText(dir + "/f.obj", obj);
  return LoadObj(dir + "/f.obj").scene;
}

AnalyticLight Point(Point3 at, float intensity) {
  AnalyticLight a;
  a.kind = LightKind::kPoint, a.position = at, a.intensity = {intensity, intensity, intensity};
  return a;
}
AnalyticLight Spot(Point3 at, float inner, float outer) {
  AnalyticLight a = Point(at, 2);
  a.kind = LightKind::kSpot, a.direction = {0, -1, 0};
  a.cosInner = std::cos(inner), a.cosOuter = std::cos(outer);
  return a;
}
AnalyticLight Sun(Vector3 direction, float irradiance) {
  AnalyticLight a;
  a.kind = LightKind::kSun, a.direction = Normalize(direction), a.intensity = {irradiance, irradiance, irradiance};
  return a;
}
AnalyticLight Sky(float radiance) {
  AnalyticLight a;
  a.kind = LightKind::kSky, a.intensity = {radiance, radiance, radiance};
  return a;
}

// An IES downlight 1 m over the floor's centre, aimed down, C = 0 along x, brighter toward C = 0 and down; its
// candela values are taken as W/sr (efficacy 1).
constexpr double kDeg = kPi / 180.0;
double Lamp(double gamma, double c) {
  return (50 + 400 * std::cos(gamma * kDeg) * (gamma <= 90)) * (1 + 0.6 * std::cos(c * kDeg));
}
AnalyticLight Ies(const std::string& name) {
  const std::string path = test::TempDirectory(name) + "/lamp.ies";
  test::WriteText(path, test::IesText({test::Degrees(0, 180, 10), test::Degrees(0, 330, 30), Lamp}));
  AnalyticLight a = Point({0, 1, 0}, 1);
  a.profile = std::make_shared<const IntensityProfile>(LoadIesFile(path));
  a.direction = {0, -1, 0}, a.c0 = {1, 0, 0};
  return a;
}

test::TracedScene WithLight(Scene scene, const AnalyticLight& light) {
  scene.analyticLights.push_back(light);
  return test::TracedScene(std::move(scene));
}

// The direct light at floor point (x, z), from many samples.
DirectSample DirectAt(const test::TracedScene& s, double x, double z, uint32_t samples = 1024) {
  const LightSampler sampler(s.scene, s.lights, *s.rays);
  Rng rng(5, uint64_t(std::fabs(x) * 1000 + std::fabs(z) * 10));
  return sampler.Irradiance({float(x), 0, float(z)}, {0, 1, 0}, samples, rng);
}

// The flux [W] that `photons` photons lay on the floor in their first hits, and its standard deviation: each
// photon carries its attenuation (its emission weight: 1 but for a sky image's) times Phi / N, so the flux is
// their mean times Phi, with the standard error of that mean (for equal weights, the binomial's).
struct Flux {
  double watts = 0, sigma = 0;
};
// Only hits within `half` of the floor's centre in x and z count (1: the room's floor, under its ceiling).
Flux FloorFlux(const test::TracedScene& s, uint64_t photons, float half = kFloorHalf) {
  const PhotonStore store = s.Trace(photons, 3);
  const Rgb phi = s.lights.back().Power();
  double sum = 0, sum2 = 0;
  for (const HitBlock& block : store.blocks)
    for (const PhotonHit& h : block) {
      const Point3 p = s.scene.PointAt(h.Triangle(), h.b1, h.b2);
      if (s.surfaces.surfaceOfTriangle[h.Triangle()] != 0 || std::fabs(p.x) > half || std::fabs(p.z) > half) continue;
      const double w = Luminance(h.attenuation * phi);
      sum += w, sum2 += w * w;
    }
  const double n = double(photons), mean = sum / n;
  return {sum / n, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n) + Luminance(phi) / n};
}

// FloorFlux against `expected` [W], within 5 standard deviations.
void ExpectFloorFlux(const test::TracedScene& s, double expected, uint64_t photons = 200'000, float half = kFloorHalf) {
  const Flux f = FloorFlux(s, photons, half);
  EXPECT_NEAR(f.watts, expected, 5 * f.sigma) << "of " << Luminance(s.lights.back().Power()) << " W";
}

// The room's window (FloorScene) as a portal: counter-clockwise seen from inside, so its inward normal is -y.
Scene WithPortal(Scene scene) {
  scene.portals.push_back({{-0.25f, 1, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}});
  return scene;
}

// A portal wound the other way (clockwise seen from inside, its normal out to the sky) is turned to face the room,
// with a warning naming it: the sun's photons still enter through it, every one (E A_window on the floor).
TEST(AnalyticLights, APortalWoundTheOtherWayIsTurnedIn) {
  Scene scene = FloorScene("portal-reversed", true);
  scene.portals.push_back({{-0.25f, 1, -0.25f}, {0, 0, 0.5f}, {0.5f, 0, 0}});
  ASSERT_GT(scene.portals[0].Inward().y, 0) << "wound to face out";
  const test::TracedScene s = WithLight(std::move(scene), Sun({0, -1, 0}, 3));
  EXPECT_LT(s.scene.portals[0].Inward().y, 0);
  bool warned = false;
  for (const std::string& w : s.warnings)
    warned |= w.find("warning: portal 0 faced out of the scene (its corners ran clockwise seen from inside: 0 of 16 "
                     "probes met geometry in front of it, 16 behind)") != std::string::npos;
  EXPECT_TRUE(warned);
  ExpectFloorFlux(s, 3 * 0.25, 200'000, 1);
  const test::TracedScene right = WithLight(WithPortal(FloorScene("portal-right", true)), Sun({0, -1, 0}, 3));
  for (const std::string& w : right.warnings) EXPECT_EQ(w.find("portal"), std::string::npos) << w;
}

TEST(AnalyticLights, PowerIsTheIntegralOfTheirEmission) {
  EXPECT_NEAR(SpotSolidAngle(1, -1), 4 * kPi / 3, 1e-9) << "inner 0, outer 180: the ramp integrates to a third";
  EXPECT_NEAR(SpotSolidAngle(0.5f, 0.5f), 2 * kPi * 0.5, 1e-6) << "a hard cone of half-angle 60 degrees";
  const test::TracedScene s = WithLight(FloorScene("power"), Point({0, 1, 0}, 3));
  EXPECT_NEAR(s.lights.back().Power().g, 12 * kPi, 1e-4);
}

TEST(AnalyticLights, PointAndSpotEmissionMatchTheirDistributions) {
  constexpr int kSamples = 200'000, kCells = 20;
  const test::TracedScene point = WithLight(FloorScene("chi-point"), Point({0, 1, 0}, 1));
  const float inner = 0.3f, outer = 0.6f;
  const test::TracedScene spot = WithLight(FloorScene("chi-spot"), Spot({0, 1, 0}, inner, outer));
  std::vector<double> zPoint(kCells, 0), zSpot(kCells, 0), phi(kCells, 0);
  const float co = std::cos(outer);
  for (int i = 0; i < kSamples; ++i) {
    Rng a(1, uint64_t(i)), b(2, uint64_t(i));
    const EmissionSample p = SampleEmission(point.scene, point.lights.back(), a);
    const EmissionSample q = SampleEmission(spot.scene, spot.lights.back(), b);
    ASSERT_FALSE(p.onSurface);
    ASSERT_EQ(p.position.y, 1.0f);
    zPoint[std::min(kCells - 1, int((p.direction.y + 1) / 2 * kCells))] += 1;
    phi[std::min(kCells - 1, int((std::atan2(p.direction.z, p.direction.x) / kPi + 1) / 2 * kCells))] += 1;
    const float c = -q.direction.y;  // the cosine from the spot's axis (down)
    ASSERT_GE(c, co - 1e-6f) << "no photon leaves beyond the outer cone";
    zSpot[std::min(kCells - 1, int((c - co) / (1 - co) * kCells))] += 1;
  }
  const test::Chi2Result pz = test::Chi2Test(zPoint, std::vector<double>(kCells, double(kSamples) / kCells));
  EXPECT_GT(pz.pValue, 1e-3) << pz.histograms;
  const test::Chi2Result pp = test::Chi2Test(phi, std::vector<double>(kCells, double(kSamples) / kCells));
  EXPECT_GT(pp.pValue, 1e-3) << pp.histograms;
  // The spot's expected share per cell of cos t: its falloff integrated over the cell, by the midpoint rule on a
  // fine grid.
  AnalyticLight s = Spot({0, 1, 0}, inner, outer);
  std::vector<double> expected(kCells, 0);
  double total = 0;
  for (int k = 0; k < kCells * 1000; ++k) {
    const double c = co + (1 - co) * (k + 0.5) / (kCells * 1000.0);
    expected[size_t(k / 1000)] += SpotFalloff(s, float(c));
    total += SpotFalloff(s, float(c));
  }
  for (double& e : expected) e *= kSamples / total;
  const test::Chi2Result sz = test::Chi2Test(zSpot, expected);
  EXPECT_GT(sz.pValue, 1e-3) << sz.histograms;
}

// Photons of an IES light leave in proportion to its intensity: chi-square over cells of (cos gamma, C) against
// the profile's intensity integrated over each cell by the midpoint rule; each sample's pdf is I / flux.
TEST(AnalyticLights, IesEmissionFollowsItsIntensity) {
  constexpr int kSamples = 300'000, kRows = 12, kColumns = 12, kFine = 40;
  const test::TracedScene ies = WithLight(FloorScene("chi-ies"), Ies("chi-ies-file"));
  const AnalyticLight& a = ies.lights.back().analytic;
  const Frame frame = ProfileFrame(a);
  std::vector<double> counts(kRows * kColumns, 0), expected(kRows * kColumns, 0);
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(7, uint64_t(i));
    const EmissionSample e = SampleEmission(ies.scene, ies.lights.back(), rng);
    const Vector3 local = frame.ToLocal(e.direction);
    const double c = std::atan2(double(local.y), double(local.x)) + (local.y < 0 ? 2 * kPi : 0);
    ASSERT_NEAR(e.pdfDirection, RelativeIntensity(a, e.direction) / a.profile->Flux(), 1e-3 * e.pdfDirection);
    const int row = std::min(kRows - 1, int((1 - local.z) / 2 * kRows)), column = std::min(kColumns - 1, int(c / (2 * kPi) * kColumns));
    counts[size_t(row * kColumns + column)] += 1;
  }
  double total = 0;
  for (int row = 0; row < kRows * kFine; ++row)
    for (int column = 0; column < kColumns * kFine; ++column) {
      const double z = 1 - 2 * (row + 0.5) / (kRows * kFine), c = 2 * kPi * (column + 0.5) / (kColumns * kFine);
      const double i = a.profile->Intensity(std::acos(z), c);  // the same solid angle in every fine cell
      expected[size_t(row / kFine * kColumns + column / kFine)] += i, total += i;
    }
  for (double& e : expected) e *= kSamples / total;
  const test::Chi2Result fit = test::Chi2Test(counts, expected);
  EXPECT_GT(fit.pValue, 1e-3) << fit.histograms;
  EXPECT_NEAR(Luminance(ies.lights.back().Power()), a.profile->Flux(), 1e-3 * a.profile->Flux());
}

TEST(AnalyticLights, SunAndSkyPhotonsLeaveDiscsOutsideTheScene) {
  constexpr int kSamples = 100'000, kCells = 20;
  const test::TracedScene sun = WithLight(FloorScene("chi-sun"), Sun({0.3f, -1, 0.2f}, 1));
  const test::TracedScene sky = WithLight(FloorScene("chi-sky"), Sky(1));
  const Light& s = sun.lights.back();
  std::vector<double> radius(kCells, 0), height(kCells, 0);
  for (int i = 0; i < kSamples; ++i) {
    Rng a(3, uint64_t(i)), b(4, uint64_t(i));
    const EmissionSample e = SampleEmission(sun.scene, s, a);
    EXPECT_EQ(e.direction.x, s.analytic.direction.x);
    const Vector3 offset = e.position - s.boundsCentre;
    ASSERT_NEAR(Dot(offset, e.direction), -s.boundsRadius, 1e-4f) << "on the plane R behind the centre";
    const Vector3 lateral = offset + e.direction * s.boundsRadius;
    radius[std::min(kCells - 1, int(LengthSquared(lateral) / (s.boundsRadius * s.boundsRadius) * kCells))] += 1;
    const EmissionSample k = SampleEmission(sky.scene, sky.lights.back(), b);
    ASSERT_LT(k.direction.y, 0) << "sky light travels down";
    height[std::min(kCells - 1, int(-k.direction.y * kCells))] += 1;
  }
  const std::vector<double> uniform(kCells, double(kSamples) / kCells);
  const test::Chi2Result r = test::Chi2Test(radius, uniform);
  EXPECT_GT(r.pValue, 1e-3) << "r^2 is uniform on a uniform disc\n" << r.histograms;
  const test::Chi2Result h = test::Chi2Test(height, uniform);
  EXPECT_GT(h.pValue, 1e-3) << "uniform directions: the height is uniform\n" << h.histograms;
}

TEST(AnalyticLights, PhotonFluxOnTheFloorIsTheClosedForm) {
  // A point light 1 m over the centre of a 4 x 4 m floor: I times the solid angle the floor subtends.
  const double a = kFloorHalf, h = 1;
  const double omega = 4 * std::atan(a * a / (h * std::sqrt(2 * a * a + h * h)));
  ExpectFloorFlux(WithLight(FloorScene("flux-point"), Point({0, 1, 0}, 1)), omega);
  // A sun at 60 degrees from the zenith: E A cos(theta).
  ExpectFloorFlux(WithLight(FloorScene("flux-sun"), Sun({std::sqrt(3.0f), -1, 0}, 2)), 2 * 16 * 0.5);
  // A sky over the open floor: pi L A.
  ExpectFloorFlux(WithLight(FloorScene("flux-sky"), Sky(0.5)), kPi * 0.5 * 16);
}

// An IES light's photons on the floor: the integral of I(gamma, C) cos(gamma) / r^2 over it, by the midpoint rule.
TEST(AnalyticLights, IesPhotonFluxOnTheFloorIsTheIntegralOfItsIrradiance) {
  const AnalyticLight ies = Ies("flux-ies-file");
  constexpr int kCells = 400;
  double expected = 0;
  const double step = 2 * kFloorHalf / kCells;
  for (int i = 0; i < kCells; ++i)
    for (int j = 0; j < kCells; ++j) {
      const double x = -kFloorHalf + (i + 0.5) * step, z = -kFloorHalf + (j + 0.5) * step, r2 = x * x + z * z + 1;
      const double c = std::atan2(-z, x);  // C = 90 degrees is -z: counter-clockwise seen from above
      expected += ies.profile->Intensity(std::acos(1 / std::sqrt(r2)), c < 0 ? c + 2 * kPi : c) / (r2 * std::sqrt(r2)) * step * step;
    }
  ExpectFloorFlux(WithLight(FloorScene("flux-ies"), ies), expected);
}

// Portals aim sun and sky photons at the window: the floor under it receives the same flux as from the bounding
// discs (the sun straight down: E A_window; the sky: the two runs agree within their noise), from far fewer photons
// lost outside, and the portal's sky directions are cosine-distributed about its inward normal.
TEST(AnalyticLights, PortalsAimSunAndSkyPhotonsAtTheWindow) {
  const test::TracedScene sunDiscs = WithLight(FloorScene("portal-sun-discs", true), Sun({0, -1, 0}, 3));
  const test::TracedScene sunPortal = WithLight(WithPortal(FloorScene("portal-sun", true)), Sun({0, -1, 0}, 3));
  ExpectFloorFlux(sunDiscs, 3 * 0.25, 200'000, 1);
  ExpectFloorFlux(sunPortal, 3 * 0.25, 200'000, 1);
  EXPECT_NEAR(Luminance(sunPortal.lights.back().Power()), 3 * 0.25, 1e-6) << "E A cos: every photon enters";
  const test::TracedScene skyDiscs = WithLight(FloorScene("portal-sky-discs", true), Sky(2));
  const test::TracedScene skyPortal = WithLight(WithPortal(FloorScene("portal-sky", true)), Sky(2));
  const Flux a = FloorFlux(skyDiscs, 400'000, 1), b = FloorFlux(skyPortal, 100'000, 1);
  EXPECT_NEAR(a.watts, b.watts, 5 * std::hypot(a.sigma, b.sigma));
  EXPECT_LT(b.sigma, a.sigma / 3) << "a quarter of the photons, and still far less noise";
  constexpr int kSamples = 100'000, kCells = 20;
  std::vector<double> cos2(kCells, 0);
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(9, uint64_t(i));
    const EmissionSample e = SampleEmission(skyPortal.scene, skyPortal.lights.back(), rng);
    ASSERT_TRUE(e.carriesLight);
    ASSERT_NEAR(e.position.y, 1, 1e-6);
    ASSERT_LE(std::fabs(e.position.x), 0.25f);
    cos2[std::min(kCells - 1, int(e.direction.y * e.direction.y * kCells))] += 1;
  }
  const test::Chi2Result lobe = test::Chi2Test(cos2, std::vector<double>(kCells, double(kSamples) / kCells));
  EXPECT_GT(lobe.pValue, 1e-3) << lobe.histograms;
}

TEST(AnalyticLights, SampledDirectLightIsTheClosedForm) {
  const test::TracedScene point = WithLight(FloorScene("direct-point"), Point({0.5f, 1.5f, 0}, 2));
  for (double x : {-1.5, 0.0, 0.5, 1.9}) {
    const double r2 = (x - 0.5) * (x - 0.5) + 1.5 * 1.5 + 0.25;
    EXPECT_NEAR(DirectAt(point, x, 0.5).irradiance.g, 2 * 1.5 / std::pow(r2, 1.5), 1e-5) << x;
  }
  // A spot 1 m up: full inside its inner cone (17.2 degrees), its falloff on the ramp, nothing beyond 34.4.
  const float inner = 0.3f, outer = 0.6f;
  const test::TracedScene spot = WithLight(FloorScene("direct-spot"), Spot({0, 1, 0}, inner, outer));
  for (double x : {0.0, 0.2, 0.45, 0.6, 0.8}) {
    const double r2 = x * x + 1, c = 1 / std::sqrt(r2);
    const double f = c >= std::cos(inner) ? 1 : std::pow(std::clamp((c - std::cos(outer)) / (std::cos(inner) - std::cos(outer)), 0.0, 1.0), 2);
    EXPECT_NEAR(DirectAt(spot, x, 0).irradiance.g, 2 * f * c / r2, 1e-5) << x;
  }
  // An IES light 1 m up: I(gamma, C) cos(gamma) / r^2 at floor points on its table's nodes, C = 90 degrees at -z.
  const test::TracedScene ies = WithLight(FloorScene("direct-ies"), Ies("direct-ies-file"));
  for (double gamma : {10.0, 30.0, 50.0}) {  // not 0: at the nadir C is undefined
    for (double c : {0.0, 90.0, 210.0, 330.0}) {
      const double r = std::tan(gamma * kDeg), r2 = r * r + 1;
      const double x = r * std::cos(c * kDeg), z = -r * std::sin(c * kDeg);
      EXPECT_NEAR(DirectAt(ies, x, z).irradiance.g, Lamp(gamma, c) * std::cos(gamma * kDeg) / r2, 1e-5 * Lamp(0, 0))
          << gamma << ", " << c;
    }
  }
  const test::TracedScene sun = WithLight(FloorScene("direct-sun"), Sun({1, -1, 0}, 3));
  EXPECT_NEAR(DirectAt(sun, 0.3, -0.7).irradiance.g, 3 / std::sqrt(2.0), 1e-5);
  EXPECT_EQ(DirectAt(sun, 0.3, -0.7).relativeNoise, 0) << "a sun's light is exact";
  // Under the room's ceiling the sun, straight down, reaches only the window's patch of floor.
  const test::TracedScene roomSun = WithLight(FloorScene("direct-sun-room", true), Sun({0, -1, 0}, 3));
  EXPECT_NEAR(DirectAt(roomSun, 0.1, 0.1).irradiance.g, 3, 1e-5);
  EXPECT_EQ(DirectAt(roomSun, 0.6, 0.1).irradiance.g, 0);
}

// Direct light at floor points under the room's window against Lambert's polygon formula with radiance L, within
// 5 predicted standard errors, whose mean square is honest; returns the relative noise under the window's centre.
double ExpectLambertUnderTheWindow(const test::TracedScene& room, double radiance, const std::string& what) {
  const std::vector<test::V3> window = {{-0.25, 1, -0.25}, {0.25, 1, -0.25}, {0.25, 1, 0.25}, {-0.25, 1, 0.25}};
  double z2 = 0, centre = 0;
  int n = 0;
  for (double x : {0.0, 0.2, 0.5}) {
    for (double z : {0.0, -0.3}) {
      const DirectSample s = DirectAt(room, x, z, 4096);
      const double exact = test::LambertPolygonIrradiance({x, 0, z}, {0, 1, 0}, window, radiance);
      const double sigma = s.relativeNoise * s.irradiance.g;
      EXPECT_GT(sigma, 0) << x << ", " << z << what;
      EXPECT_NEAR(s.irradiance.g, exact, 5 * sigma) << x << ", " << z << what;
      z2 += std::pow((s.irradiance.g - exact) / sigma, 2), ++n;
      if (x == 0 && z == 0) centre = s.relativeNoise;
    }
  }
  EXPECT_LT(z2 / n, 2.5) << "the predicted noise is honest" << what;
  return centre;
}

// The sky in the open is pi L, exactly; through the room's window Lambert's formula, and with the window a portal
// the directions aimed at it (estimators/sky_sampling.h) cut the noise under it by more than half.
TEST(AnalyticLights, SampledSkyIsPiLInTheOpenAndLambertThroughAWindow) {
  const test::TracedScene open = WithLight(FloorScene("sky-open"), Sky(0.5));
  const DirectSample e = DirectAt(open, 0.3, 0.2);
  EXPECT_NEAR(e.irradiance.g, kPi * 0.5, 1e-5) << "every ray leaves toward the sky";
  const double cosine = ExpectLambertUnderTheWindow(WithLight(FloorScene("sky-room", true), Sky(2)), 2, "");
  const double aimed = ExpectLambertUnderTheWindow(WithLight(WithPortal(FloorScene("sky-room-portal", true)), Sky(2)), 2,
                                                   " through the portal");
  EXPECT_LT(aimed, 0.5 * cosine);
}

// Skies with an image (mesh/sky_image.h, estimators/sky_sampling.h). An image 2h x h whose texel (x, y) is
// texel(x, y), looking toward -z at its centre.
std::shared_ptr<const SkyImage> ImageOf(int height, const std::function<Rgb(int, int)>& texel) {
  SkyImage image{"sky.exr", 2 * height, height, {}};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < 2 * height; ++x) image.texels.push_back(texel(x, y));
  return std::make_shared<const SkyImage>(std::move(image));
}
AnalyticLight ImageSky(std::shared_ptr<const SkyImage> image, bool wholeSphere = false) {
  AnalyticLight a = Sky(1);
  a.image = std::move(image), a.c0 = {0, 0, -1}, a.wholeSphere = wholeSphere;
  return a;
}
// A texel's solid angle above the horizon (or all of it, for the whole sphere) [sr].
double TexelSolidAngle(const SkyImage& image, int y, bool wholeSphere) {
  const double top = kPi * y / image.height, bottom = std::min(kPi * (y + 1) / image.height, wholeSphere ? kPi : kPi / 2);
  return bottom > top ? 2 * kPi / image.width * (std::cos(top) - std::cos(bottom)) : 0;
}
Rgb Colourful(int x, int y) { return {float(1 + x % 3), float(0.5 + (x * y) % 5), float(0.2 + y % 2)}; }

// The image's layout: its centre column at the horizon looks along the front (-z), three quarters across to the
// right of it (+x), the top row at the zenith; each direction drawn has pdf L_lum / sum L_lum Omega, and they fall
// on the texels in proportion to L_lum Omega (chi-square over every texel), for a sky above the horizon and for
// the whole sphere.
TEST(AnalyticLights, SkyImageDirectionsFollowItsLuminance) {
  const Frame frame = SkyFrame(ImageSky(ImageOf(8, Colourful)));
  const Vector3 front = SkyDirection(frame, kPi / 2, kPi), right = SkyDirection(frame, kPi / 2, 1.5 * kPi);
  EXPECT_NEAR(front.z, -1, 1e-6);
  EXPECT_NEAR(right.x, 1, 1e-6);
  EXPECT_NEAR(SkyDirection(frame, 0, 1).y, 1, 1e-6);
  for (bool whole : {false, true}) {
    const test::TracedScene s = WithLight(FloorScene(whole ? "chi-sky-image-whole" : "chi-sky-image"), ImageSky(ImageOf(8, Colourful), whole));
    const Light& light = s.lights.back();
    const SkyImage& image = *light.analytic.image;
    constexpr int kSamples = 200'000;
    std::vector<double> counts(image.texels.size(), 0), expected(image.texels.size(), 0);
    double total = 0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        total += expected[size_t(y * image.width + x)] = Luminance(image.Texel(x, y)) * TexelSolidAngle(image, y, whole);
    for (int i = 0; i < kSamples; ++i) {
      Rng rng(11, uint64_t(i));
      const std::optional<SkySample> d = SampleSkyImage(light, rng.Uniform2());
      ASSERT_TRUE(d.has_value());
      ASSERT_TRUE(whole || d->from.y >= 0) << "none from below the horizon";
      const Vector3 local = SkyFrame(light.analytic).ToLocal(d->from);
      const double phi = std::atan2(-double(local.y), -double(local.x)) + (local.y > 0 ? 2 * kPi : 0);
      const int x = std::min(image.width - 1, int(phi / (2 * kPi) * image.width));
      const int y = std::min(image.height - 1, int(std::acos(std::clamp(double(local.z), -1.0, 1.0)) / kPi * image.height));
      ASSERT_NEAR(d->pdf, Luminance(image.Texel(x, y)) / total, 1e-4 * d->pdf) << x << ", " << y;
      counts[size_t(y * image.width + x)] += 1;
    }
    for (double& e : expected) e *= kSamples / total;
    const test::Chi2Result fit = test::Chi2Test(counts, expected);
    EXPECT_GT(fit.pValue, 1e-3) << fit.histograms;
  }
}

// Photons drawn by luminance carry their colour as a weight: in every channel, the weights of the photons from a
// part of the sky (its columns 2, 5, 8, ..., reddest) add up to that part's share of the channel's flux, and all
// of them to 1 (mean over photons, within 5 standard errors).
TEST(AnalyticLights, SkyImagePhotonsCarryEachChannelsFlux) {
  const test::TracedScene s = WithLight(FloorScene("sky-image-weights"), ImageSky(ImageOf(8, Colourful)));
  const Light& light = s.lights.back();
  const SkyImage& image = *light.analytic.image;
  const auto inPart = [&](int x) { return x % 3 == 2; };
  std::array<double, 3> part{}, whole{};
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const Rgb l = image.Texel(x, y) * float(TexelSolidAngle(image, y, false));
      for (size_t k = 0; k < 3; ++k) (inPart(x) ? part : whole)[k] += k == 0 ? l.r : k == 1 ? l.g : l.b;
    }
  constexpr int kSamples = 100'000;
  std::array<double, 3> sum{}, sum2{}, all{};
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(12, uint64_t(i));
    const EmissionSample e = SampleEmission(s.scene, light, rng);
    const Vector3 local = SkyFrame(light.analytic).ToLocal(-e.direction);
    const double phi = std::atan2(-double(local.y), -double(local.x)) + (local.y > 0 ? 2 * kPi : 0);
    const bool in = inPart(std::min(image.width - 1, int(phi / (2 * kPi) * image.width)));
    const std::array<double, 3> w{e.weight.r, e.weight.g, e.weight.b};
    for (size_t k = 0; k < 3; ++k) sum[k] += in * w[k], sum2[k] += in * w[k] * w[k], all[k] += w[k];
  }
  for (size_t k = 0; k < 3; ++k) {
    const double mean = sum[k] / kSamples, sigma = std::sqrt((sum2[k] / kSamples - mean * mean) / kSamples);
    EXPECT_NEAR(mean, part[k] / (part[k] + whole[k]), 5 * sigma) << "channel " << k;
    EXPECT_NEAR(all[k] / kSamples, 1, 0.02) << "channel " << k;
  }
}

// A grey sky brighter toward the zenith, L = 1 + 2 cos(theta) at each row's centre, over an open floor: H is the
// sum over rows of L pi (sin^2 theta_bottom - sin^2 theta_top), both sampled at points (within 5 of their
// predicted standard errors) and by photons (the floor's flux, H A).
TEST(AnalyticLights, ASkyImageLightsAnOpenFloorByItsIntegral) {
  const auto image = ImageOf(32, [](int, int y) {
    const float l = 1 + 2 * float(std::cos(kPi * (y + 0.5) / 32));
    return Rgb{l, l, l};
  });
  double exact = 0;
  for (int y = 0; y < 16; ++y) {
    const double t = kPi * y / 32, b = kPi * (y + 1) / 32;
    exact += Luminance(image->Texel(0, y)) * kPi * (std::pow(std::sin(b), 2) - std::pow(std::sin(t), 2));
  }
  const test::TracedScene s = WithLight(FloorScene("sky-image-open"), ImageSky(image));
  for (double x : {0.0, 0.7, -1.3}) {
    const DirectSample d = DirectAt(s, x, 0.4, 256);
    ASSERT_GT(d.relativeNoise, 0);
    EXPECT_NEAR(d.irradiance.g, exact, 5 * d.relativeNoise * d.irradiance.g) << x;
    EXPECT_LT(d.relativeNoise, 0.02) << "cosine and image directions together";
  }
  ExpectFloorFlux(s, exact * 16);
}

// One bright texel is a sun of the same solid angle: an image black but for the texel 45 degrees from the zenith
// (V = 1000 over Omega) lights an open floor as a sun of E = V Omega from the texel's centre does, at points
// (within the texel's own extent, 0.7 degrees: 0.5%) and by photons (within their binomial noise).
TEST(AnalyticLights, OneBrightTexelIsTheSun) {
  constexpr int kHeight = 256, kX = 320, kY = 64;
  const auto image = ImageOf(kHeight, [](int x, int y) { return x == kX && y == kY ? Rgb{1000, 1000, 1000} : Rgb{}; });
  const AnalyticLight sky = ImageSky(image);
  const Vector3 centre = SkyDirection(SkyFrame(sky), kPi * (kY + 0.5) / kHeight, 2 * kPi * (kX + 0.5) / (2 * kHeight));
  const double e = 1000 * TexelSolidAngle(*image, kY, false);
  const test::TracedScene bySky = WithLight(FloorScene("sky-image-texel"), sky);
  const test::TracedScene bySun = WithLight(FloorScene("sky-image-sun"), Sun(-centre, float(e)));
  for (double x : {0.0, 1.2}) {
    const double sun = DirectAt(bySun, x, -0.5).irradiance.g;
    EXPECT_NEAR(sun, e * centre.y, 1e-5 * sun);
    EXPECT_NEAR(DirectAt(bySky, x, -0.5, 64).irradiance.g, sun, 5e-3 * sun) << x;
  }
  const Flux a = FloorFlux(bySky, 200'000), b = FloorFlux(bySun, 200'000);
  EXPECT_NEAR(a.watts, b.watts, 5 * std::hypot(a.sigma, b.sigma));
}

// Through a portal, an image sky's photons start on the window and are drawn by the light each texel sends in
// (mesh/sky_texels.h): the floor under the room's window receives what the bounding discs' photons bring it (a sky
// brighter toward the zenith, and one bright texel, which then is the sun E A cos through the window), from a
// quarter of the photons, with less noise.
TEST(AnalyticLights, PortalsAimSkyImagePhotonsAtTheWindow) {
  const auto zenith = ImageOf(16, [](int x, int y) {
    const float l = 1 + 2 * float(std::cos(kPi * (y + 0.5) / 16));
    return Rgb{l, l * (x % 2 ? 0.5f : 1.0f), l};
  });
  const Flux discs = FloorFlux(WithLight(FloorScene("portal-image-discs", true), ImageSky(zenith)), 400'000, 1);
  const Flux portal = FloorFlux(WithLight(WithPortal(FloorScene("portal-image", true)), ImageSky(zenith)), 100'000, 1);
  EXPECT_NEAR(portal.watts, discs.watts, 5 * std::hypot(discs.sigma, portal.sigma));
  EXPECT_LT(portal.sigma, discs.sigma / 3);
  constexpr int kHeight = 128, kX = 100, kY = 20;
  const auto texel = ImageOf(kHeight, [](int x, int y) { return x == kX && y == kY ? Rgb{1000, 1000, 1000} : Rgb{}; });
  const AnalyticLight sky = ImageSky(texel);
  const TexelSpan span = SpanOf(sky, kX, kY);
  const Vector3 centre = SkyDirection(SkyFrame(sky), 0.5 * (span.theta0 + span.theta1), 0.5 * (span.phi0 + span.phi1));
  const test::TracedScene s = WithLight(WithPortal(FloorScene("portal-image-texel", true)), sky);
  const double expected = 1000 * TexelCosineSolidAngle(sky, kX, kY, {0, -1, 0}) * 0.25;
  EXPECT_NEAR(Luminance(s.lights.back().Power()), expected, 1e-4 * expected) << "its flux: L C A";
  EXPECT_NEAR(expected, 1000 * span.SolidAngle() * centre.y * 0.25, 2e-3 * expected) << "C is Omega cos, nearly";
  const double onFloor = FloorFlux(s, 100'000, 1).watts;
  EXPECT_NEAR(onFloor, expected, 0.02 * expected) << "every photon through the window reaches the floor under it";
}

// Direct light from an image sky through the room's window: an image of L = 2 above the horizon (and a bright
// texel below it, which a sky above the horizon does not show, so that the image is no constant sky) gives
// Lambert's polygon formula with radiance 2 under the window, within 5 predicted standard errors, with the portal
// given or not; with it, the directions toward it cut the noise under the window by more than half. Those
// directions' pdf is checked by its measure: the mean of 1 / pdf is the window's solid angle.
TEST(AnalyticLights, SampledSkyImageThroughAWindowIsLambert) {
  const auto image = ImageOf(16, [](int x, int y) { return y >= 8 && x == 3 ? Rgb{50, 50, 50} : Rgb{2, 2, 2}; });
  const test::TracedScene withPortal = WithLight(WithPortal(FloorScene("sky-image-portal-pdf", true)), ImageSky(image));
  const Point3 at{0.1f, 0, 0.2f};
  double inverse = 0, inverse2 = 0, omega = 0;
  constexpr int kDraws = 20'000, kGrid = 400;
  for (int i = 0; i < kDraws; ++i) {
    Rng rng(13, uint64_t(i));
    const std::optional<SkySample> d = SampleTowardPortals(withPortal.lights.back(), at, rng.Uniform2());
    ASSERT_TRUE(d.has_value());
    inverse += 1.0 / d->pdf / kDraws, inverse2 += 1.0 / (double(d->pdf) * d->pdf) / kDraws;
  }
  const double sigma = std::sqrt((inverse2 - inverse * inverse) / kDraws);
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const double x = -0.25 + 0.5 * (i + 0.5) / kGrid - 0.1, z = -0.25 + 0.5 * (j + 0.5) / kGrid - 0.2;
      omega += 1 / std::pow(x * x + z * z + 1, 1.5) * 0.25 / (kGrid * kGrid);  // cos / d^2 dA, cos = 1 / d
    }
  EXPECT_NEAR(inverse, omega, 5 * sigma) << "uniform on the window: 1 / pdf = A cos / d^2";
  const double anywhere = ExpectLambertUnderTheWindow(WithLight(FloorScene("sky-image-window", true), ImageSky(image)), 2, "");
  const double aimed = ExpectLambertUnderTheWindow(
      WithLight(WithPortal(FloorScene("sky-image-window-portal", true)), ImageSky(image)), 2, " through the portal");
  EXPECT_LT(aimed, 0.5 * anywhere);
}

}  // namespace
}  // namespace pb
