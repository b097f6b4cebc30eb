// Covered parts of surfaces (estimators/surface_cover.h): where other geometry stands or lies on a surface, no
// light is estimated into it and none is lost beside it.
//  - Geometry: a slab lying on a floor covers its footprint (to the bisection's precision); a block against the
//    floor's edge covers only the floor's part of its footprint; a one-sided table top over the floor covers
//    nothing; the box's two blocks cover their footprints and nothing else does.
//  - A closed form: a thin (1 mm, so that its shadow is negligible) black slab on a black floor under a square
//    light. Floor vertices under the slab read 0 exactly (no photon reaches them, and no kernel reaches across
//    the contact line). Floor vertices beside it match the estimator's own expectation within 5 sigma: Lambert's
//    E integrated against the local linear fit's weights over the open floor only. That expectation differs
//    from E itself by the fit's second-order bias, which the test bounds separately (1%).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "baker/0_prepare_scene.h"
#include "baker/bake.h"
#include "estimators/kernels.h"
#include "tests/lambert.h"
#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

// A box [x0, x1] x [y0, y1] x [z0, z1], closed (six faces, outward), of material `material`.
std::string Box(double x0, double x1, double y0, double y1, double z0, double z1, int firstVertex,
                const std::string& material) {
  std::string obj;
  for (double y : {y0, y1})
    for (auto [x, z] : {std::pair{x0, z0}, std::pair{x1, z0}, std::pair{x1, z1}, std::pair{x0, z1}})
      obj += "v " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + "\n";
  const auto f = [&](int a, int b, int c, int d) {
    return "f " + std::to_string(firstVertex + a) + " " + std::to_string(firstVertex + b) + " " +
           std::to_string(firstVertex + c) + " " + std::to_string(firstVertex + d) + "\n";
  };
  obj += "usemtl " + material + "\n";
  obj += f(4, 7, 6, 5) + f(0, 1, 2, 3) + f(0, 4, 5, 1) + f(1, 5, 6, 2) + f(2, 6, 7, 3) + f(3, 7, 4, 0);
  return obj;
}
// A slab [x0, x1] x [0, height] x [z0, z1] on the floor.
std::string Slab(double x0, double x1, double z0, double z1, double height, int firstVertex, const std::string& material) {
  return Box(x0, x1, 0, height, z0, z1, firstVertex, material);
}

// A black 2 x 2 m floor y = 0, cut into 20 x 20 quads, under a 0.5 m square light of radiance 10 at height 1,
// with `extra` OBJ text (of `extraVertices` vertices, numbered from 5) between the light and the floor.
std::string WithGriddedFloor(const std::string& dir, const std::string& extra, int extraVertices) {
  test::WriteText(dir + "/c.mtl", "newmtl black\nKd 0 0 0\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n"
                                  "newmtl glass\nKd 0 0 0\nNi 1.5\nillum 4\n");
  std::string obj = "mtllib c.mtl\nv -0.25 1 -0.25\nv 0.25 1 -0.25\nv 0.25 1 0.25\nv -0.25 1 0.25\n"
                    "usemtl lamp\nf 1 2 3 4\n" + extra;
  const int first = 5 + extraVertices;
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i)
      obj += "v " + std::to_string(-1 + 0.1 * i) + " 0 " + std::to_string(-1 + 0.1 * j) + "\n";
  obj += "usemtl black\n";
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) {
      const int a = first + j * 21 + i;
      obj += "f " + std::to_string(a) + " " + std::to_string(a + 21) + " " + std::to_string(a + 22) + " " +
             std::to_string(a + 1) + "\n";
    }
  test::WriteText(dir + "/c.obj", obj);
  return dir + "/c.obj";
}

// The floor's surface: the one of 4 m^2 facing up.
uint32_t Floor(const PreparedScene& p) {
  for (uint32_t s = 0; s < p.surfaces.surfaces.size(); ++s)
    if (p.surfaces.surfaces[s].area > 3.9 && p.surfaces.surfaces[s].chart.frame.n.y > 0.99f) return s;
  ADD_FAILURE() << "no floor";
  return 0;
}
const SurfaceCover& FloorCover(const PreparedScene& p) { return p.covers[Floor(p)]; }

