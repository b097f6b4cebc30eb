// Stage 4, mesh refinement (baker/4_refine_mesh.h): the refined mesh follows the light within the tolerance, at a
// fraction of the vertices of uniform subdivision, and leaves the geometry exactly as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tuple>
#include <map>
#include <optional>

#include "baker/bake.h"
#include "baker/runtime/interrupt.h"
#include "baker/runtime/threads.h"
#include "baker/tone_map.h"
#include "mesh/half_edge_mesh.h"
#include "mesh/subdivide.h"
#include "tests/ply_reader.h"
#include "tests/staged_bake.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

uint32_t SurfaceOfMaterial(const test::StagedBake& bake, const std::string& name) {
  const auto& surfaces = bake.traced.surfaces.surfaces;
  for (uint32_t s = 0; s < surfaces.size(); ++s)
    if (bake.traced.scene.materials[surfaces[s].material].name == name) return s;
  ADD_FAILURE() << "no surface of material " << name;
  return 0;
}

// The displayed grey level that the mesh shows at floor point (x, 0, z): the vertices' grey levels interpolated
// linearly across the face that holds the point, as a viewer's rasteriser does.
std::optional<double> ShownOnFloor(const BakedMesh& baked, uint32_t floor, float exposure, float x, float z) {
  const SplitMesh& m = baked.mesh;
  for (const auto& f : m.faces) {
    if (m.surface[f[0]] != floor) continue;
    const Point2 a{m.positions[f[0]].x, m.positions[f[0]].z}, b{m.positions[f[1]].x, m.positions[f[1]].z},
        c{m.positions[f[2]].x, m.positions[f[2]].z}, p{x, z};
    const double area = SignedArea(a, b, c), wa = SignedArea(p, b, c) / area, wb = SignedArea(a, p, c) / area,
                 wc = 1 - wa - wb;
    if (wa < -1e-6 || wb < -1e-6 || wc < -1e-6) continue;
    return wa * DisplayedLuminance(baked.Radiance(f[0]), exposure) +
           wb * DisplayedLuminance(baked.Radiance(f[1]), exposure) +
           wc * DisplayedLuminance(baked.Radiance(f[2]), exposure);
  }
  return std::nullopt;
}

struct LineError {
  double max = 0;
  int above = 0, points = 0;
};

// Along z = 0.1, x in [0.2, 0.95]: across the shadow's edge (umbra to x = 0.55, penumbra to 0.65).
LineError ErrorAcrossTheEdge(const test::StagedBake& bake, const BakedMesh& baked, double tolerance) {
  const uint32_t floor = SurfaceOfMaterial(bake, "floor");
  LineError e;
  for (int i = 0; i < 600; ++i) {
    const float x = 0.2f + 0.75f * float(i) / 599.0f, z = 0.1f;
    const std::optional<double> shown = ShownOnFloor(baked, floor, bake.exposure, x, z);
    EXPECT_TRUE(shown.has_value()) << "no face holds (" << x << ", 0, " << z << ")";
    const double exact = DisplayedLuminance(bake.LightOnPlane(floor, {x, 0, z}).Radiance(), bake.exposure);
    const double error = std::fabs(shown.value_or(0) - exact);
    e.max = std::max(e.max, error);
    e.above += error > tolerance;
    ++e.points;
  }
  return e;
}

// The uniform baseline, with no error measurement: OpenSubdiv's levels, then the estimate at every vertex.
BakedMesh UniformMesh(const test::StagedBake& bake, int level) {
  const Scene& scene = bake.traced.scene;
  const SurfaceSet& surfaces = bake.traced.surfaces;
  const HalfEdgeMesh fine = SubdivideUniform(BuildHalfEdgeMesh(scene, surfaces), level);
  return EstimateIrradiance(bake.field, ToSplitMesh(fine, scene, surfaces, bake.base.mesh), Log(true));
}

