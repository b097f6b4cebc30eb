// Where the light comes from (--sh, estimators/incident_moments.h), on a closed form: a 1 x 1 m square light of
// radiance L = 1 W/(m^2 sr), 1 m above a black 4 x 4 m floor. At a floor point x, the light's irradiance vector is
// Arvo's (1995) closed form, the vector whose normal component is Lambert's polygon formula:
//   D(x) = (L / 2) sum_i beta_i unit(R_i x R_{i+1})   (oriented toward the light),
// pointing at the light's solid-angle centroid; E(n) = D . n for every normal n whose hemisphere holds the whole
// light. The baked SH must give D's direction, E at the vertex normal and E at a tilted normal, within the noise:
//   photons only (--direct photons, 1M photons, h 0.1 m): H's relative noise at the floor's centre is
//     sqrt(phi R(K) / (E h^2)) = 0.6%, and 2.4% at the interior's edge 1.5 m out, where E is 1/16 of it; the
//     tangential part of D, each photon weighted by tan(theta) (below 0.7 at the centre, 1 to 3 at the edge), is
//     about as noisy relative to |D|, so its direction errs by about 0.3 degrees at the centre and 1.5 at the edge
//     (measured: 0.3 on average, 1.2 at worst): within the issue's 10 at every vertex, 1 on average;
//   shadow rays (the default): D from the 64 stratified rays' directions (measured: 0.16 on average, 0.9 at
//     worst): within 3 at every vertex, 0.5 on average.
// E at the tilted normal, averaged over 868 vertices, is then within 1% (photons) and 0.5% (rays); measured 0.1%
// and 0.005%.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "baker/bake.h"
#include "baker/files/image_io.h"
#include "estimators/incident_moments.h"
#include "tests/lambert.h"
#include "tests/ply_reader.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

using test::V3;

const std::vector<V3> kLight = {{-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5}};

// Arvo's irradiance vector of the light at x, pointing toward it.
V3 IrradianceVector(V3 x) {
  V3 d{0, 0, 0};
  for (size_t i = 0; i < kLight.size(); ++i) {
    const V3 a = test::Unit(test::Sub(kLight[i], x)), b = test::Unit(test::Sub(kLight[(i + 1) % kLight.size()], x));
    const double beta = std::acos(std::clamp(test::DotD(a, b), -1.0, 1.0));
    const V3 u = test::Unit(test::CrossD(a, b));
    d = {d.x + 0.5 * beta * u.x, d.y + 0.5 * beta * u.y, d.z + 0.5 * beta * u.z};
  }
  return d.y < 0 ? V3{-d.x, -d.y, -d.z} : d;  // the corners' winding decides the sign
}

double AngleDegrees(V3 a, V3 b) {
  return std::acos(std::clamp(test::DotD(test::Unit(a), test::Unit(b)), -1.0, 1.0)) * 180 / M_PI;
}

// Channel g's SH of vertex v: L00, L1x, L1y, L1z.
ShL1 ShOf(const test::PlyData& ply, size_t v) {
  ShL1 sh;
  for (int k = 0; k < 4; ++k) {
    const std::string suffix = std::to_string(k);
    sh.c[size_t(k)] = {float(ply.vertex.at("sh_r" + suffix)[v]), float(ply.vertex.at("sh_g" + suffix)[v]),
                       float(ply.vertex.at("sh_b" + suffix)[v])};
  }
  return sh;
}

// Bakes `scene` with --sh, 1M photons and h [m] into dir/out.ply; its report into `report` when given.
test::PlyData BakeWithSh(const std::string& scene, const std::string& dir, float h, DirectLight direct,
                         BakeReport* report = nullptr, bool stored = false, bool maps = false) {
  BakeOptions o;
  if (maps) o.mapsDirectory = dir + "/maps", o.texel = 0.1f;
  if (stored) o.savePhotonsPath = dir + "/photons";  // which keeps every photon stored, not binned while traced
  o.scenePath = scene;
  o.outputPath = dir + "/out.ply";
  o.photons = 1'000'000;
  o.estimator.bandwidth = h;
  o.direct.mode = direct;
  o.sh = true;
  o.quiet = true;
  const BakeReport r = Bake(o, Log(true));
  if (report != nullptr) *report = r;
  return test::ReadPly(o.outputPath);
}

