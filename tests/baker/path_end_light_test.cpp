// The photons' light where gathered paths end, read from tables (baker/3_path_end_light.h), against the estimate
// itself: on the floor under a square light, the lattice's bilinear interpolation at h / 4 within a small part of
// the estimate's own noise, and the estimate itself, bit for bit, in every cell not wholly on the floor; on the
// office's pooled surfaces, each triangle's corners read the pooled estimate bit for bit and its inside within
// the pooled estimate's smoothness; and every value the same whichever threads filled the tables, in any order.
#include <gtest/gtest.h>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "baker/2_bin_photons.h"
#include "baker/3_contributions.h"
#include "baker/3_path_end_light.h"
#include "estimators/rng.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

float RelativeDifference(Rgb a, Rgb b) { return std::fabs(a.g - b.g) / std::max(std::fabs(b.g), 1e-12f); }

// Random chart points over surface s's bounds, some beyond its outline.
std::vector<Point2> PointsOver(const SurfaceRegion& region, int count, uint64_t seed) {
  const Bounds2 b = region.Bounds();
  std::vector<Point2> points;
  for (int k = 0; k < count; ++k) {
    const Point2 r = Rng(seed, uint64_t(k)).Uniform2();
    points.push_back({b.lo.u + r.u * (b.hi.u - b.lo.u), b.lo.v + r.v * (b.hi.v - b.lo.v)});
  }
  return points;
}

// 400,000 photons on the 4 x 4 m floor, h chosen per surface (0.285 m). Interpolating the estimate between nodes
// h / 4 apart is an error second order in the spacing, of H (smooth on the scale of the light's height, 1 m) and
// of the estimate's own noise (smooth on the scale of h): so a fraction of that noise, largest within h of the
// outline, where the local linear fit's weights swing and the noise varies fastest. Measured over 4,000 points: at
// most 0.42 of the estimate's predicted noise; farther than h from the outline at most 0.74% of H and 0.14% RMS.
// The difference is the noise's, not a bias: the table's value is the photons' estimate with its kernel smoothed
// over a quarter of h, whose mean differs from the estimate's by the second-order smoothing of H alone.
TEST(PathEndLight, TheFloorsLatticeReadsTheEstimateWithinAFractionOfItsNoise) {
  const std::string dir = test::TempDirectory("path-end-light");
  const test::TracedScene prepared(test::WriteSquareLightOverFloor(dir, 1.0f, 1.0f, 1.0f, 4.0f, 80));
  const PhotonStore hits = prepared.Trace(400'000, 5);
  const SurfaceBins bins = BinPhotons(prepared.surfaces, hits);
  EstimatorSettings settings;
  settings.bandwidth.reset();
  const PhotonIrradiance photons(prepared, bins, settings, SurfaceBandwidths(prepared.regions, bins, settings));
  const uint32_t floor = prepared.surfaces.surfaceOfTriangle[0];
  const SurfaceRegion& region = *prepared.regions[floor];
  const std::vector<Point2> points = PointsOver(region, 4000, 11);

  const PathEndLight ends(prepared, photons);
  double worst = 0, squares = 0, worstOfNoise = 0;
  int interpolated = 0, partial = 0, inside = 0;
  // The lattice starts at the floor's corner; its last cell in each axis overhangs the floor unless the side is a
  // whole number of cells.
  const float spacing = photons.Bandwidth(floor) / PathEndLight::kNodesPerH;
  const Bounds2 b = region.Bounds();
  const float wholeU = std::floor((b.hi.u - b.lo.u) / spacing) * spacing, wholeV = std::floor((b.hi.v - b.lo.v) / spacing) * spacing;
  for (const Point2& x : points) {
    const Rgb table = ends.ChartDensity(floor, x), exact = photons.ChartDensity(floor, x);
    if (x.u - b.lo.u > 1.0001f * wholeU || x.v - b.lo.v > 1.0001f * wholeV) {
      ++partial;
      EXPECT_TRUE(table.r == exact.r && table.g == exact.g && table.b == exact.b) << "a cell at the outline reads the estimate itself";
      continue;
    }
    if (x.u - b.lo.u > 0.9999f * wholeU || x.v - b.lo.v > 0.9999f * wholeV) continue;  // at the last whole cell's rim
    ++interpolated;
    const double d = RelativeDifference(table, exact);
    SurfacePoint p;
    p.surface = floor, p.uv = x;
    worstOfNoise = std::max(worstOfNoise, d / photons.WithNoise(p).relativeNoise);
    if (std::min({x.u - b.lo.u, b.hi.u - x.u, x.v - b.lo.v, b.hi.v - x.v}) < photons.Bandwidth(floor)) continue;
    ++inside;
    worst = std::max(worst, d), squares += d * d;
  }
  std::printf("h %.3f m: %d points interpolated, at most %.3f of the estimate's noise off it; %d of them farther than h "
              "from the outline, at most %.4f%% and %.4f%% RMS off; %d in cells at the outline\n",
              photons.Bandwidth(floor), interpolated, worstOfNoise, inside, 100 * worst, 100 * std::sqrt(squares / inside), partial);
  ASSERT_GT(inside, 2500);
  EXPECT_LT(worstOfNoise, 0.6);
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(std::sqrt(squares / inside), 0.002);

  // The same values filled by 4 threads in reverse order.
  const PathEndLight again(prepared, photons);
  std::vector<Rgb> first(points.size()), second(points.size());
  for (size_t k = 0; k < points.size(); ++k) first[k] = ends.ChartDensity(floor, points[k]);
  {
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 4);
    tbb::parallel_for(size_t(0), points.size(), [&](size_t k) {
      const size_t i = points.size() - 1 - k;
      second[i] = again.ChartDensity(floor, points[i]);
    });
  }
  for (size_t k = 0; k < points.size(); ++k)
    ASSERT_TRUE(first[k].r == second[k].r && first[k].g == second[k].g && first[k].b == second[k].b) << k;
}