std::string ShadowScene(const std::string& name) {
  return test::WriteShadowScene(test::TempDirectory(name), 0.5f, 0.1f, 200.0f, 0.6f, 1);
}
// The shadow scene's floor peaks at L = R H / pi = 0.5 x 2 W/m^2 / pi = 0.32 W/(m^2 sr) under the light; this
// exposure shows it at grey level 0.66, so the floor spans most of the display range. (The automatic exposure
// of a mesh with four floor vertices and four light vertices would show the floor nearly black.)
constexpr float kShadowExposure = 2.0f;

RefineSettings Adaptive(float tolerance, size_t maxVertices = 200'000) {
  RefineSettings settings;
  settings.adaptive = true;
  settings.tolerance = tolerance;
  settings.maxVertices = maxVertices;
  return settings;
}

// The acceptance test of the issue. 2M photons at h = 0.05 m put about 1,000 photons under each kernel in the
// light, so the estimate's own noise (about 3% of H, under 2% in grey level) stays below the tolerance of 0.03:
// refinement follows the shadow, not the noise. Faces are judged at lattice points at most h/2 apart; the
// line below samples 600 points, 1.25 mm apart, between them.
TEST(Refine, HardShadowEdgeWithinTheToleranceAtAFractionOfUniformVertices) {
  const test::StagedBake bake(ShadowScene("refine_shadow"), 2'000'000, {.bandwidth = 0.05f}, kShadowExposure);
  const RefineSettings settings = Adaptive(0.03f);
  RefineReport adaptiveReport;
  const BakedMesh adaptive = bake.Refine(settings, adaptiveReport);
  const LineError line = ErrorAcrossTheEdge(bake, adaptive, settings.tolerance);
  EXPECT_LE(line.max, settings.tolerance) << line.above << " of " << line.points << " points above the tolerance";
  EXPECT_LE(adaptiveReport.maxError, settings.tolerance);
  EXPECT_EQ(adaptiveReport.refusedByEdgeLength + adaptiveReport.refusedByBudget, 0u);
  EXPECT_GT(adaptiveReport.splits, 20u) << "the shadow's edge was not refined";

  // Uniform subdivision (OpenSubdiv) of the same floor, level by level, until it is as accurate along the line.
  for (int level = 1; level <= 7; ++level) {
    const BakedMesh uniform = UniformMesh(bake, level);
    if (ErrorAcrossTheEdge(bake, uniform, settings.tolerance).max > line.max) continue;
    EXPECT_LE(3 * adaptive.mesh.VertexCount(), uniform.mesh.VertexCount())
        << "adaptive " << adaptive.mesh.VertexCount() << " vertices, uniform level " << level << " "
        << uniform.mesh.VertexCount();
    return;
  }
  ADD_FAILURE() << "uniform subdivision never reached the adaptive mesh's error along the line, " << line.max;
}

// Per-surface sums of face area [m^2], and the bounding box, of a display mesh.
struct Extent {
  std::map<uint32_t, double> area;
  std::array<float, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
};
Extent ExtentOf(const SplitMesh& m) {
  Extent e;
  for (const auto& f : m.faces) {
    const Point3 a = m.positions[f[0]], b = m.positions[f[1]], c = m.positions[f[2]];
    e.area[m.surface[f[0]]] += 0.5 * Length(Cross(b - a, c - a));
  }
  for (const Point3& p : m.positions)
    for (int k = 0; k < 3; ++k) {
      const float x = k == 0 ? p.x : k == 1 ? p.y : p.z;
      e.lo[k] = std::min(e.lo[k], x), e.hi[k] = std::max(e.hi[k], x);
    }
  return e;
}

