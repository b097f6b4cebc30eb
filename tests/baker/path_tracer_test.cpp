// The path tracer (baker/render/path_tracer.h): both samplers converge to the same image, and to the closed form where
// there is one; the importance map's floor is what keeps photon sampling unbiased; degenerate maps stay finite;
// images do not depend on the thread count.
//
// Tolerances come from the images' own noise: each pixel's variance of the mean is estimated from its samples,
// blocks of pixels are compared by z = (a - b) / sqrt(var a + var b), and the sum of z^2 over blocks is tested
// against chi-square with one degree of freedom per block.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "baker/render/render.h"
#include "baker/runtime/threads.h"
#include "mesh/lights.h"
#include "mesh/obj_loader.h"
#include "mesh/surfaces.h"
#include "tests/chi2.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

struct Fixture : test::TracedScene {
  using TracedScene::TracedScene;
  std::vector<MapPhoton> Photons(uint64_t n, const std::vector<Light>& from) const {
    const TransportPlan plan = PlanTransport(scene, surfaces, from, {});
    return MapPhotonsOf(scene, TracePhotons(scene, from, *rays, plan, {n, 99}, Log(true)));
  }
  // With photon sampling, the maps cached as render caches them (s.mapCache) or built at every hit.
  RenderedImage Render(const PathSettings& s, const std::vector<MapPhoton>* photons, const Camera& camera, int size,
                       uint32_t spp, uint64_t seed) const {
    const LightSampler sampler(scene, lights, *rays);
    std::optional<ImportanceCache> cache;
    std::optional<PhotonMap> map;
    if (photons != nullptr && s.sampling == DirectionSampling::kPhotons) {
      if (s.mapCache)
        cache.emplace(*photons, s.Map());
      else
        map.emplace(*photons);
    }
    const PathTracer tracer(scene, *rays, map ? &*map : nullptr, &sampler, s, cache ? &*cache : nullptr);
    return RenderImage(tracer, s, PinholeCamera(camera, size, size), size, size, spp, seed, Log(true));
  }
};

struct BlockStats {
  std::vector<double> mean, variance;  // luminance of each block's mean, and its variance
};

BlockStats Blocks(const RenderedImage& r, int block) {
  BlockStats b;
  for (int by = 0; by < r.mean.height / block; ++by)
    for (int bx = 0; bx < r.mean.width / block; ++bx) {
      double m = 0, v = 0;
      for (int y = by * block; y < (by + 1) * block; ++y)
        for (int x = bx * block; x < (bx + 1) * block; ++x) {
          m += Luminance(r.mean.At(x, y));
          v += r.luminanceVariance[size_t(y) * size_t(r.mean.width) + size_t(x)];
        }
      const double n = double(block * block);
      b.mean.push_back(m / n);
      b.variance.push_back(v / (n * n));
    }
  return b;
}

// chi-square p-value of sum z^2 over blocks, z = (a - b) / sqrt(var a + var b).
double AgreementP(const BlockStats& a, const BlockStats& b, std::string& table) {
  double chi2 = 0;
  for (size_t i = 0; i < a.mean.size(); ++i) {
    const double z = (a.mean[i] - b.mean[i]) / std::sqrt(a.variance[i] + b.variance[i]);
    chi2 += z * z;
    table += std::to_string(i) + ": " + std::to_string(a.mean[i]) + " vs " + std::to_string(b.mean[i]) + " z " +
             std::to_string(z) + "\n";
  }
  return test::RegularizedGammaQ(a.mean.size() / 2.0, chi2 / 2.0);
}

