// Gathering in narrow gaps (baker/3_gap_gather.h), on a grey slab floating 3 mm above a grey floor
// (test::WriteGapScene), where the floor under the slab is lit only through the mouth around its rim:
//  - against the path tracer (bake --reference) the gathered floor under the slab agrees vertex by vertex within
//    4 sigma of their two predicted noises plus 3% of the rim's light (the photons read where the gathered paths
//    end carry their kernel's own bias); the photons' kernel alone, which carries the bright rim 5 cm into the
//    dark, fails that on the first ring inside;
//  - only points in gaps are gathered: the floor under the slab, the slab's underside and the ceiling 1 cm over
//    the light's back, never the open floor or the floor where it meets a wall;
//  - with --gap-small-area, every vertex of a surface smaller than its kernel (the slab's sides) is gathered, and
//    nothing else changes; with a share of the triangles (the defaults'), the smallest such surfaces first, within it;
//  - with --gap-noise, each gathered point takes the paths its own noise asks for: the floor under the slab still
//    agrees with the path tracer as above, and its lit points' predicted noise is the target in RMS (within the
//    pilot's misjudgement), where a fixed 256 paths leave it several times higher;
//  - with --gap-edges, the floor's vertices along the walls (a concave corner, where the kernel reads high) are
//    gathered too and agree with the path tracer in the mean;
//  - the gathered bake is the same, bit for bit, on one thread and on two, guided or not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "baker/bake.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

// The slab scene's bake at h = 0.1 m with `gapPaths` gathered a point.
BakeOptions GapOptions(uint32_t gapPaths, uint64_t photons) {
  static const std::string scene = test::WriteGapScene(test::TempDirectory("gap-gather"));
  BakeOptions o;
  o.scenePath = scene;
  o.photons = photons;
  o.estimator.bandwidth = 0.1f;
  o.gaps.paths = gapPaths;
  return o;
}

BakeResult BakeGap(uint32_t gapPaths, uint32_t referencePaths = 0, unsigned threads = 0, float smallArea = 0,
                   double gapNoise = 0, bool edges = false, uint64_t photons = 1'000'000, uint64_t guidePhotons = 0,
                   float smallShare = 1) {
  BakeOptions o = GapOptions(gapPaths, photons);
  o.gaps.smallArea = smallArea;
  o.gaps.smallShare = smallShare;
  o.gaps.noise = gapNoise;
  o.gaps.edges = edges;
  o.referencePaths = referencePaths;
  o.guidePhotons = guidePhotons;
  o.threads = threads;
  return BakeMesh(o, Log(true));
}

// Vertex v's position in the scene's coordinates [m].
Point3 World(const BakedMesh& b, size_t v) {
  const auto& o = b.mesh.origin;
  return b.mesh.positions[v] + Vector3{float(o[0]), float(o[1]), float(o[2])};
}
bool UnderSlab(const BakedMesh& b, size_t v) {
  const Point3 p = World(b, v);
  return std::abs(p.y) < 1e-5f && b.mesh.normals[v].y > 0.5f && p.x > 0.299f && p.x < 0.701f && p.z > 0.299f &&
         p.z < 0.701f;
}
bool SlabUnderside(const BakedMesh& b, size_t v) { return b.mesh.normals[v].y < -0.5f && World(b, v).y < 0.5f; }
// The ceiling over the light, whose back hangs 1 cm below it: a gap too.
bool OverLight(const BakedMesh& b, size_t v) {
  const Point3 p = World(b, v);
  return b.mesh.normals[v].y < -0.5f && p.y > 0.999f && std::abs(p.x - 0.5f) < 0.101f && std::abs(p.z - 0.5f) < 0.101f;
}