// How many faces use each undirected edge, by its end points' exact positions (vertices of different surfaces at
// one position are one point): in a watertight mesh with no T-junction every edge has exactly two faces.
std::map<std::array<float, 6>, int> EdgeUses(const SplitMesh& m, uint32_t skipSurface) {
  std::map<std::array<float, 6>, int> uses;
  for (const auto& f : m.faces) {
    if (m.surface[f[0]] == skipSurface) continue;
    for (int k = 0; k < 3; ++k) {
      Point3 a = m.positions[f[k]], b = m.positions[f[(k + 1) % 3]];
      if (std::tie(b.x, b.y, b.z) < std::tie(a.x, a.y, a.z)) std::swap(a, b);
      ++uses[{a.x, a.y, a.z, b.x, b.y, b.z}];
    }
  }
  return uses;
}

TEST(Refine, GeometryIsUnchangedAndTheClosedBoxStaysWatertight) {
  const std::string obj = test::WriteClosedBox(test::TempDirectory("refine_box"), 1.0f, 0.6f, 0.2f, 30.0f);
  const test::StagedBake bake(obj, 1'000'000, {.bandwidth = 0.08f});
  RefineReport report;
  const BakedMesh refined = bake.Refine(Adaptive(0.02f), report);
  EXPECT_GT(report.collapses, 0u);
  EXPECT_GT(report.splits, 0u);

  const Extent before = ExtentOf(bake.base.mesh), after = ExtentOf(refined.mesh);
  ASSERT_EQ(before.area.size(), after.area.size());
  for (const auto& [surface, area] : before.area) EXPECT_NEAR(after.area.at(surface), area, 1e-6 * area) << surface;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(after.lo[k], before.lo[k], 1e-6);
    EXPECT_NEAR(after.hi[k], before.hi[k], 1e-6);
  }
  // No face flipped: each faces the way its surface does, with positive area.
  const SplitMesh& m = refined.mesh;
  for (const auto& f : m.faces) {
    const Vector3 n = Cross(m.positions[f[1]] - m.positions[f[0]], m.positions[f[2]] - m.positions[f[0]]);
    EXPECT_GT(Dot(n, bake.traced.surfaces.surfaces[m.surface[f[0]]].chart.frame.n), 0.0f);
  }
  // The six walls were watertight (the light floats below the ceiling), and still are.
  const uint32_t light = SurfaceOfMaterial(bake, "light");
  for (const SplitMesh* mesh : {&bake.base.mesh, &refined.mesh}) {
    int open = 0;
    for (const auto& [edge, uses] : EdgeUses(*mesh, light)) open += uses != 2;
    EXPECT_EQ(open, 0) << (mesh == &refined.mesh ? "refined" : "input") << " mesh has edges without two faces";
  }
}

// A finely cut floor (16 x 16 cells, 289 vertices) under a light far larger than it: H varies smoothly by a few
// per cent, so all but the corners can go. The estimate must be smooth too: 2M photons at h = 0.25 m put about
// 6,000 photons under each kernel (noise about 1.3% of H); at h = 0.1 m with 1M photons (4.6%) the noise alone
// keeps 85 of the 289 vertices.
TEST(Refine, AUniformlyLitFloorDecimatesToAFewVertices) {
  const std::string obj = test::WriteShadowScene(test::TempDirectory("refine_flat"), 0.5f, 8.0f, 1.0f, 0.0f, 16);
  const test::StagedBake bake(obj, 2'000'000, {.bandwidth = 0.25f});
  RefineReport report;
  const BakedMesh refined = bake.Refine(Adaptive(0.02f), report);
  const uint32_t floor = SurfaceOfMaterial(bake, "floor");
  size_t floorVertices = 0;
  for (uint32_t s : refined.mesh.surface) floorVertices += s == floor;
  EXPECT_EQ(report.verticesBefore, 289u + 4u);
  EXPECT_LE(floorVertices, 8u) << "of 289";
  EXPECT_LE(report.maxError, 0.02);
  const Extent before = ExtentOf(bake.base.mesh), after = ExtentOf(refined.mesh);
  EXPECT_NEAR(after.area.at(floor), 4.0, 4e-6);
}