test::PlyData BakeSquareLight(const std::string& name, DirectLight direct, BakeReport* report = nullptr,
                              bool stored = false) {
  const std::string dir = test::TempDirectory(name);
  return BakeWithSh(test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 40), dir, 0.1f, direct, report, stored);
}

// The SH of the interior floor vertices against the closed forms: direction of L1 (every vertex and the mean), E
// at the floor's normal, and E at a normal tilted 30 degrees about z, where the light lies wholly above the
// tilted plane (elsewhere D . n drops the light below it: the SH's own truncation, docs/bake.md).
void ExpectClosedForms(const test::PlyData& ply, double worstDegrees, double meanDegrees, double tiltedError) {
  const V3 tilted{std::sin(M_PI / 6), std::cos(M_PI / 6), 0};
  double sumAngle = 0, sumTilted = 0, sumNormal = 0;
  int interior = 0, aboveTilt = 0;
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    const V3 x{ply.vertex.at("x")[v], ply.vertex.at("y")[v], ply.vertex.at("z")[v]};
    if (x.y != 0.0 || std::fabs(x.x) > 1.5 || std::fabs(x.z) > 1.5) continue;
    const ShL1 sh = ShOf(ply, v);
    const V3 l1{sh.c[1].g, sh.c[2].g, sh.c[3].g};
    const double angle = AngleDegrees(l1, IrradianceVector(x));
    EXPECT_LT(angle, worstDegrees) << "vertex at (" << x.x << ", " << x.z << ")";
    sumAngle += angle;
    const double h = ply.vertex.at("irradiance_g")[v];
    sumNormal += ShIrradiance(sh, {0, 1, 0}).g / h - 1;
    ++interior;
    bool whole = true;
    for (const V3& corner : kLight) whole = whole && test::DotD(test::Sub(corner, x), tilted) > 0;
    if (!whole) continue;
    const double exact = test::LambertPolygonIrradiance(x, tilted, kLight, 1.0);
    sumTilted += ShIrradiance(sh, {float(tilted.x), float(tilted.y), 0}).g / exact - 1;
    ++aboveTilt;
  }


  ASSERT_GT(interior, 600);
  ASSERT_GT(aboveTilt, 300);
  EXPECT_LT(sumAngle / interior, meanDegrees);
  EXPECT_NEAR(sumNormal / interior, 0, 1e-5) << "E at the vertex normal is H itself";
  EXPECT_NEAR(sumTilted / aboveTilt, 0, tiltedError) << "mean relative error of E at the tilted normal";
}

TEST(Directional, PhotonsPointAtTheLightsCentroid) {
  ExpectClosedForms(BakeSquareLight("sh-photons", DirectLight::kPhotons), 10, 1, 0.01);
}

// The photons' weighted fluxes binned as they are traced (the default here, and bake-mpi's way) give the moments of
// the same photons stored: the node sums' fixed point rounds each share to 1.5e-8 of the brightest photon's
// weighted flux, far below 1e-5 of any vertex's.
TEST(Directional, BinnedWhileTracedAsStored) {
  BakeReport binned;
  const test::PlyData a = BakeSquareLight("sh-binned", DirectLight::kPhotons, &binned);
  const test::PlyData b = BakeSquareLight("sh-stored", DirectLight::kPhotons, nullptr, true);
  ASSERT_LT(binned.storedHits, binned.trace.hits) << "photons binned while traced";
  ASSERT_EQ(a.VertexCount(), b.VertexCount());
  double largest = 0, difference = 0;
  for (const std::string c : {"r", "g", "b"})
    for (int k = 0; k < 4; ++k)
      for (size_t v = 0; v < a.VertexCount(); ++v) {
        const double x = a.vertex.at("sh_" + c + std::to_string(k))[v], y = b.vertex.at("sh_" + c + std::to_string(k))[v];
        largest = std::max(largest, std::fabs(y)), difference = std::max(difference, std::fabs(x - y));
      }
  EXPECT_GT(largest, 0.1);
  EXPECT_LT(difference, 1e-5 * largest);
}