// The office with books at 40,000 photons: its surfaces with fewer than 100 front hits are pooled. At a pooled
// triangle's corners the table reads the pooled estimate itself; at its centroid, where its corners' estimates are
// interpolated (its longest edge within half the pooled reach), within a few percent of it: the pooled estimate
// averages photons within the reach, so it changes little across a triangle of half that size (measured 1.97% RMS
// over 1,327 triangles).
TEST(PathEndLight, PooledTrianglesReadTheirCornersEstimates) {
  const test::TracedScene prepared(PB_SOURCE_DIR "/data/office_books/office_books.obj");
  const PhotonStore hits = prepared.Trace(40'000, 3);
  SurfaceBins bins = BinPhotons(prepared.surfaces, hits);
  PoolSparseHits(prepared.scene, prepared.surfaces, hits, bins);
  EstimatorSettings settings;
  settings.bandwidth.reset();
  const PhotonIrradiance photons(prepared, bins, settings, SurfaceBandwidths(prepared.regions, bins, settings),
                                 nullptr, true);
  const PathEndLight ends(prepared, photons);
  const Scene& scene = prepared.scene;
  int pooled = 0, interpolated = 0;
  double squares = 0;
  for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
    if (!photons.Pooled(prepared.surfaces.surfaceOfTriangle[t])) continue;
    ++pooled;
    const Normal3 n = scene.FrontNormal(t);
    const Rgb centre = ends.Pooled(t, 1.0f / 3, 1.0f / 3);
    const Rgb exact = photons.PooledAt(scene.PointAt(t, 1.0f / 3, 1.0f / 3), n).irradiance;
    if (centre.g == exact.g) continue;  // read directly: too large against the reach
    ++interpolated;
    for (int k = 0; k < 3; ++k) {
      const Rgb corner = ends.Pooled(t, k == 1 ? 1.0f : 0.0f, k == 2 ? 1.0f : 0.0f);
      ASSERT_EQ(corner.g, photons.PooledAt(scene.Corner(t, k), n).irradiance.g) << "triangle " << t << " corner " << k;
    }
    if (exact.g > 0) squares += std::pow(RelativeDifference(centre, exact), 2);
  }
  std::printf("%d pooled triangles, %d interpolated: %.3f%% RMS off the pooled estimate at their centroids\n", pooled,
              interpolated, 100 * std::sqrt(squares / std::max(interpolated, 1)));
  ASSERT_GT(interpolated, 100);
  EXPECT_LT(std::sqrt(squares / interpolated), 0.05);
}

}  // namespace
}  // namespace pb