PreparedScene Prepare(const std::string& path) {
  StageClock clock;
  return PrepareScene(SceneSettings{path, 1.0f, {}}, clock);
}

TEST(Cover, ASlabLyingOnTheFloorCoversItsFootprint) {
  const std::string dir = test::TempDirectory("cover-slab");
  const PreparedScene p = Prepare(WithGriddedFloor(dir, Slab(0.13, 0.77, -0.23, 0.27, 0.001, 5, "black"), 8));
  const SurfaceCover& cover = FloorCover(p);
  // Its sides are found to the lattice spacing s / 1024, on the covered side (s = 25 mm), and its corners are
  // recovered inside their cells: 2.28 m of perimeter lose at most 2.28 s / 1024 = 5.6e-5 m^2 (marching squares
  // alone cut up to s^2 / 2 = 3.1e-4 m^2 at each corner).
  EXPECT_NEAR(cover.Area(), 0.64 * 0.5, 2.28 * 0.025 / 1024);
  EXPECT_LE(cover.Area(), 0.64 * 0.5);
  const SurfaceChart& chart = p.surfaces.surfaces[Floor(p)].chart;
  const auto covered = [&](double x, double z) { return cover.Covered(chart.ToUv(Point3{float(x), 0, float(z)})); };
  EXPECT_TRUE(covered(0.45, 0.02));
  EXPECT_TRUE(covered(0.135, 0.0));  // 5 mm inside its edge
  EXPECT_TRUE(covered(0.16, -0.2));  // 3 cm in from a corner, both ways
  EXPECT_TRUE(covered(0.1305, 0.2695));  // half a millimetre in from a corner, both ways
  EXPECT_FALSE(covered(0.125, 0.0));
  EXPECT_FALSE(covered(0.45, 0.28));
  EXPECT_FALSE(covered(-0.5, -0.5));
}

TEST(Cover, ABlockAgainstTheFloorsEdgeCoversOnlyTheFloor) {
  const std::string dir = test::TempDirectory("cover-edge");
  // x in [0.8, 1.2]: half of it beyond the floor's edge at x = 1.
  const PreparedScene p = Prepare(WithGriddedFloor(dir, Slab(0.8, 1.2, -0.2, 0.2, 0.3, 5, "black"), 8));
  // Two corners on the floor, each left cut by at most s^2 / 8 (when it lies within s / 4 of a lattice line). The
  // block's bottom lies on the floor (PressedAt), so the cover reaches the footprint's edge to the contact test's
  // rounding (a millionth of the block's bottom, at most 1e-6 m^2 over).
  EXPECT_NEAR(FloorCover(p).Area(), 0.2 * 0.4, 2 * 0.025 * 0.025 / 8);
  EXPECT_LE(FloorCover(p).Area(), 0.2 * 0.4 + 1e-6);
}

// A block standing on the floor with its side against a wall (x = 1, facing the block): flush, and sunk into the
// wall by 0.3 mm (touching is within 2^-11 of the scene's size, 0.49 mm here). Rays from the floor under it that run to its side meet the wall's front and the
// block's back in the same place (flush; which one first is the BVH's choice) or the wall's front first (sunk);
// either way the block's closed side decides, and its whole footprint is covered.
TEST(Cover, ABlockAgainstAWallCoversItsWholeFootprint) {
  for (const double side : {1.0, 1.0003}) {
    const std::string dir = test::TempDirectory("cover-wall");
    const std::string wall = "v 1 0 -1\nv 1 0 1\nv 1 1 1\nv 1 1 -1\nusemtl black\nf 5 6 7 8\n";
    const PreparedScene p = Prepare(WithGriddedFloor(dir, wall + Slab(0.6, side, -0.2, 0.2, 0.3, 9, "black"), 12));
    // Three corners in the floor, the fourth where the wall meets it: each left cut by at most s^2 / 8.
    EXPECT_NEAR(FloorCover(p).Area(), 0.4 * 0.4, 3 * 0.025 * 0.025 / 8) << "side at x = " << side;
    EXPECT_LE(FloorCover(p).Area(), 0.4 * 0.4 + 1e-6);
  }
}

