// Effects a scene calls for (baker/0_plan_transport.h) and the photon loops that simulate them
// (baker/1_trace_photons.h): the plan's choices and reasons, the same answer with every effect forced on,
// forbidden effects tallied, and two closed forms with specular surfaces:
//  - a small light beside a mirror lights a black floor as the light plus its mirror image would;
//  - a closed box with a clear glass sphere (which absorbs nothing) still conserves energy, and the flux reaching
//    its diffuse walls is Phi / (1 - rho), whatever the sphere does to the paths.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "baker/0_plan_transport.h"
#include "baker/1_trace_photons.h"
#include "baker/bake.h"
#include "mesh/errors.h"
#include "mesh/obj_loader.h"
#include "tests/chi2.h"
#include "tests/floor_cells.h"
#include "tests/ply_reader.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

BakeReport QuietBake(const std::string& scene, const std::string& output, uint64_t photons,
                     const std::string& effects = "auto") {
  BakeOptions o;
  o.scenePath = scene;
  o.outputPath = output;
  o.photons = photons;
  o.effectsText = effects;
  return Bake(o, Log(true));
}

using Loaded = test::TracedScene;

TEST(EffectOverrides, ParsesListsAndRefusesBadNames) {
  const EffectOverrides o = ParseEffectOverrides("+caustics,-refraction,reflection");
  EXPECT_EQ(o.forced[size_t(Effect::kCaustics)], std::optional<bool>(true));
  EXPECT_EQ(o.forced[size_t(Effect::kRefraction)], std::optional<bool>(false));
  EXPECT_EQ(o.forced[size_t(Effect::kReflection)], std::optional<bool>(true));
  EXPECT_FALSE(o.forced[size_t(Effect::kInterreflection)].has_value());
  for (const auto& f : ParseEffectOverrides("all").forced) EXPECT_EQ(f, std::optional<bool>(true));
  for (const auto& f : ParseEffectOverrides("auto").forced) EXPECT_FALSE(f.has_value());
  EXPECT_THROW(ParseEffectOverrides("+glow"), InputError);
  EXPECT_THROW(ParseEffectOverrides("-direct"), InputError);
  EXPECT_THROW(ParseEffectOverrides("caustics,"), InputError);
}

TEST(TransportPlan, DiffuseBoxNeedsNoSpecularTransport) {
  const TransportPlan plan = Loaded(PB_SOURCE_DIR "/data/box/box.obj").Plan();
  EXPECT_TRUE(plan.On(Effect::kDirect));
  EXPECT_TRUE(plan.On(Effect::kInterreflection));
  EXPECT_FALSE(plan.NeedsSpecularKernel());
  EXPECT_EQ(plan.Describe(Effect::kRefraction), "skipped: no transmissive material");
  EXPECT_EQ(plan.Describe(Effect::kReflection), "skipped: no mirror or glass material");
  EXPECT_NEAR(plan.largestAlbedo, 0.78f, 1e-6);
  EXPECT_EQ(plan.significantBounces, 28u);  // 0.78^28 = 9.5e-4 < 1e-3 < 0.78^27
}

TEST(TransportPlan, BlackReceiversStopAtTheFirstHit) {
  const std::string dir = test::TempDirectory("black-receivers");
  const Loaded s(test::WriteSquareLightOverFloor(dir, 0.5f, 1.0f, 1.0f, 2.0f, 4));
  const TransportPlan plan = s.Plan();
  EXPECT_FALSE(plan.On(Effect::kInterreflection));
  EXPECT_NE(plan.Describe(Effect::kInterreflection).find("every surface is black"), std::string::npos);
  const PhotonStore hits = TracePhotons(s.scene, s.lights, *s.rays, plan, {20000, 3}, Log(true));
  EXPECT_EQ(hits.stats.diffuseBounces, 0u);
  EXPECT_EQ(hits.stats.hits + hits.stats.escaped, hits.stats.emitted) << "one hit or an escape per photon";
  EXPECT_EQ(hits.stats.absorbed, hits.stats.hits);
}

TEST(TransportPlan, ALightThatFacesAwayFromEverythingGetsNoPhotons) {
  const std::string dir = test::TempDirectory("facing-away");
  // The first lamp faces down onto the floor; the second (above it) faces up into empty space.
  const std::string path = test::WriteFloorWithLamps(dir, 0.5f, 1.0f, {{0, 1, 0, 1, 1, true}, {0, 1, 0, 1, 2, false}});
  const BakeReport r = QuietBake(path, dir + "/out.ply", 10000);
  ASSERT_EQ(r.lights.size(), 2u);
  EXPECT_EQ(r.lights[0].photons, 10000u);
  EXPECT_EQ(r.lights[1].photons, 0u);
  EXPECT_NE(r.lights[1].note.find("behind its emitting side"), std::string::npos) << r.lights[1].note;
  EXPECT_EQ(r.lights[0].note, "");
  EXPECT_NEAR(r.trace.fluxEmitted.g, M_PI, 1e-5) << "only the reaching light's flux is emitted";

  const std::string away = test::WriteFloorWithLamps(test::TempDirectory("all-away"), 0.5f, 1.0f, {{0, 1, 0, 1, 1, false}});
  EXPECT_THROW(QuietBake(away, dir + "/out.ply", 10000), InputError);
}