// Vertices under the slab whose H differs from the reference's by more than 4 sigma + 3% of the rim's mean H.
int Disagreements(const BakedMesh& bake, const BakedMesh& reference) {
  double rim = 0;
  int rimVertices = 0;
  for (size_t v = 0; v < bake.mesh.VertexCount(); ++v) {
    const Point3 p = World(bake, v);
    if (UnderSlab(bake, v) && (std::abs(p.x - 0.3f) < 1e-3f || std::abs(p.x - 0.7f) < 1e-3f))
      rim += Luminance(reference.irradiance[v]), ++rimVertices;
  }
  rim /= rimVertices;
  int disagree = 0;
  for (size_t v = 0; v < bake.mesh.VertexCount(); ++v) {
    if (!UnderSlab(bake, v)) continue;
    const double b = Luminance(bake.irradiance[v]), r = Luminance(reference.irradiance[v]);
    const double sigma = std::hypot(b * bake.irradianceNoise[v], r * reference.irradianceNoise[v]);
    if (std::abs(b - r) > 4 * sigma + 0.03 * rim) ++disagree;
  }
  return disagree;
}

// The RMS of the predicted relative noise (the gather's alone: no direct light reaches them) over the vertices
// under the slab that `lit` reads at least 5% of the brightest of them: deeper in, H falls to 10^-4 of the rim's,
// where a relative error says little (256 paths find no light there and report none).
double RmsNoiseUnderSlab(const BakedMesh& b, const BakedMesh& lit) {
  double brightest = 0, sum = 0;
  for (size_t v = 0; v < b.mesh.VertexCount(); ++v)
    if (UnderSlab(b, v)) brightest = std::max(brightest, double(Luminance(lit.irradiance[v])));
  int n = 0;
  for (size_t v = 0; v < b.mesh.VertexCount(); ++v)
    if (UnderSlab(b, v) && Luminance(lit.irradiance[v]) >= 0.05 * brightest)
      sum += b.irradianceNoise[v] * b.irradianceNoise[v], ++n;
  return std::sqrt(sum / n);
}