// A block in the corner of two walls (flush with both): its cover runs to the floor's outline, which the cover's
// bisection leaves a step outside it; the floor's vertices along the walls under the block are tested as points
// (IrradianceField::AtItsCoversRim) and read no light, as the path tracer's do. Both ways round: the corner at
// +x +z and at -x -z.
TEST(Cover, TheFloorsOutlineUnderABlockInACornerReadsNoLight) {
  for (const double c : {1.0, -1.0}) {
    const std::string dir = test::TempDirectory("cover-corner");
    // Walls x = c and z = c, each facing the floor's centre.
    const std::string walls = c > 0 ? "v 1 0 -1\nv 1 0 1\nv 1 1 1\nv 1 1 -1\nv -1 0 1\nv -1 1 1\nv 1 1 1\nv 1 0 1\n"
                                    : "v -1 0 -1\nv -1 1 -1\nv -1 1 1\nv -1 0 1\nv -1 0 -1\nv 1 0 -1\nv 1 1 -1\nv -1 1 -1\n";
    BakeOptions o;
    o.scenePath = WithGriddedFloor(dir, walls + "usemtl black\nf 5 6 7 8\nf 9 10 11 12\n" +
                                            Slab(std::min(c, 0.6 * c), std::max(c, 0.6 * c), std::min(c, 0.6 * c),
                                                 std::max(c, 0.6 * c), 0.3, 13, "black"), 16);
    o.outputPath = dir + "/out.ply";
    o.photons = 200'000;
    o.estimator.bandwidth = 0.5f;  // reaching the open floor beside the block
    Bake(o, Log(true));
    const test::PlyData ply = test::ReadPly(o.outputPath);
    int outline = 0;
    for (size_t v = 0; v < ply.VertexCount(); ++v) {
      const double x = ply.vertex.at("x")[v] * c, y = ply.vertex.at("y")[v], z = ply.vertex.at("z")[v] * c;
      if (y != 0.0 || ply.vertex.at("ny")[v] < 0.99) continue;  // the floor's vertices only
      if (!((x == 1.0 && z > 0.65) || (z == 1.0 && x > 0.65))) continue;  // not the contact lines' ends
      EXPECT_EQ(ply.vertex.at("irradiance_g")[v], 0.0) << "under the block at (" << x * c << ", " << z * c << ")";
      ++outline;
    }
    EXPECT_EQ(outline, 7);  // 0.7, 0.8, 0.9 and 1 along each wall, the corner once
  }
}

// The bathroom of `make-scene glass-room`, its bath (a closed box) in the corner of two walls (x = 0 and z = 0,
// over x < 1.7, z < 0.75), lit only through the window. No light reaches:
//  - the floor's vertices along the walls under the bath: they lie on the cover's rim, which the cover's bisection
//    leaves a step outside the cover; with h = 0.75 m their open-domain estimate reached the lit floor beside the
//    bath (0.3-0.5 W/m^2). Tested as points (IrradianceField::AtItsCoversRim).
//  - the bath's own faces pressed against the walls and the floor: their shadow rays, spawned off them, started
//    behind the wall and found the sky outside (0.07-0.16 W/m^2 on average). PressedAt covers them whole.
TEST(Cover, NoLightReachesUnderOrBehindTheBath) {
  const std::string dir = test::TempDirectory("cover-bath");
  ASSERT_EQ(test::RunTool(PB_MAKE_SCENE_EXE, "glass-room --out " + dir).status, 0);
  BakeOptions o;
  o.scenePath = dir + "/room.obj";
  o.outputPath = dir + "/out.ply";
  o.photons = 100'000;
  o.estimator.bandwidth = 0.75f;
  Bake(o, Log(true));
  const test::PlyData ply = test::ReadPly(o.outputPath);
  int outline = 0, pressed = 0;
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    const double x = ply.vertex.at("x")[v], y = ply.vertex.at("y")[v], z = ply.vertex.at("z")[v];
    const double ny = ply.vertex.at("ny")[v], nx = ply.vertex.at("nx")[v], nz = ply.vertex.at("nz")[v];
    const double H = ply.vertex.at("irradiance_g")[v];
    const bool underTheBath = x <= 1.7 && z <= 0.75 && y == 0.0;
    if (underTheBath && ny > 0.99) {  // the floor's vertices
      // Not the contact lines' ends, nor the room's corner (x = z = 0), where three surfaces meet and RayStart's
      // step inward is along neither wall.
      if (!((x == 0.0 && z > 0.05 && z < 0.72) || (z == 0.0 && x > 0.05 && x < 1.65))) continue;
      EXPECT_EQ(H, 0.0) << "the floor under the bath at (" << x << ", " << z << ")";
      ++outline;
    }
    const bool bathsBottom = underTheBath && ny < -0.99, bathsBack = z == 0.0 && x <= 1.7 && y <= 0.55 && nz < -0.99,
               bathsEnd = x == 0.0 && z <= 0.75 && y <= 0.55 && nx < -0.99;
    if (bathsBottom || bathsBack || bathsEnd) {
      EXPECT_EQ(H, 0.0) << "the bath's face against the floor or a wall at (" << x << ", " << y << ", " << z << ")";
      ++pressed;
    }
  }
  EXPECT_EQ(outline, 23);  // every 10 cm: z = 0.1 to 0.7 along x = 0, x = 0.1 to 1.6 along z = 0
  EXPECT_GT(pressed, 300);
}

