// The predicted error per surface (baker/photons/progressive.h, PredictedErrorPerSurface): each surface's own RMS of
// noise and bias over its vertices, relative to its own mean H, where the bake's figure is dominated by the
// brightest surfaces.
#include <gtest/gtest.h>

#include <cmath>

#include "baker/photons/progressive.h"

namespace pb {
namespace {

// Two triangles, surfaces 0 and 1, far apart: surface 0 lit at H = 1 with 1% noise, surface 1 at H `dim` with 40%
// noise and 30% smoothing bias (a room lit through a door left ajar).
BakedMesh TwoRooms(float dim) {
  BakedMesh b;
  for (uint32_t s = 0; s < 2; ++s) {
    const float x = 10.0f * float(s);
    for (Point3 p : {Point3{x, 0, 0}, Point3{x + 1, 0, 0}, Point3{x, 0, 1}}) b.mesh.AddVertex(p, {0, 1, 0}, {p.x, p.z}, {}, s, 1);
    b.mesh.faces.push_back({3 * s, 3 * s + 1, 3 * s + 2});
  }
  b.irradiance = {Rgb{1, 1, 1}, Rgb{1, 1, 1}, Rgb{1, 1, 1}, Rgb{dim, dim, dim}, Rgb{dim, dim, dim}, Rgb{dim, dim, dim}};
  b.albedo.assign(6, Rgb{0.5f, 0.5f, 0.5f}), b.emitted.assign(6, Rgb{});
  b.irradianceNoise = {0.01, 0.01, 0.01, 0.4, 0.4, 0.4};
  b.irradianceBias = {0, 0, 0, 0.3, 0.3, 0.3};
  b.photonVarianceShare.assign(6, 1.0);
  return b;
}

TEST(PredictedErrorPerSurface, EachSurfaceReadsItsOwnErrorRelativeToItsOwnMean) {
  const BakedMesh b = TwoRooms(0.01f);
  const std::vector<BakeError> each = PredictedErrorPerSurface(b, 2);
  ASSERT_EQ(each.size(), 2u);
  EXPECT_NEAR(each[0].noise, 0.01, 1e-6);
  EXPECT_NEAR(each[0].bias, 0.0, 1e-12);
  EXPECT_NEAR(each[1].noise, 0.4, 1e-6);
  EXPECT_NEAR(each[1].bias, 0.3, 1e-6);
  EXPECT_NEAR(each[1].Total(), 0.5, 1e-6);
  // The whole bake's figure, relative to the mean H over both (0.505), hides the dim surface: its noise adds
  // 0.4 x 0.01 = 0.004 W/m^2 over half the vertices.
  const BakeError all = PredictedError(b);
  EXPECT_NEAR(all.noise, std::sqrt((0.01 * 0.01 + 0.004 * 0.004) / 2) / 0.505, 1e-6);
  EXPECT_LT(all.Total(), 0.05 * each[1].Total());
}

// One surface: the per-surface figure is the bake's, term by term.
TEST(PredictedErrorPerSurface, OneSurfaceIsTheWholeBakesFigure) {
  BakedMesh b = TwoRooms(0.5f);
  b.mesh.surface.assign(6, 0);
  const std::vector<BakeError> each = PredictedErrorPerSurface(b, 1);
  const BakeError all = PredictedError(b);
  EXPECT_DOUBLE_EQ(each[0].noise, all.noise);
  EXPECT_DOUBLE_EQ(each[0].bias, all.bias);
}

// A surface with no vertex (all of it refined away, or no light at all) reads no error rather than 0 / 0.
TEST(PredictedErrorPerSurface, ASurfaceWithoutLightOrVerticesReadsZero) {
  BakedMesh b = TwoRooms(0.0f);
  const std::vector<BakeError> each = PredictedErrorPerSurface(b, 3);
  EXPECT_EQ(each[1].Total(), 0.0);
  EXPECT_EQ(each[2].Total(), 0.0);
  EXPECT_GT(each[0].Total(), 0.0);
}

}  // namespace
}  // namespace pb