TEST(GapGather, TheFloorUnderAFloatingSlabMatchesThePathTracer) {
  const BakeResult gathered = BakeGap(1024), kernel = BakeGap(0), reference = BakeGap(0, 8192);
  // The same with the gathered paths' first directions guided (--guide-photons).
  const BakeResult guided = BakeGap(1024, 0, 0, 0, 0, false, 1'000'000, 250'000);
  EXPECT_EQ(Disagreements(guided.mesh, reference.mesh), 0);
  std::printf("RMS predicted noise under the slab: %.4f gathered, %.4f guided\n",
              RmsNoiseUnderSlab(gathered.mesh, reference.mesh), RmsNoiseUnderSlab(guided.mesh, reference.mesh));
  ASSERT_EQ(gathered.mesh.mesh.VertexCount(), reference.mesh.mesh.VertexCount());
  ASSERT_FALSE(gathered.mesh.irradianceNoise.empty());
  ASSERT_FALSE(reference.mesh.irradianceNoise.empty());
  int under = 0;
  for (size_t v = 0; v < gathered.mesh.mesh.VertexCount(); ++v) under += UnderSlab(gathered.mesh, v);
  ASSERT_EQ(under, 81) << "9 x 9 floor vertices, 5 cm apart";
  const int withGather = Disagreements(gathered.mesh, reference.mesh), without = Disagreements(kernel.mesh, reference.mesh);
  std::printf("vertices under the slab off the path tracer: %d gathered, %d from the kernel alone\n", withGather, without);
  EXPECT_EQ(withGather, 0);
  EXPECT_GE(without, 16) << "the kernel carries the rim's light onto the first ring inside: the test can fail";
}


TEST(GapGather, ANoiseTargetChoosesEachPointsPaths) {
  constexpr double kTarget = 0.03;
  const BakeResult adaptive = BakeGap(16384, 0, 0, 0, kTarget), fixed = BakeGap(256), reference = BakeGap(0, 8192);
  const double rms = RmsNoiseUnderSlab(adaptive.mesh, reference.mesh), fixedRms = RmsNoiseUnderSlab(fixed.mesh, reference.mesh);
  std::printf("RMS noise under the slab: %.4f with a target of %.2f, %.4f at 256 paths\n", rms, kTarget, fixedRms);
  EXPECT_EQ(Disagreements(adaptive.mesh, reference.mesh), 0) << "unbiased: the pilot is not averaged in";
  // A 64-path pilot misjudges a point's noise by about 1 / sqrt(2 x 64) = 9% for light Gaussian tails, more for
  // heavy ones; the chosen count follows the square of that.
  EXPECT_GT(rms, 0.6 * kTarget);
  EXPECT_LT(rms, 1.4 * kTarget);
  EXPECT_GT(fixedRms, 2 * kTarget) << "256 paths fall short of the target: the test can fail";
}

TEST(GapGather, OnlyPointsInTheGapAreGathered) {
  const BakeResult gathered = BakeGap(256), kernel = BakeGap(0);
  const BakedMesh &a = gathered.mesh, &b = kernel.mesh;
  int changed = 0, underChanged = 0;
  for (size_t v = 0; v < a.mesh.VertexCount(); ++v) {
    if (a.irradiance[v] == b.irradiance[v]) continue;
    ++changed;
    underChanged += UnderSlab(a, v);
    EXPECT_TRUE(UnderSlab(a, v) || SlabUnderside(a, v) || OverLight(a, v))
        << "gathered at (" << World(a, v).x << ", " << World(a, v).y << ", " << World(a, v).z << ")";
  }
  std::printf("%d vertices gathered, %d of them on the floor under the slab\n", changed, underChanged);
  EXPECT_GE(underChanged, 49) << "at least the 7 x 7 inside the rim";
}

// The slab's four sides (0.4 m x 1 cm: 0.004 m^2) are below 1 h^2 = 0.01 m^2; nothing else is.
TEST(GapGather, SurfacesSmallerThanTheKernelAreGatheredEverywhere) {
  const BakeResult small = BakeGap(256, 0, 0, 1.0f), gaps = BakeGap(256);
  const BakedMesh &a = small.mesh, &b = gaps.mesh;
  int sides = 0;
  for (size_t v = 0; v < a.mesh.VertexCount(); ++v) {
    const Point3 p = World(a, v);
    const bool side = std::abs(a.mesh.normals[v].y) < 0.5f && p.y < 0.02f && p.x > 0.29f && p.x < 0.71f &&
                      p.z > 0.29f && p.z < 0.71f;
    if (!side) continue;
    ++sides;
    EXPECT_NE(a.irradiance[v], b.irradiance[v]) << "a side vertex was not gathered";
  }
  EXPECT_EQ(sides, 16) << "four vertices on each of four sides";
  for (size_t v = 0; v < a.mesh.VertexCount(); ++v)
    if (a.irradiance[v] != b.irradiance[v]) {
      EXPECT_LT(std::abs(a.mesh.normals[v].y), 0.5f) << "only the sides change";
    }
}

// Below 20 h^2 = 0.2 m^2 lie the slab's sides (0.004 m^2, 2 triangles each), the light (0.04 m^2, 2) and the slab's
// top and underside (0.16 m^2, 32 each), of the scene's 1,034 triangles. A share of 9.5 of them takes the four sides
// and nothing larger: the same bake, bit for bit, as the sides alone (1 h^2, every small surface). A share of 5.5
// takes two of the four sides.
TEST(GapGather, TheSmallestSurfacesAreGatheredFirstWithinTheirShare) {
  constexpr float kTriangles = 1034;
  const auto bake = [](float smallArea, float share) {
    return BakeGap(256, 0, 0, smallArea, 0, false, 1'000'000, 0, share);
  };
  const BakeResult sides = bake(1.0f, 1.0f), capped = bake(20.0f, 9.5f / kTriangles);
  ASSERT_EQ(sides.mesh.irradiance.size(), capped.mesh.irradiance.size());
  for (size_t v = 0; v < sides.mesh.irradiance.size(); ++v)
    ASSERT_EQ(sides.mesh.irradiance[v], capped.mesh.irradiance[v]) << "vertex " << v;
  const BakeResult gaps = bake(0.0f, 1.0f), two = bake(20.0f, 5.5f / kTriangles);
  int changed = 0;
  for (size_t v = 0; v < gaps.mesh.irradiance.size(); ++v)
    if (two.mesh.irradiance[v] != gaps.mesh.irradiance[v]) {
      ++changed;
      EXPECT_LT(std::abs(two.mesh.mesh.normals[v].y), 0.5f) << "only sides change";
    }
  EXPECT_EQ(changed, 8) << "two sides of four vertices each";
}

// With rounds and time left, the small surfaces the share left to the photons (of the slab's sides, top and
// underside and the light, the share of 5.5 triangles takes two sides) are gathered at their vertices afterwards,
// smallest first, and weighed against their photons: the bake of one round with time to spare differs from the
// same bake without rounds exactly there, on every vertex of the surfaces left out (but the slab's underside, which
// its narrow gap had gathered and weighed alike) and on nothing else, and the report counts them.
TEST(GapGather, TheTimeTheRoundsLeaveGathersTheSmallSurfacesTheShareLeftOut) {
  BakeOptions once = GapOptions(64, 200'000);
  once.gaps.smallArea = 20, once.gaps.smallShare = 5.5f / 1034;
  BakeOptions rounds = once;
  rounds.targetNoise = 0.9f, rounds.maxRounds = 1, rounds.maxSeconds = 1000;
  const BakeResult a = BakeMesh(once, Log(true)), b = BakeMesh(rounds, Log(true));
  const ProgressiveReport::SmallSurfaces& small = b.report.progressive.small;
  EXPECT_EQ(small.leftOut, 5u) << "two sides, the light, the slab's top and underside";
  EXPECT_EQ(small.gathered, small.leftOut);
  EXPECT_EQ(a.report.progressive.small.leftOut, 0u) << "no rounds, no time left to spend";
  // Weighed against their photons as the first estimate's small surfaces were: the two sides and the light at least
  // are new among the weighed surfaces (the slab's underside was already, in its narrow gap).
  EXPECT_GE(b.report.narrowGaps.surfaces, a.report.narrowGaps.surfaces + 3);
  ASSERT_EQ(a.mesh.irradiance.size(), b.mesh.irradiance.size());
  const auto onTheSlab = [&](size_t v) {
    const Point3 p = World(a.mesh, v);
    return p.x > 0.299f && p.x < 0.701f && p.z > 0.299f && p.z < 0.701f && p.y > 0.001f && p.y < 0.5f;
  };
  size_t changed = 0, slabOrLight = 0, sameUnderside = 0;
  for (size_t v = 0; v < a.mesh.irradiance.size(); ++v) {
    if (a.mesh.irradiance[v] == b.mesh.irradiance[v]) {
      sameUnderside += onTheSlab(v) && a.mesh.mesh.normals[v].y < -0.5f;
      continue;
    }
    ++changed;
    const bool light = a.mesh.emitted[v].r > 0;
    if (onTheSlab(v) || light) ++slabOrLight;
    // Gathered: with the gathered paths' noise, or dark (the slab's underside, 3 mm over the floor).
    EXPECT_TRUE(b.mesh.gatheredVarianceShare[v] > 0 || b.mesh.irradiance[v] == Rgb{}) << "vertex " << v;
  }
  // The slab's underside (5 x 5 vertices) lies wholly in its narrow gap: the first estimate gathered it already and
  // weighed it from the same 25 pairs, so it reads the same.
  EXPECT_EQ(sameUnderside, 25u);
  EXPECT_EQ(changed + sameUnderside, small.vertices) << "every other vertex of the surfaces left out, and only those";
  EXPECT_EQ(slabOrLight, changed) << "only on the slab and the light";
}

// The floor's vertices along the walls, off the slab's corners (the room's floor is 20 x 20 cells of 5 cm).
bool FloorAlongAWall(const BakedMesh& b, size_t v) {
  const Point3 p = World(b, v);
  const auto atWall = [](float c) { return c < 1e-4f || c > 1 - 1e-4f; };
  return std::abs(p.y) < 1e-5f && b.mesh.normals[v].y > 0.5f && (atWall(p.x) || atWall(p.z));
}

// Where the floor meets a wall, the light scattered off the walls darkens into the corner closer than h = 0.1 m,
// and the kernel's local linear fit reads the turn as a line, high. With --gap-edges those vertices are gathered:
// their mean over the 80 vertices agrees with the path tracer's within 4 standard errors of the mean (from both
// bakes' predicted noises), where the kernel's alone, even from 4M photons, reads above it by more than that; and
// nothing else on the open floor changes.
TEST(GapGather, EdgesAlongTheWallsMatchThePathTracer) {
  const BakeResult edges = BakeGap(4096, 0, 0, 0, 0, true), kernel = BakeGap(4096, 0, 0, 0, 0, false, 4'000'000),
                   reference = BakeGap(0, 8192), unchanged = BakeGap(4096);
  const BakedMesh &e = edges.mesh, &k = kernel.mesh, &r = reference.mesh;
  // The mean of b - reference over the floor's vertices along the walls, and its standard error [W/m^2].
  struct Difference {
    double mean = 0, error = 0;
  };
  const auto difference = [&](const BakedMesh& b) {
    Difference d;
    int n = 0;
    for (size_t v = 0; v < b.mesh.VertexCount(); ++v) {
      if (!FloorAlongAWall(b, v)) continue;
      const double x = Luminance(b.irradiance[v]), y = Luminance(r.irradiance[v]);
      d.mean += x - y, d.error += std::pow(x * b.irradianceNoise[v], 2) + std::pow(y * r.irradianceNoise[v], 2), ++n;
    }
    EXPECT_EQ(n, 80) << "21 vertices on each side of the floor, the corners shared";
    d.mean /= n, d.error = std::sqrt(d.error) / n;
    return d;
  };
  const Difference gathered = difference(e), photons = difference(k);
  std::printf("floor along the walls, mean minus the path tracer's: gathered %+.5f (standard error %.5f), kernel "
              "%+.5f (%.5f) W/m^2\n", gathered.mean, gathered.error, photons.mean, photons.error);
  EXPECT_LT(std::abs(gathered.mean), 4 * gathered.error);
  EXPECT_GT(photons.mean, 4 * photons.error) << "the kernel reads the corner high: the test can fail";
  for (size_t v = 0; v < e.mesh.VertexCount(); ++v) {
    const Point3 p = World(e, v);
    if (!FloorAlongAWall(e, v) && e.mesh.normals[v].y > 0.5f && std::abs(p.y) < 1e-5f) {
      EXPECT_EQ(e.irradiance[v], unchanged.mesh.irradiance[v]) << "the floor changed at (" << p.x << ", " << p.z << ")";
    }
  }
}

// With a fixed count and with a noise target (each point's pilot, then its own count), the second with the edges
// gathered too: the adaptive gather's and the edges' code run here under the sanitizers too, which leave out the
// statistical tests above.
TEST(GapGather, TheSameOnAnyThreadCount) {
  for (const double noise : {0.0, 0.1}) {
    const bool edges = noise > 0;
    const BakeResult one = BakeGap(256, 0, 1, 0, noise, edges), two = BakeGap(256, 0, 2, 0, noise, edges);
    ASSERT_EQ(one.mesh.irradiance.size(), two.mesh.irradiance.size());
    for (size_t v = 0; v < one.mesh.irradiance.size(); ++v)
      ASSERT_EQ(one.mesh.irradiance[v], two.mesh.irradiance[v]) << v << ", noise target " << noise;
  }
  // Guided (--guide-photons): the maps and the paths alike.
  const BakeResult one = BakeGap(256, 0, 1, 0, 0, true, 1'000'000, 100'000);
  const BakeResult two = BakeGap(256, 0, 2, 0, 0, true, 1'000'000, 100'000);
  for (size_t v = 0; v < one.mesh.irradiance.size(); ++v)
    ASSERT_EQ(one.mesh.irradiance[v], two.mesh.irradiance[v]) << v << ", guided";
}

}  // namespace
}  // namespace pb