TEST(Cover, AOneSidedTableTopOverTheFloorCoversNothing) {
  const std::string dir = test::TempDirectory("cover-table");
  // One quad facing up at 0.4 m: the floor under it sees its back, but its grazing rays get out.
  const std::string table = "v -0.5 0.4 -0.5\nv -0.5 0.4 0.5\nv 0.5 0.4 0.5\nv 0.5 0.4 -0.5\nusemtl black\nf 5 6 7 8\n";
  const PreparedScene p = Prepare(WithGriddedFloor(dir, table, 4));
  EXPECT_TRUE(FloorCover(p).Empty());
}

// OBJ statements `obj` with materials grey (Kd 0.5) and lamp (Ke 10), prepared.
PreparedScene PrepareGreyUnderLamp(const std::string& name, const std::string& obj) {
  const std::string dir = test::TempDirectory(name);
  test::WriteText(dir + "/c.mtl", "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n");
  test::WriteText(dir + "/c.obj", "mtllib c.mtl\n" + obj);
  return Prepare(dir + "/c.obj");
}

// A 20 x 20 m floor with nothing on it: its lattice (s = 25 mm) has 646,416 points, but rays are cast only in the
// band along its outline (4 x 800 cells, the corners of each: about 6,400 points). Fails if the whole lattice is
// probed.
TEST(Cover, AFloorWithNothingOnItProbesOnlyItsOutline) {
  const PreparedScene p = PrepareGreyUnderLamp("cover-empty-floor",
                                               "v -0.25 1 -0.25\nv 0.25 1 -0.25\nv 0.25 1 0.25\nv -0.25 1 0.25\n"
                                               "usemtl lamp\nf 1 2 3 4\nv -10 0 -10\nv -10 0 10\nv 10 0 10\n"
                                               "v 10 0 -10\nusemtl grey\nf 5 6 7 8\n");
  uint32_t floor = 0;
  for (uint32_t s = 0; s < p.surfaces.surfaces.size(); ++s)
    if (p.surfaces.surfaces[s].area > 399) floor = s;
  EXPECT_TRUE(p.covers[floor].Empty());
  EXPECT_GE(p.covers[floor].ProbedPoints(), 4u * 800);  // the outline is probed
  EXPECT_LT(p.covers[floor].ProbedPoints(), 4u * 800 * 3);
}