TEST(Effects, ForcingEveryEffectOnADiffuseSceneGivesTheSameBytes) {
  // The specular loop draws the same random numbers for a diffuse material as the diffuse loop (one for the
  // event, two for the direction) and computes the same weight, so the result is not merely equal within noise:
  // it is identical. The benchmark (bench_trace, BM_TraceEffects) shows what the diffuse loop saves.
  const std::string dir = test::TempDirectory("forced-effects");
  const BakeReport a = QuietBake(PB_SOURCE_DIR "/data/box/box.obj", dir + "/auto.ply", 200000);
  const BakeReport b = QuietBake(PB_SOURCE_DIR "/data/box/box.obj", dir + "/all.ply", 200000, "all");
  EXPECT_EQ(a.trace.SpecularEvents(), 0u);
  EXPECT_EQ(b.trace.SpecularEvents(), 0u);
  EXPECT_EQ(a.trace.causticHits + b.trace.causticHits, 0u);
  EXPECT_GT(a.trace.diffuseBounces, 0u);
  EXPECT_EQ(a.trace.diffuseBounces, b.trace.diffuseBounces);
  EXPECT_TRUE(b.plan.effects[size_t(Effect::kRefraction)].overridden);
  EXPECT_EQ(test::ReadBytes(dir + "/auto.ply"), test::ReadBytes(dir + "/all.ply"));
}

// A 2 cm light at (0.5, 0.5, 0) facing -x toward a mirror (Ks 0.9) in the plane x = 0, over a black floor
// y = 0, x in [0, 1.5], z in [-1, 1]. Nothing else reflects.
std::string WriteLightBesideMirror(const std::string& dir, float radiance) {
  test::WriteText(dir + "/m.mtl", fmt::format("newmtl floor\nKd 0 0 0\nnewmtl mirror\nKd 0 0 0\nKs 0.9 0.9 0.9\n"
                                              "illum 3\nnewmtl lamp\nKd 0 0 0\nKe {0} {0} {0}\n", radiance));
  test::WriteText(dir + "/m.obj",
                  "mtllib m.mtl\no floor\nusemtl floor\nv 0 0 1\nv 1.5 0 1\nv 1.5 0 -1\nv 0 0 -1\nf 1 2 3 4\n"
                  "o mirror\nusemtl mirror\nv 0 0 1.5\nv 0 0 -1.5\nv 0 1.5 -1.5\nv 0 1.5 1.5\nf 5 6 7 8\n"
                  "o lamp\nusemtl lamp\nv 0.5 0.49 -0.01\nv 0.5 0.49 0.01\nv 0.5 0.51 0.01\nv 0.5 0.51 -0.01\n"
                  "f 9 10 11 12\n");
  return dir + "/m.obj";
}

// Irradiance on the floor at (x, 0, z) from a small Lambertian emitter of intensity I(theta) = L A cos(theta)
// at `light` facing along `axis` (+1 or -1 in x) [W/m^2], as a point source (the 2 cm light is 25 times smaller
// than the nearest distance, so the error is below 1e-3).
double PointSourceIrradiance(double x, double z, double lx, double axis, double intensity) {
  const double dx = lx - x, dy = 0.5, r2 = dx * dx + dy * dy + z * z, r = std::sqrt(r2);
  const double cosLight = -axis * dx / r;  // the light's normal is (axis, 0, 0); the floor point is at -d
  return cosLight > 0 ? intensity * cosLight * (dy / r) / r2 : 0.0;
}