TEST(Refine, TheVertexBudgetIsKept) {
  const test::StagedBake bake(ShadowScene("refine_budget"), 500'000, {.bandwidth = 0.05f}, kShadowExposure);
  for (size_t budget : {40, 90, 150}) {
    RefineReport report;
    const BakedMesh refined = bake.Refine(Adaptive(0.002f, budget), report);
    EXPECT_LE(refined.mesh.VertexCount(), budget);
    EXPECT_GT(refined.mesh.VertexCount(), budget - 10) << "the budget was not used";
    EXPECT_GT(report.refusedByBudget, 0u);
  }
}

// Refinement cannot tell noise from light: a bake with too few photons for its tolerance is warned about.
TEST(Refine, ANoisierEstimateThanTheToleranceIsWarnedAbout) {
  const std::string obj = ShadowScene("refine_noise");
  for (const auto& [photons, tolerance, warned] : {std::tuple{20'000, 0.01f, true}, std::tuple{2'000'000, 0.03f, false}}) {
    const test::StagedBake bake(obj, photons, {.bandwidth = 0.05f}, kShadowExposure);
    const std::vector<std::string> warnings =
        NoiseWarnings(bake.field, bake.bins, bake.exposure, tolerance);
    EXPECT_EQ(!warnings.empty(), warned) << photons << " photons";
    for (const std::string& w : warnings) EXPECT_NE(w.find("(floor): the estimate's noise"), std::string::npos) << w;
  }
}

TEST(Refine, OneAndTwoThreadsRefineAlike) {
  const test::StagedBake bake(ShadowScene("refine_threads"), 300'000, {.bandwidth = 0.05f}, kShadowExposure);
  std::vector<BakedMesh> meshes;
  for (unsigned threads : {1u, 2u}) {
    const ThreadScope scope(threads);
    RefineReport report;
    meshes.push_back(bake.Refine(Adaptive(0.03f), report));
  }
  ASSERT_EQ(meshes[0].mesh.VertexCount(), meshes[1].mesh.VertexCount());
  EXPECT_EQ(0, std::memcmp(meshes[0].mesh.positions.data(), meshes[1].mesh.positions.data(),
                           meshes[0].mesh.VertexCount() * sizeof(Point3)));
  EXPECT_EQ(0, std::memcmp(meshes[0].irradiance.data(), meshes[1].irradiance.data(),
                           meshes[0].mesh.VertexCount() * sizeof(Rgb)));
}

// A Ctrl-C during refinement (here, as coarsening starts) stops it: the bake writes the mesh it had, the bytes of
// the same bake unrefined, and says so. Before, a Ctrl-C after the estimate ended the bake at once.
TEST(Refine, CtrlCDuringRefinementWritesTheMeshUnrefined) {
  const std::string dir = test::TempDirectory("refine-ctrl-c");
  BakeOptions o;
  o.scenePath = PB_SOURCE_DIR "/data/box/box.obj";
  o.photons = 50'000;
  o.estimator.bandwidth = 0.05f;
  o.direct.samples = 16;
  o.quiet = true;
  o.outputPath = dir + "/unrefined.ply";
  Bake(o, Log(true));
  o.refine.adaptive = true;
  o.outputPath = dir + "/refined.ply";
  std::vector<std::string> lines;
  const BakeReport r = Bake(o, Log(true, [&](const std::string& line) {
                              lines.push_back(line);
                              if (line.starts_with("coarsen mesh")) RequestInterrupt();
                            }));
  EXPECT_FALSE(r.refine.ran);
  EXPECT_TRUE(std::any_of(lines.begin(), lines.end(), [](const std::string& line) {
    return line.find("warning: Ctrl-C stopped refinement; the mesh is written as estimated, unrefined") !=
           std::string::npos;
  }));
  EXPECT_TRUE(test::ReadBytes(dir + "/refined.ply") == test::ReadBytes(dir + "/unrefined.ply"));
}

}  // namespace
}  // namespace pb