// A one-sided lamp (1.2 x 0.3 m) hanging 1 cm under a ceiling, facing down, as the offices' lamps do: the
// ceiling's points behind it whose rays, the lowest 10 degrees below the ceiling, all meet the lamp's back are
// covered. Each side is cut by about 1 cm / tan(10 deg) = 57 mm, less the spiral's azimuths allow: at most
// (1.2 - 0) x 0.3 m, at least (1.2 - 0.12) x (0.3 - 0.12) m. Fails when the lamp is not found within reach.
TEST(Cover, ALampJustUnderACeilingCoversTheCeilingBehindIt) {
  const PreparedScene p = PrepareGreyUnderLamp("cover-lamp",
                                               "v -0.6 2.99 -0.15\nv 0.6 2.99 -0.15\nv 0.6 2.99 0.15\nv -0.6 2.99 0.15\n"
                                               "usemtl lamp\nf 1 2 3 4\nv -2 3 -2\nv 2 3 -2\nv 2 3 2\nv -2 3 2\n"
                                               "usemtl grey\nf 5 6 7 8\nv -2 0 -2\nv -2 0 2\nv 2 0 2\nv 2 0 -2\n"
                                               "f 9 10 11 12\n");
  double ceiling = -1;
  for (uint32_t s = 0; s < p.surfaces.surfaces.size(); ++s)
    if (p.surfaces.surfaces[s].chart.frame.n.y < -0.99f) ceiling = p.covers[s].Area();
  EXPECT_GT(ceiling, (1.2 - 0.12) * (0.3 - 0.12));
  EXPECT_LT(ceiling, 1.2 * 0.3);
}

TEST(Cover, TheBoxsBlocksCoverTheirFootprintsAndNothingElseIsCovered) {
  const PreparedScene p = Prepare(PB_SOURCE_DIR "/data/box/box.obj");
  double covered = 0;
  size_t coveredSurfaces = 0;
  for (const SurfaceCover& c : p.covers)
    if (!c.Empty()) covered += c.Area(), ++coveredSurfaces;
  EXPECT_EQ(coveredSurfaces, 1u) << "only the floor";
  // The published blocks' footprints (cornell-box.md, by the shoelace formula): 0.027633 + 0.0276265 m^2, less
  // at most s^2 / 8 at each of their 8 corners (a corner within s / 4 of a lattice line stays cut). Measured:
  // 9.8e-5 m^2 less.
  EXPECT_NEAR(covered, 0.0552595, 8 * 0.025 * 0.025 / 8);
  EXPECT_LE(covered, 0.0552595);
}

// At a kernel much wider than the mesh (h = 0.08 m over the 25 mm box), every floor vertex 1 mm or more inside a
// block's footprint reads exactly 0: the cover lattice is at most 10 mm apart, so no footprint corner is cut past
// a vertex. At h/2 = 40 mm the short block's corner was cut past the vertex (0.2397, 0.2674), 4.6 mm inside it,
// which read the open floor's light.
TEST(Cover, AWideKernelLeavesNoFloorVertexUnderTheBlocksLit) {
  BakeOptions o;
  o.scenePath = PB_SOURCE_DIR "/data/box/box_25mm.obj";
  o.outputPath = test::TempDirectory("cover-wide") + "/box.ply";
  o.photons = 200'000;
  o.estimator.bandwidth = 0.08f;
  Bake(o, Log(true));
  const test::PlyData ply = test::ReadPly(o.outputPath);
  // The published footprints [mm], counter-clockwise seen from above (cornell-box.md).
  const std::vector<std::vector<std::pair<double, double>>> footprints = {
      {{130, 65}, {82, 225}, {240, 272}, {290, 114}}, {{423, 247}, {265, 296}, {314, 456}, {472, 406}}};
  const auto depthInside = [](const std::vector<std::pair<double, double>>& f, double x, double z) {
    double depth = 1e9;  // the least signed distance to an edge's line, positive inside [mm]
    for (size_t k = 0; k < f.size(); ++k) {
      const auto [ax, az] = f[k];
      const auto [bx, bz] = f[(k + 1) % f.size()];
      const double ex = bx - ax, ez = bz - az, length = std::hypot(ex, ez);
      depth = std::min(depth, ((x - ax) * ez - (z - az) * ex) / length);
    }
    return depth;
  };
  int under = 0;
  for (size_t v = 0; v < ply.vertex.at("x").size(); ++v) {
    if (ply.vertex.at("y")[v] != 0) continue;
    const double x = 1000 * ply.vertex.at("x")[v], z = 1000 * ply.vertex.at("z")[v];
    for (const auto& f : footprints) {
      const double depth = std::max(depthInside(f, x, z), depthInside({f.rbegin(), f.rend()}, x, z));
      if (depth < 1) continue;
      ++under;
      EXPECT_EQ(ply.vertex.at("irradiance_g")[v], 0.0) << x << ", " << z << " mm, " << depth << " mm inside";
    }
  }
  EXPECT_GT(under, 80);
}