TEST(Effects, MirrorImageMatchesTheClosedForm) {
  const std::string dir = test::TempDirectory("mirror-image");
  const float radiance = 100.0f;
  const Loaded s(WriteLightBesideMirror(dir, radiance));
  const TransportPlan plan = s.Plan();
  ASSERT_TRUE(plan.On(Effect::kReflection));
  ASSERT_TRUE(plan.On(Effect::kCaustics));
  constexpr uint64_t kPhotons = 1'000'000;
  const PhotonStore hits = TracePhotons(s.scene, s.lights, *s.rays, plan, {kPhotons, 21}, Log(true));
  EXPECT_GT(hits.stats.mirrorReflections, kPhotons / 4);
  EXPECT_GT(hits.stats.causticHits, 0u);

  // Photon counts in 0.25 m cells of the floor against N * integral(H) / Phi over each cell. Every photon
  // carries Phi / N (Ks / max(Ks) = 1), so counts are Poisson: chi-square over the cells.
  const test::FloorCells cells{6, 8, 0.25, 0.0, -1.0};
  const uint32_t floorMaterial = s.scene.triangles[0].material;
  std::vector<double> observed(cells.Count(), 0.0);
  hits.ForEach([&](const PhotonHit& h, Rgb) {
    if (s.scene.triangles[h.Triangle()].material != floorMaterial || !h.OnFront()) return;
    const Point3 p = s.scene.PointAt(h.Triangle(), h.b1, h.b2);
    ++observed[cells.Of(p.x, p.z)];
  });
  const double area = 0.02 * 0.02, intensity = radiance * area, phi = M_PI * radiance * area;
  // H is smooth within each cell: the direct light's cut-off at x = 0.5 is a cell edge.
  const std::vector<double> expected = cells.ExpectedCounts(
      [&](double x, double z) {
        return PointSourceIrradiance(x, z, 0.5, -1, intensity) + 0.9 * PointSourceIrradiance(x, z, -0.5, 1, intensity);
      },
      double(kPhotons) / phi, 24);
  double chi2 = 0;
  for (size_t c = 0; c < observed.size(); ++c) chi2 += (observed[c] - expected[c]) * (observed[c] - expected[c]) / expected[c];
  const double p = test::RegularizedGammaQ(observed.size() / 2.0, chi2 / 2.0);
  EXPECT_GT(p, 1e-3) << "chi2 " << chi2 << " over " << observed.size() << " cells";
  // Without the mirror's contribution the far cells would hold 10% of what they do: the test can fail.
  const size_t far = cells.Of(1.4, 0.0);
  EXPECT_GT(observed[far], 0.9 * expected[far]);
}

TEST(Effects, ForbiddenReflectionIsTalliedNotLost) {
  const std::string dir = test::TempDirectory("forbid-mirror");
  const std::string path = WriteLightBesideMirror(dir, 100.0f);
  const BakeReport r = QuietBake(path, dir + "/out.ply", 200000, "-reflection");
  EXPECT_FALSE(r.plan.On(Effect::kReflection));
  EXPECT_FALSE(r.plan.On(Effect::kCaustics)) << "caustics need a specular effect";
  EXPECT_EQ(r.trace.mirrorReflections, 0u);
  EXPECT_GT(r.trace.forbidden, 0u);
  const double out = r.trace.fluxAbsorbed.g + r.trace.fluxEscaped.g + r.trace.fluxForbidden.g;
  EXPECT_NEAR(out / r.trace.fluxEmitted.g, 1.0, 0.01);  // the mirror's Ks 0.9: forbidden, its 0.1: absorbed
  EXPECT_EQ(r.trace.absorbed + r.trace.escaped + r.trace.forbidden, r.trace.emitted);
}

TEST(Effects, ClosedBoxWithGlassSphereConservesEnergy) {
  // Grey walls (rho = 0.5) and a clear sphere: a photon keeps its flux Phi / N through every event, and the number
  // of diffuse hits before absorption is geometric with mean 1 / (1 - rho) and variance rho / (1 - rho)^2.
  // So the flux reaching diffuse surfaces sums to Phi / (1 - rho) with relative sd sqrt(rho / N) = 0.07% at
  // N = 1M; 0.5% is 7 sd. The expected absorption equals emission within the same bound.
  const std::string dir = test::TempDirectory("glass-energy");
  const float rho = 0.5f;
  const Loaded s(test::WriteClosedBox(dir, 1.0f, rho, 0.2f, 10.0f, 0.25f));
  const TransportPlan plan = s.Plan();
  ASSERT_TRUE(plan.On(Effect::kRefraction));
  constexpr uint64_t kPhotons = 1'000'000;
  const PhotonStore hits = TracePhotons(s.scene, s.lights, *s.rays, plan, {kPhotons, 8}, Log(true));
  const TraceStats& t = hits.stats;
  EXPECT_GT(t.refractions, kPhotons / 20);
  EXPECT_GT(t.fresnelReflections, 0u);
  EXPECT_GT(t.causticHits, 0u);
  EXPECT_EQ(t.escaped, 0u) << "light leaks out of the box or through the glass";
  EXPECT_EQ(t.truncated, 0u);
  EXPECT_NEAR(t.fluxAbsorbed.g / t.fluxEmitted.g, 1.0, 0.005);
  double diffuseFlux = 0;
  hits.ForEach([&](const PhotonHit& h, Rgb flux) {
    if (!s.scene.MaterialOf(h.Triangle()).IsSpecular()) diffuseFlux += flux.g;
  });
  EXPECT_NEAR(diffuseFlux * (1 - rho) / t.fluxEmitted.g, 1.0, 0.005);
}

}  // namespace
}  // namespace pb