// A closed cube [0,1]^3 whose inward walls all emit Le and reflect rho: the radiance is Le / (1 - rho)
// everywhere (the furnace), whatever the sampler. Faces are wound to face inward.
std::string WriteGlowingCube(const std::string& dir, float radiance, float albedo) {
  test::WriteText(dir + "/cube.mtl", fmt::format("newmtl glow\nKd {0} {0} {0}\nKe {1} {1} {1}\n", albedo, radiance));
  test::WriteText(dir + "/cube.obj",
                  "mtllib cube.mtl\nusemtl glow\n"
                  "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                  "f 5 6 2 1\nf 3 7 8 4\nf 2 3 4 1\nf 8 7 6 5\nf 4 8 5 1\nf 6 7 3 2\n");
  return dir + "/cube.obj";
}

const Camera kInsideCube{{0.5f, 0.5f, 0.2f}, {0.5f, 0.5f, 1.0f}, {0, 1, 0}, 90};

TEST(PathTracer, BothSamplersMatchTheFurnaceClosedForm) {
  const Fixture f(WriteGlowingCube(test::TempDirectory("furnace"), 1.0f, 0.5f));
  const std::vector<MapPhoton> photons = f.Photons(200000, f.lights);
  for (const auto& [sampling, cached] : {std::pair{DirectionSampling::kBrdf, false}, std::pair{DirectionSampling::kPhotons, false},
                                         std::pair{DirectionSampling::kPhotons, true}}) {
    PathSettings s;
    s.sampling = sampling;
    s.mapCache = cached;
    s.neighbours = cached ? s.neighbours : 200;  // a map of the 200 nearest at every hit, at a quarter of the cost
    // Photon sampling here is skewed (maps of few photons leave most regions to the floor, whose directions then
    // carry large weights), so each 4 x 4 block gets 8192 samples before its mean is close to normal.
    const RenderedImage image = f.Render(s, &photons, kInsideCube, 8, 512, 5);
    const BlockStats b = Blocks(image, 4);
    double chi2 = 0;
    for (size_t i = 0; i < b.mean.size(); ++i) chi2 += std::pow(b.mean[i] - 2.0, 2) / b.variance[i];
    EXPECT_GT(test::RegularizedGammaQ(b.mean.size() / 2.0, chi2 / 2.0), 1e-3)
        << SamplingName(sampling) << (cached ? " cached" : "") << " chi2 " << chi2 << " mean of block 0 " << b.mean[0];
  }
}

TEST(PathTracer, PhotonSamplingMatchesBrdfSamplingOnTheBox) {
  const Fixture f(PB_SOURCE_DIR "/data/box/box.obj");
  const std::vector<MapPhoton> photons = f.Photons(300000, f.lights);
  const Camera camera = LoadCamera(PB_SOURCE_DIR "/data/box/box.camera.json");
  PathSettings brdf, guided;
  guided.sampling = DirectionSampling::kPhotons;
  // Blocks of 8 x 8 pixels: both estimators are skewed (rare paths find the small ceiling light), so each block
  // needs thousands of samples before its mean is close to normal.
  const BlockStats a = Blocks(f.Render(brdf, nullptr, camera, 24, 512, 1), 8);
  const BlockStats b = Blocks(f.Render(guided, &photons, camera, 24, 128, 2), 8);
  std::string table;
  EXPECT_GT(AgreementP(a, b, table), 1e-3) << table;
}

// Two 0.4 m lights 1 m above a grey floor; the photon map holds photons from the first light only.
TEST(PathTracer, TheFloorKeepsDirectionsWithoutPhotonsReachable) {
  const std::string dir = test::TempDirectory("floor-matters");
  const Fixture f(test::WriteFloorWithLamps(dir, 0.5f, 5.0f, {{-0.9f, -0.5f, -0.2f, 0.2f, 1}, {0.5f, 0.9f, -0.2f, 0.2f, 1}}));
  ASSERT_EQ(f.lights.size(), 2u);
  const std::vector<MapPhoton> firstOnly = f.Photons(100000, {f.lights[0]});
  const Camera down{{0, 0.8f, -0.01f}, {0, 0, 0}, {0, 0, 1}, 60};
  PathSettings brdf, guided;
  guided.sampling = DirectionSampling::kPhotons;
  brdf.lightSampling = guided.lightSampling = false;  // the paper's pure form, where the map alone finds the lights
  guided.mapCache = false;  // the cache raises the floor of maps from few photons
  guided.neighbours = 200;
  const BlockStats reference = Blocks(f.Render(brdf, nullptr, down, 16, 256, 3), 16);  // one block: the image mean
  guided.floorFraction = 0;
  const BlockStats noFloor = Blocks(f.Render(guided, &firstOnly, down, 16, 64, 4), 16);
  guided.floorFraction = 0.2f;
  const BlockStats withFloor = Blocks(f.Render(guided, &firstOnly, down, 16, 64, 4), 16);
  const auto z = [&](const BlockStats& b) {
    return (b.mean[0] - reference.mean[0]) / std::sqrt(b.variance[0] + reference.variance[0]);
  };
  EXPECT_LT(z(noFloor), -6) << "without a floor the second light is never sampled: the image is too dark";
  EXPECT_LT(std::abs(z(withFloor)), 4) << "with a floor every direction can be drawn: unbiased";
}

// Light sampling changes how the light is found, not what is found: on the box, paths that sample the lights at
// every diffuse hit agree with paths that must hit them (both BRDF-sampled), block by block.
TEST(PathTracer, LightSamplingAgreesWithHittingTheLights) {
  const Fixture f(PB_SOURCE_DIR "/data/box/box.obj");
  const Camera camera = LoadCamera(PB_SOURCE_DIR "/data/box/box.camera.json");
  PathSettings hitting, sampled;
  hitting.lightSampling = false;
  const BlockStats a = Blocks(f.Render(hitting, nullptr, camera, 24, 512, 1), 8);
  const BlockStats b = Blocks(f.Render(sampled, nullptr, camera, 24, 64, 2), 8);
  std::string table;
  EXPECT_GT(AgreementP(a, b, table), 1e-3) << table;
}

// A sun straight above a grey floor (Kd 0.5, E 2 W/m^2), seen from above: with light sampling every pixel is the
// closed form Kd E / pi, exactly (one shadow ray finds a sun whole, before Russian roulette); without it the sun
// is never hit.
TEST(PathTracer, ASunIsRenderedWithLightSampling) {
  const std::string dir = test::TempDirectory("render-sun");
  test::WriteText(dir + "/f.mtl", "newmtl grey\nKd 0.5 0.5 0.5\n");
  test::WriteText(dir + "/f.obj", "mtllib f.mtl\nusemtl grey\nv -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\nf 1 4 3 2\n");
  test::WriteText(dir + "/f.lights.json", R"({"lights": [{"type": "sun", "direction": [0, -1, 0], "irradiance_W_m2": 2}]})");
  test::WriteText(dir + "/f.camera.json", R"({"position_m": [0, 1, 0.01], "look_at_m": [0, 0, 0], "up": [0, 0, 1],
                                             "vertical_fov_deg": 40})");
  RenderOptions o;
  o.scenePath = dir + "/f.obj";
  o.outputPath = dir + "/f.exr";
  o.width = o.height = 8;
  o.spp = 4;
  o.quiet = true;
  Render(o, Log(true));
  for (const Rgb& p : ReadExr(o.outputPath).pixels) EXPECT_NEAR(p.g, 0.5 * 2 / M_PI, 1e-6);
  o.path.lightSampling = false;
  Render(o, Log(true));
  for (const Rgb& p : ReadExr(o.outputPath).pixels) EXPECT_EQ(p.g, 0.0f);
}