// A map's texels carry the SH as vertices do: on the floor's map, the interior texels' L1 points at the light's
// centroid (the photons alone, as above) and E at the floor's normal is the texel's H.
TEST(Directional, MapsCarryTheShToo) {
  const std::string dir = test::TempDirectory("sh-maps");
  BakeWithSh(test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 40), dir, 0.1f, DirectLight::kPhotons,
             nullptr, false, true);
  int checked = 0;
  double sumAngle = 0;
  for (const auto& file : std::filesystem::directory_iterator(dir + "/maps")) {
    std::vector<std::pair<std::string, std::string>> attributes;
    std::vector<float> coverage;
    std::vector<ExrChannel> sh;
    for (const char c : {'r', 'g', 'b'})
      for (int k = 0; k < 4; ++k) sh.push_back({std::string("sh_") + c + std::to_string(k), {}});
    const Image image = ReadExr(file.path().string(), &attributes, &coverage, &sh);
    std::map<std::string, std::string> a(attributes.begin(), attributes.end());
    double ox, oy, oz, ux, uy, uz, vx, vy, vz, u0, v0;
    std::istringstream(a.at("chart_origin_m")) >> ox >> oy >> oz;
    std::istringstream(a.at("chart_u_axis")) >> ux >> uy >> uz;
    std::istringstream(a.at("chart_v_axis")) >> vx >> vy >> vz;
    std::istringstream(a.at("uv_corner_m")) >> u0 >> v0;
    if (oy != 0 || uy != 0 || vy != 0) continue;  // the light's map
    for (int j = 0; j < image.height; ++j)
      for (int i = 0; i < image.width; ++i) {
        const size_t k = size_t(j) * size_t(image.width) + size_t(i);
        const double u = u0 + (i + 0.5) * 0.1, v = v0 + (j + 0.5) * 0.1;
        const V3 x{ox + u * ux + v * vx, 0, oz + u * uz + v * vz};
        if (coverage[k] < 0.999 || std::fabs(x.x) > 1.5 || std::fabs(x.z) > 1.5) continue;
        const V3 l1{sh[5].values[k], sh[6].values[k], sh[7].values[k]};
        const double angle = AngleDegrees(l1, IrradianceVector(x));
        EXPECT_LT(angle, 10) << "texel at (" << x.x << ", " << x.z << ")";
        sumAngle += angle;
        EXPECT_NEAR(std::sqrt(4 * M_PI / 3) * l1.y, image.At(i, j).g, 1e-5 * image.At(i, j).g);
        ++checked;
      }
  }
  ASSERT_EQ(checked, 900);
  EXPECT_LT(sumAngle / checked, 1);
}

// The predicted noise of each vertex's direction against its actual error on the closed form, and the same for H:
// over the interior vertices, the RMS of the predicted standard errors over the RMS of the actual errors (the
// angle between L1 and Arvo's vector; H against Lambert's formula).
struct NoiseRatios {
  double direction, irradiance;  // predicted / actual
};
NoiseRatios PredictedOverActual(DirectLight direct, const std::string& name) {
  const std::string dir = test::TempDirectory(name);
  BakeOptions o;
  o.scenePath = test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 40);
  o.outputPath = dir + "/out.ply";
  o.photons = 1'000'000;
  o.estimator.bandwidth = 0.1f;
  o.direct.mode = direct;
  o.sh = true;
  o.quiet = true;
  const BakeResult r = BakeMesh(o, Log(true));
  double predicted = 0, actual = 0, predictedH = 0, actualH = 0;
  int n = 0;
  for (size_t v = 0; v < r.mesh.mesh.VertexCount(); ++v) {
    const Point3 p = r.mesh.mesh.positions[v];
    if (p.y != 0 || std::fabs(p.x) > 1.5f || std::fabs(p.z) > 1.5f) continue;
    const ShL1& sh = r.mesh.sh[v];
    const V3 l1{Luminance(sh.c[1]), Luminance(sh.c[2]), Luminance(sh.c[3])};
    actual += std::pow(AngleDegrees(l1, IrradianceVector({p.x, p.y, p.z})) * M_PI / 180, 2);
    predicted += std::pow(r.mesh.directionNoise[v], 2);
    const double exact = test::LambertPolygonIrradiance({p.x, 0, p.z}, {0, 1, 0}, kLight, 1.0);
    actualH += std::pow(Luminance(r.mesh.irradiance[v]) / exact - 1, 2);
    predictedH += std::pow(r.mesh.irradianceNoise[v], 2);
    ++n;
  }
  EXPECT_GT(n, 600);
  std::printf("%s: direction %.3f degrees predicted, %.3f actual; H %.3f%% predicted, %.3f%% actual (RMS)\n", name.c_str(),
              std::sqrt(predicted / n) * 180 / M_PI, std::sqrt(actual / n) * 180 / M_PI, 100 * std::sqrt(predictedH / n),
              100 * std::sqrt(actualH / n));
  return {std::sqrt(predicted / actual), std::sqrt(predictedH / actualH)};
}