// Lambert's E at a floor point under the scene's light.
double Lambert(double x, double z) {
  static const std::vector<test::V3> light = {{-0.25, 1, -0.25}, {0.25, 1, -0.25}, {0.25, 1, 0.25}, {-0.25, 1, 0.25}};
  return test::LambertPolygonIrradiance({x, 0, z}, {0, 1, 0}, light, 10.0);
}

// What the edge-corrected Epanechnikov estimate at (x, z) converges to, and its standard deviation for photons of
// flux phi [W]. The local linear estimate (kernel_estimator.h) weights a photon at offset t by w(t) = K(t)
// (1 - c.t) / (m0 - c.m1), with m0, m1, m2 the kernel's moments over the open floor within h and c = m2^-1 m1;
// its mean is integral(w E) and its variance phi integral(w^2 E) (Poisson positions). By the midpoint rule on a
// 200 x 200 grid over the kernel's square.
struct Expectation {
  double mean = 0, sigma = 0;
};
Expectation Expected(double x, double z, double h, double phi, bool (*open)(double, double)) {
  constexpr int kSteps = 200;
  const double dA = (2 * h / kSteps) * (2 * h / kSteps);
  struct Node {
    double dx, dz, k, E;
  };
  std::vector<Node> nodes;
  double m0 = 0, mx = 0, mz = 0, sxx = 0, sxz = 0, szz = 0;
  for (int j = 0; j < kSteps; ++j)
    for (int i = 0; i < kSteps; ++i) {
      const double dx = h * (2 * (i + 0.5) / kSteps - 1), dz = h * (2 * (j + 0.5) / kSteps - 1);
      const double k = KernelDensity(Kernel::kEpanechnikov, float(dx * dx + dz * dz), float(h)) * dA;
      if (k <= 0 || !open(x + dx, z + dz)) continue;
      nodes.push_back({dx, dz, k, Lambert(x + dx, z + dz)});
      m0 += k, mx += k * dx, mz += k * dz, sxx += k * dx * dx, sxz += k * dx * dz, szz += k * dz * dz;
    }
  const double det = sxx * szz - sxz * sxz;
  const double cx = (szz * mx - sxz * mz) / det, cz = (sxx * mz - sxz * mx) / det;
  const double denominator = m0 - (cx * mx + cz * mz);
  Expectation e;
  double variance = 0;
  for (const Node& n : nodes) {
    const double w = n.k * (1 - (cx * n.dx + cz * n.dz)) / denominator;
    e.mean += w * n.E;
    variance += phi * w * w / dA * n.E;
  }
  e.sigma = std::sqrt(variance);
  return e;
}

bool OpenFloor(double x, double z) {
  const bool underSlab = x > 0.13 && x < 0.77 && z > -0.23 && z < 0.27;
  return std::fabs(x) <= 1 && std::fabs(z) <= 1 && !underSlab;
}