TEST(PathTracer, DegenerateImportanceMapsStayFinite) {
  const Fixture f(PB_SOURCE_DIR "/data/box/box.obj");
  const Camera camera = LoadCamera(PB_SOURCE_DIR "/data/box/box.camera.json");
  std::vector<std::vector<MapPhoton>> maps;
  maps.emplace_back();                                                                     // no photons at all
  maps.push_back({{{0.3f, 0.01f, 0.3f}, {0, 1, 0}, {1, 1, 1}, {0, 1, 0}}});                // one photon
  maps.emplace_back(500, MapPhoton{{0.3f, 0.2f, 0.3f}, {0, 1, 0}, {1, 1, 1}, {0, 1, 0}});  // one region, one point
  for (float floor : {0.0f, 0.1f})
    for (bool cached : {false, true})
      for (const std::vector<MapPhoton>& map : maps) {
        PathSettings s;
        s.sampling = DirectionSampling::kPhotons;
        s.floorFraction = floor;
        s.mapCache = cached;
        const RenderedImage image = f.Render(s, &map, camera, 8, 4, 6);
        for (const Rgb& p : image.mean.pixels) {
          ASSERT_TRUE(std::isfinite(p.r) && std::isfinite(p.g) && std::isfinite(p.b));
          ASSERT_GE(std::min({p.r, p.g, p.b}), 0.0f);
        }
      }
}

TEST(PathTracer, ImagesDoNotDependOnTheThreadCount) {
  const Fixture f(PB_SOURCE_DIR "/data/box/box.obj");
  const std::vector<MapPhoton> photons = f.Photons(50000, f.lights);
  const Camera camera = LoadCamera(PB_SOURCE_DIR "/data/box/box.camera.json");
  PathSettings s;
  s.sampling = DirectionSampling::kPhotons;
  s.warp = ImportanceWarp::kInversion;
  std::vector<Rgb> one, two;
  {
    const ThreadScope t(1);
    one = f.Render(s, &photons, camera, 16, 4, 7).mean.pixels;
  }
  {
    const ThreadScope t(2);
    two = f.Render(s, &photons, camera, 16, 4, 7).mean.pixels;
  }
  ASSERT_EQ(one.size(), two.size());
  for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i].g, two[i].g) << i;
}

}  // namespace
}  // namespace pb
