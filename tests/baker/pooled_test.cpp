// Sparse surfaces pooled (estimators/pooled_estimator.h, with --h auto) in a bake, on a closed form: a 0.3 m square
// light of radiance 10 at 0.5 m over a 1 m floor cut into 16 x 16 cells, each its own material (the same grey), so
// each cell is a surface of its own, and 30,000 photons leave most of them (all but those under the light) with fewer
// than kPooledBelowHits. With --direct
// photons the photons carry all of H, which Lambert's polygon formula gives exactly (tests/lambert.h).
//  - Pooled, the floor reads Lambert's H within its own predicted noise: the RMS error over the vertices is at most
//    1.5 times the RMS of their predicted sigma plus 3% for the pooling's smoothing over r ~ 7 cm (E changes by
//    about 4% over 7 cm at the light's rim); each cell on its own (pooling off), with the h that --h auto gives it,
//    reads at least 1.5 times worse (measured: 24% pooled, 44% alone), which shows the check can fail.
//  - The pooled bake is the same, bit for bit, on one thread and on two; the report counts the pooled surfaces, their
//    vertices and the share of the light the pooled photons bring.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "baker/bake.h"
#include "tests/lambert.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

constexpr int kCells = 16;
constexpr float kLight = 0.3f, kHeight = 0.5f, kRadiance = 10;

std::string WriteCutFloor(const std::string& directory) {
  std::string mtl = fmt::format("newmtl light\nKd 0 0 0\nKe {0} {0} {0}\n", kRadiance);
  std::string obj = "mtllib cut.mtl\n";
  int vertex = 1;
  const float step = 1.0f / kCells;
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      mtl += fmt::format("newmtl cell_{}_{}\nKd 0.5 0.5 0.5\n", i, j);
      obj += fmt::format("usemtl cell_{}_{}\n", i, j);
      const float x = -0.5f + i * step, z = -0.5f + j * step;
      // Facing +y: counter-clockwise seen from above.
      obj += fmt::format("v {} 0 {}\nv {} 0 {}\nv {} 0 {}\nv {} 0 {}\n", x, z + step, x + step, z + step, x + step, z, x, z);
      obj += fmt::format("f {} {} {} {}\n", vertex, vertex + 1, vertex + 2, vertex + 3);
      vertex += 4;
    }
  const float l = kLight / 2;
  obj += "usemtl light\n";  // facing -y: counter-clockwise seen from below
  obj += fmt::format("v {0} {1} {0}\nv {2} {1} {0}\nv {2} {1} {2}\nv {0} {1} {2}\n", -l, kHeight, l);
  obj += fmt::format("f {} {} {} {}\n", vertex, vertex + 1, vertex + 2, vertex + 3);
  test::WriteText(directory + "/cut.mtl", mtl);
  test::WriteText(directory + "/cut.obj", obj);
  return directory + "/cut.obj";
}

BakeResult BakeCutFloor(unsigned threads, bool pooled = true) {
  static const std::string scene = WriteCutFloor(test::TempDirectory("pooled"));
  BakeOptions o;
  o.scenePath = scene;
  o.photons = 30'000;
  o.direct.mode = DirectLight::kPhotons;
  o.estimator.bandwidth.reset();  // --h auto
  o.threads = threads;
  if (!pooled) {  // each cell on its own, with the h --h auto chose it
    const BakeResult automatic = BakeMesh(o, Log(true));
    o.estimator.bandwidth = float(automatic.report.surfaces[0].bandwidth);
  }
  return BakeMesh(o, Log(true));
}

struct FloorError {
  double rms = 0, predicted = 0;  // relative to the mean exact H
};
FloorError ErrorOf(const BakedMesh& b) {
  double sum2 = 0, predicted2 = 0, exact = 0;
  size_t n = 0;
  for (size_t v = 0; v < b.mesh.VertexCount(); ++v) {
    const Point3 p = b.mesh.positions[v];
    if (std::abs(p.y) > 1e-4f) continue;  // the floor only
    const double e = test::LambertPolygonIrradiance(
        {p.x + b.mesh.origin[0], 0, p.z + b.mesh.origin[2]}, {0, 1, 0},
        {{-kLight / 2, kHeight, -kLight / 2}, {kLight / 2, kHeight, -kLight / 2}, {kLight / 2, kHeight, kLight / 2},
         {-kLight / 2, kHeight, kLight / 2}},
        kRadiance);
    const double h = Luminance(b.irradiance[v]);
    sum2 += (h - e) * (h - e), predicted2 += std::pow(h * b.irradianceNoise[v], 2), exact += e, ++n;
  }
  const double mean = exact / double(n);
  return {std::sqrt(sum2 / double(n)) / mean, std::sqrt(predicted2 / double(n)) / mean};
}

TEST(Pooled, AFloorCutIntoSparseSurfacesReadsLambertWithinItsNoise) {
  const BakeResult pooled = BakeCutFloor(0);
  EXPECT_GT(pooled.report.pooled.surfaces, uint32_t(kCells * kCells / 2));  // those under the light hold more
  // The report says how much of the light the pooled photons bring (all of their vertices' H, with --direct photons)
  // and over what reach, since the predicted bias does not count their smoothing.
  const BakeReport::Pooled& said = pooled.report.pooled;
  EXPECT_GT(said.vertices, pooled.mesh.mesh.VertexCount() / 2);
  EXPECT_LT(said.vertices, pooled.mesh.mesh.VertexCount());
  EXPECT_GT(said.lightShare, 0.05);
  EXPECT_LT(said.lightShare, 0.95);  // the cells under the light hold photons of their own
  EXPECT_GT(said.reach, 0.0);
  const FloorError e = ErrorOf(pooled.mesh);
  EXPECT_GT(e.predicted, 0.02);
  EXPECT_LE(e.rms, 1.5 * e.predicted + 0.03) << "predicted " << e.predicted;
  const FloorError alone = ErrorOf(BakeCutFloor(0, false).mesh);
  EXPECT_GT(alone.rms, 1.5 * e.rms) << "each cell on its own: " << alone.rms << ", pooled: " << e.rms;
}

TEST(Pooled, TheSameOnAnyThreadCount) {
  const BakeResult one = BakeCutFloor(1), two = BakeCutFloor(2);
  ASSERT_EQ(one.mesh.irradiance.size(), two.mesh.irradiance.size());
  for (size_t v = 0; v < one.mesh.irradiance.size(); ++v) {
    ASSERT_EQ(one.mesh.irradiance[v], two.mesh.irradiance[v]) << "vertex " << v;
    ASSERT_EQ(one.mesh.irradianceNoise[v], two.mesh.irradianceNoise[v]) << "vertex " << v;
  }
}

}  // namespace
}  // namespace pb