TEST(Cover, AThinSlabOnAFloorDarkensOnlyWhatItCovers) {
  const std::string dir = test::TempDirectory("cover-slab-bake");
  BakeOptions o;
  o.scenePath = WithGriddedFloor(dir, Slab(0.13, 0.77, -0.23, 0.27, 0.001, 5, "black"), 8);
  o.outputPath = dir + "/out.ply";
  o.photons = 2'000'000;
  o.estimator.bandwidth = 0.1f;
  Bake(o, Log(true));
  const test::PlyData ply = test::ReadPly(o.outputPath);
  const double phi = 10 * M_PI * 0.25 / double(o.photons), h = *o.estimator.bandwidth;
  int under = 0, beside = 0;
  double worstBias = 0;
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    const double x = ply.vertex.at("x")[v], y = ply.vertex.at("y")[v], z = ply.vertex.at("z")[v];
    const double H = ply.vertex.at("irradiance_g")[v];
    if (y != 0.0 || ply.vertex.at("ny")[v] < 0.99) continue;  // the floor's vertices only
    if (!OpenFloor(x, z)) {
      EXPECT_EQ(H, 0.0) << "under the slab at (" << x << ", " << z << ")";
      ++under;
      continue;
    }
    const bool nearSlab = x > 0.13 - h && x < 0.77 + h && z > -0.23 - h && z < 0.27 + h;
    if (!nearSlab) continue;
    const Expectation expected = Expected(x, z, h, phi, OpenFloor);
    EXPECT_NEAR(H, expected.mean, 5 * expected.sigma) << "beside the slab at (" << x << ", " << z << ")";
    worstBias = std::max(worstBias, std::fabs(expected.mean / Lambert(x, z) - 1));
    ++beside;
  }
  EXPECT_EQ(under, 6 * 5);
  EXPECT_GE(beside, 20);
  // The local linear fit leaves no first-order bias where E has a gradient across the contact line (measured:
  // 0.41% at worst); renormalisation left 0.34 h |grad E| / E, up to 5% here.
  EXPECT_LT(worstBias, 0.01);
}

// A post 2 cm square from y = 0.1 to 0.5 m (its sides narrower than two lattice spacings, so no cover lattice is laid
// on them) whose foot stands in a closed block 0.15 m tall, every photon's first hit stored (--direct photons): the
// vertices of its sides at y = 0.1, inside the block, read 0, though the post's lit part lies within h of them and
// the kernel, renormalised at the edges, reaches it (it reads 0.03-0.14 W/m^2 there without the test); those above the block read light. In a closed glass block instead, which lets light in, the foot reads light too.
TEST(Cover, APostsFootInsideAClosedBlockReadsNoLight) {
  for (const std::string block : {"black", "glass"}) {
    const std::string dir = test::TempDirectory("cover-post-" + block);
    BakeOptions o;
    // The block floats 1 mm over the floor: where its base lies in the floor's plane, Embree meets either face first,
    // so rays cast down from inside may leave through the floor, and the foot stays read as open (as before the test).
    o.scenePath = WithGriddedFloor(dir, Box(-0.3, 0.3, 0.001, 0.15, -0.3, 0.3, 5, block) +
                                            Box(-0.01, 0.01, 0.1, 0.5, -0.01, 0.01, 13, "black"), 16);
    o.photons = 400'000;
    o.estimator.bandwidth = 0.1f;
    o.direct.mode = DirectLight::kPhotons;  // the photons bring all the light, so the kernel would carry it down
    o.estimator.localLinear = false;        // renormalised only: a linear fit extrapolates the light's rise below 0
    const BakedMesh baked = BakeMesh(o, Log(true)).mesh;
    int foot = 0, above = 0;
    for (size_t v = 0; v < baked.mesh.positions.size(); ++v) {
      const Point3 p = baked.mesh.positions[v] + Vector3{float(baked.mesh.origin[0]), float(baked.mesh.origin[1]),
                                                         float(baked.mesh.origin[2])};
      const bool onPostSide = std::abs(p.x) <= 0.0101f && std::abs(p.z) <= 0.0101f && std::abs(baked.mesh.normals[v].y) < 0.1f;
      if (!onPostSide) continue;
      const double H = Luminance(baked.irradiance[v]);
      if (p.y < 0.11f) {
        ++foot;
        if (block == "black") EXPECT_EQ(H, 0.0) << "the post's foot at (" << p.x << ", " << p.y << ", " << p.z << ")";
        else EXPECT_GT(H, 0.0) << "the post's foot in glass at (" << p.x << ", " << p.y << ", " << p.z << ")";
      } else {
        ++above;
        EXPECT_GT(H, 0.0) << "the post above the block at (" << p.x << ", " << p.y << ", " << p.z << ")";
      }
    }
    EXPECT_EQ(foot, 8) << block;  // four sides, two corners each
    EXPECT_EQ(above, 8) << block;
  }
}

}  // namespace
}  // namespace pb