// Photons: the prediction is the Poisson variance (measured: 0.364 degrees RMS predicted, 0.369 actual). Shadow
// rays: as conservative as H's own prediction, which the strata's second differences make (measured: 0.30 against
// 0.20 degrees, and H's 0.26% against 0.17%; with pairs of strata 0.33 degrees and 0.30%).
TEST(Directional, DirectionNoiseIsPredictedAsHs) {
  const NoiseRatios photons = PredictedOverActual(DirectLight::kPhotons, "sh-noise-photons");
  EXPECT_NEAR(photons.direction, 1, 0.25);
  EXPECT_NEAR(photons.irradiance, 1, 0.25);
  const NoiseRatios rays = PredictedOverActual(DirectLight::kSampled, "sh-noise-rays");
  EXPECT_NEAR(rays.direction / rays.irradiance, 1, 0.3);
  EXPECT_GE(rays.direction, 1) << "conservative, as H's";
}

TEST(Directional, ShadowRaysPointAtTheLightsCentroid) {
  ExpectClosedForms(BakeSquareLight("sh-sampled", DirectLight::kSampled), 3, 0.5, 0.005);
}

// The box (data/box), whose light is mostly interreflected off its walls, baked with --sh twice.
BakeOptions BoxWithSh(const std::string& name, uint64_t photons) {
  BakeOptions o;
  o.scenePath = PB_SOURCE_DIR "/data/box/box.obj";
  o.outputPath = test::TempDirectory(name) + "/out.ply";
  o.photons = photons;
  o.sh = true;
  o.quiet = true;
  return o;
}

test::PlyData BakeBox(const std::string& name, uint32_t referencePaths, unsigned threads, uint64_t photons,
                      BakeReport* report = nullptr) {
  BakeOptions o = BoxWithSh(name, photons);
  o.referencePaths = referencePaths;
  o.threads = threads;
  const BakeReport r = Bake(o, Log(true));
  if (report != nullptr) *report = r;
  return test::ReadPly(o.outputPath);
}

// Channel g's L1 at vertex v with its component along the vertex normal removed, and its L00.
V3 Tangential(const test::PlyData& ply, size_t v) {
  const V3 l{ply.vertex.at("sh_g1")[v], ply.vertex.at("sh_g2")[v], ply.vertex.at("sh_g3")[v]};
  const V3 n{ply.vertex.at("nx")[v], ply.vertex.at("ny")[v], ply.vertex.at("nz")[v]};
  const double along = test::DotD(l, n);
  return {l.x - along * n.x, l.y - along * n.y, l.z - along * n.z};
}

// The photons' moments of interreflected light (and the shadow rays' of the direct) against a path tracer's
// (--reference, each path's first direction), vertex by vertex, on the box. Both are noisy: with 1M photons and
// 512 paths, H differs by 4.6% on average (|dH| / H over the vertices, three seeds: 4.4-4.6%) and the tangential
// part of L1 by 19.5% (19.3-19.6%) of its own size; with the photons' x axis flipped, 45%. F, summed over the
// box, agrees within 0.9%.
TEST(Directional, PhotonsAgreeWithGatheredPathsOnTheBox) {
  const test::PlyData photons = BakeBox("sh-box-photons", 0, 0, 1'000'000), paths = BakeBox("sh-box-paths", 512, 0, 1);
  ASSERT_EQ(photons.VertexCount(), paths.VertexCount());
  double difference = 0, size = 0, scalarPhotons = 0, scalarPaths = 0;
  for (size_t v = 0; v < photons.VertexCount(); ++v) {
    const V3 a = Tangential(photons, v), b = Tangential(paths, v);
    difference += std::sqrt(test::DotD(test::Sub(a, b), test::Sub(a, b)));
    size += std::sqrt(test::DotD(b, b));
    scalarPhotons += photons.vertex.at("sh_g0")[v], scalarPaths += paths.vertex.at("sh_g0")[v];
  }
  EXPECT_LT(difference / size, 0.3);
  EXPECT_NEAR(scalarPhotons / scalarPaths, 1, 0.03);
}

TEST(Directional, SameBytesOnAnyThreadCount) {
  BakeReport report;
  const test::PlyData one = BakeBox("sh-threads-1", 0, 1, 100'000, &report), three = BakeBox("sh-threads-3", 0, 3, 100'000);
  // The report's 95th percentile of the direction noise: a few degrees at 100,000 photons.
  EXPECT_GT(report.directionNoise * 180 / M_PI, 0.1);
  EXPECT_LT(report.directionNoise * 180 / M_PI, 30);
  for (const std::string c : {"r", "g", "b"})
    for (int k = 0; k < 4; ++k) {
      const std::string name = "sh_" + c + std::to_string(k);
      EXPECT_EQ(one.vertex.at(name), three.vertex.at(name)) << name;
    }
}

// The truncation the docs state, under a sky of radiance 1 over an open black floor (light spread evenly over the
// hemisphere: H = pi, F = 2 pi, D = pi n): at a normal tilted 60 degrees, E = D . n reads pi cos 60 = pi / 2 where
// the truth is pi (1 + cos 60) / 2; F reads 1.98 pi, grazing light floored at kGrazingCosine (the mean of
// 1 / max(c, 0.02) over cosine-distributed c is 2 - 0.02). Averaged over the floor's 441 vertices, the shadow
// rays' noise (256 rays) and the photons' (1M photons, h 0.2 m: 1.2% per vertex) fall below 0.5% (measured: E at
// 60 degrees 0.4988 and 0.4991 of H, F 1.989 and 1.982 of H).
void ExpectEvenSky(DirectLight direct, const std::string& name) {
  const std::string dir = test::TempDirectory(name);
  test::WriteText(dir + "/f.mtl", "newmtl black\nKd 0 0 0\n");
  std::string obj = "mtllib f.mtl\nusemtl black\n";  // a 2 x 2 m floor of 20 x 20 quads, facing up
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) obj += "v " + std::to_string(-1 + 0.1 * i) + " 0 " + std::to_string(-1 + 0.1 * j) + "\n";
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) {
      const int a = j * 21 + i + 1;
      obj += "f " + std::to_string(a) + " " + std::to_string(a + 21) + " " + std::to_string(a + 22) + " " +
             std::to_string(a + 1) + "\n";
    }
  test::WriteText(dir + "/f.obj", obj);
  test::WriteText(dir + "/f.lights.json", R"({"lights": [{"type": "sky", "radiance_W_m2_sr": 1}]})");
  const test::PlyData ply = BakeWithSh(dir + "/f.obj", dir, 0.2f, direct);
  ASSERT_EQ(ply.VertexCount(), 441u);
  double tilted = 0, scalar = 0, alongX = 0, alongZ = 0, count = 0;
  const float s60 = std::sin(float(M_PI / 3)), c60 = 0.5f;
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    const ShL1 sh = ShOf(ply, v);
    const double h = ply.vertex.at("irradiance_g")[v];
    tilted += ShIrradiance(sh, {s60, c60, 0}).g / h;
    scalar += sh.c[0].g / kShY00 / h;
    alongX += sh.c[1].g / sh.c[2].g, alongZ += sh.c[3].g / sh.c[2].g;
    ++count;
  }
  EXPECT_NEAR(tilted / count, 0.5, 0.005) << "D . n at 60 degrees: cos 60 of H (the truth: 0.75)";
  EXPECT_NEAR(scalar / count, 2 - kGrazingCosine, 0.01) << "F / H";
  // Per vertex, L1's tangential part is noise (10% of its normal part from the rays, 4% from the photons); on
  // average, none.
  EXPECT_NEAR(alongX / count, 0, 0.01) << "no light from aside";
  EXPECT_NEAR(alongZ / count, 0, 0.01) << "no light from aside";
}

TEST(Directional, EvenSkyShowsTheStatedTruncation) {
  ExpectEvenSky(DirectLight::kSampled, "sh-sky-rays");
  ExpectEvenSky(DirectLight::kPhotons, "sh-sky-photons");
}

// A refined mesh (new vertices, no per-vertex noise of H: --refine and --subdivide alike) carries the SH of its own
// vertices, E at each normal its H, and the report its direction noise (such a bake once crashed there).
TEST(Directional, RefinedMeshesCarryTheShToo) {
  BakeOptions o = BoxWithSh("sh-subdivided", 100'000);
  o.refine.subdivide = 1;
  const BakeResult r = BakeMesh(o, Log(true));
  ASSERT_TRUE(r.mesh.irradianceNoise.empty()) << "the case that crashed";
  ASSERT_EQ(r.mesh.sh.size(), r.mesh.mesh.VertexCount());
  for (size_t v = 0; v < r.mesh.sh.size(); ++v)
    ASSERT_NEAR(ShIrradiance(r.mesh.sh[v], r.mesh.mesh.normals[v]).g, r.mesh.irradiance[v].g,
                1e-4f * (1 + r.mesh.irradiance[v].g));
  EXPECT_GT(r.report.directionNoise, 0);
}

TEST(Directional, OneArrivalGivesItsOwnMoments) {
  // Light e = 2 W/m^2 arriving 60 degrees from the normal z, from +x: L1 along it, F = e / cos, E(n) = D . n.
  IncidentMoments m;
  const Vector3 w{std::sin(float(M_PI / 3)), 0, 0.5f};
  m.Add({2, 2, 2}, w, 0.5f);
  const ShL1 sh = ShProjection(m, {0, 0, 1}, {2, 2, 2});
  EXPECT_NEAR(sh.c[0].r * 2 * std::sqrt(M_PI), 4, 1e-5);
  EXPECT_NEAR(ShIrradiance(sh, {0, 0, 1}).r, 2, 1e-5);
  EXPECT_NEAR(ShIrradiance(sh, {1, 0, 0}).r, 4 * w.x, 1e-5);
  EXPECT_EQ(ShIrradiance(sh, {-1, 0, 0}).r, 0) << "a normal turned from the light reads none";
  // Grazing light is floored at kGrazingCosine: its moments stay finite.
  IncidentMoments grazing;
  grazing.Add({1, 1, 1}, {1, 0, 0}, 0.0f);
  EXPECT_NEAR(grazing.scalar.r, 1 / kGrazingCosine, 1e-3);
}

TEST(Directional, ProjectionSetsTheNormalComponentToTheIrradiance) {
  IncidentMoments m;
  m.Add({1, 1, 1}, {0, 0, 1}, 1.0f);
  const ShL1 sh = ShProjection(m, {0, 0, 1}, {1.5f, 1.5f, 1.5f});
  EXPECT_NEAR(ShIrradiance(sh, {0, 0, 1}).g, 1.5, 1e-6);
  EXPECT_NEAR(sh.c[1].g, 0, 1e-7);
  EXPECT_NEAR(sh.c[0].g, kShY00, 1e-7) << "F is the moments' own";
}

}  // namespace
}  // namespace pb


