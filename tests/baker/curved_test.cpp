// Curved receivers: a closed, inward-facing tessellated sphere of albedo rho around a small isotropic emitter at
// its centre. Every patch of a sphere's inside sees every other patch alike, so the irradiance is uniform and,
// by energy balance, E = Phi / (A (1 - rho)). The sphere must be cut into several conformal charts, and the bake
// must show neither seams nor blotches:
//   - the mean over vertices is E within 2%;
//   - each vertex is within 5 sigma of E, and copies of one vertex on the two sides of a chart seam differ by
//     at most 5 sigma of their difference.
// sigma: grey albedo with survival = albedo keeps every photon's flux at phi = Phi / N, so the kernel estimate
// has variance phi H R(K) V / h^2 inside, with R(K) the kernel's roughness; V = 1 inside, and the local linear
// fit raises it to V = kSeamVariance on a seam and kCornerVariance at a chart's corner. 1% is allowed on top for the flat facets' geometry (a facet's
// centre is nearer the light than its corners: ~0.3% at this tessellation).
// The sphere's irradiance maps (--maps) read the same light: every texel wholly on the receiver is within the
// same bound of E, and the maps' mean is the vertices' mean.
// The cylinder and the blob have no closed form; they must bake with several charts of bounded distortion and
// agree across seams within noise at the median and 95th percentile, with sigma from their local H.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <map>
#include <vector>

#include "baker/bake.h"
#include "baker/files/image_io.h"
#include "tests/ply_reader.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

constexpr float kAlbedo = 0.5f;
constexpr uint64_t kPhotons = 1'000'000;
constexpr float kH = 0.1f;
// The local linear estimate's variance over the interior's, for the Epanechnikov kernel at a point on a straight
// edge (the kernel's half on the chart) and at a right-angled corner (its quarter), from integral w^2 with w the
// fit's weight (kernel_estimator.h); renormalisation's are 2 and 4.
constexpr double kSeamVariance = 6.95, kCornerVariance = 30.5;

struct CurvedBake {
  BakeReport report;
  test::PlyData ply;
  double phi = 0;  // flux per photon [W]
  // The standard deviation of a vertex's H where the local linear fit sees `variance` times the interior's
  // variance: kSeamVariance on a seam, kCornerVariance at a chart's corner.
  double Sigma(double H, double variance) const {
    return std::sqrt(phi * H * MomentsOf(Kernel::kEpanechnikov).roughness * variance / (double(kH) * kH));
  }
};

double TotalFlux(const BakeReport& r) {  // [W]; the light sphere may itself be cut into several charts
  double phi = 0;
  for (const LightReport& l : r.lights) phi += Luminance(l.power);
  return phi;
}

constexpr float kTexel = 0.05f;  // [m], for the sphere's maps

CurvedBake BakeCurved(test::CurvedShape shape, const std::string& name) {
  const std::string dir = test::TempDirectory(name);
  BakeOptions o;
  o.scenePath = test::WriteCurvedEnclosure(dir, shape, 4, kAlbedo, 0.02f, 100.0f);
  o.outputPath = dir + "/out.ply";
  o.photons = kPhotons;
  o.estimator.bandwidth = kH;
  if (shape == test::CurvedShape::kSphere) o.mapsDirectory = dir, o.texel = kTexel;
  CurvedBake b;
  b.report = Bake(o, Log(true));
  b.ply = test::ReadPly(o.outputPath);
  b.phi = TotalFlux(b.report) / double(kPhotons);
  return b;
}

bool IsReceiver(const test::PlyData& ply, size_t v) {  // the light is within 0.02 m of the origin
  return std::hypot(ply.vertex.at("x")[v], ply.vertex.at("y")[v], ply.vertex.at("z")[v]) > 0.1;
}

// For every vertex copied across a chart seam (same position, normals within 20 degrees: not a crease),
// z = |H_a - H_b| / sigma_difference, sorted ascending.
std::vector<double> SeamScores(const CurvedBake& b) {
  const auto& V = b.ply.vertex;
  std::map<std::array<double, 3>, std::vector<size_t>> copies;
  for (size_t v = 0; v < b.ply.VertexCount(); ++v)
    if (IsReceiver(b.ply, v)) copies[{V.at("x")[v], V.at("y")[v], V.at("z")[v]}].push_back(v);
  std::vector<double> z;
  for (const auto& [position, list] : copies)
    for (size_t i = 1; i < list.size(); ++i) {
      const size_t a = list[0], c = list[i];
      const double cosine = V.at("nx")[a] * V.at("nx")[c] + V.at("ny")[a] * V.at("ny")[c] + V.at("nz")[a] * V.at("nz")[c];
      if (cosine < std::cos(20 * M_PI / 180)) continue;  // a crease: H may differ
      const double ha = V.at("irradiance_g")[a], hc = V.at("irradiance_g")[c];
      z.push_back(std::fabs(ha - hc) / (std::sqrt(2.0) * b.Sigma((ha + hc) / 2, kSeamVariance)));
    }
  std::sort(z.begin(), z.end());
  EXPECT_GT(z.size(), 50u) << "no chart seams: the receiver was not cut into charts";
  return z;
}

double Percentile(const std::vector<double>& sorted, double p) { return sorted.empty() ? 0 : sorted[size_t(p * (sorted.size() - 1))]; }

double ReceiverArea(const BakeReport& r) {
  double area = 0;
  for (const SurfaceReport& s : r.surfaces)
    if (s.material == "wall") area += s.area;
  return area;
}

void ExpectSeveralBoundedCharts(const BakeReport& r) {
  size_t curved = 0;
  for (const SurfaceReport& s : r.surfaces) {
    if (s.planar) continue;
    ++curved;
    EXPECT_LE(s.areaDistortion, SurfaceOptions().maxAreaDistortion);
  }
  EXPECT_GE(curved, 4u);
}

const CurvedBake& SphereBake() {
  static const CurvedBake bake = BakeCurved(test::CurvedShape::kSphere, "curved-sphere");
  return bake;
}

TEST(Curved, SphereAroundAPointLightIsUniformAndMatchesTheEnergyBalance) {
  const CurvedBake& b = SphereBake();
  ExpectSeveralBoundedCharts(b.report);
  const double exact = TotalFlux(b.report) / (ReceiverArea(b.report) * (1 - kAlbedo));
  double sum = 0;
  int n = 0;
  for (size_t v = 0; v < b.ply.VertexCount(); ++v) {
    if (!IsReceiver(b.ply, v)) continue;
    const double H = b.ply.vertex.at("irradiance_g")[v];
    ASSERT_TRUE(std::isfinite(H));
    EXPECT_LE(std::fabs(H - exact), 5 * b.Sigma(exact, kCornerVariance) + 0.01 * exact) << "vertex " << v;
    sum += H, ++n;
  }
  EXPECT_NEAR(sum / n / exact, 1.0, 0.02);
  const std::vector<double> z = SeamScores(b);
  EXPECT_LE(z.back(), 5.0);  // uniform light: no gradient, so no boundary bias; every seam is within noise
}

// Issue 15: the maps once multiplied by surface / chart area where the vertices multiply by chart / surface area,
// and read 0.72x to 1.41x the vertices' H on this sphere.
TEST(Curved, SphereMapsReadTheVerticesIrradianceOnEveryCoveredTexel) {
  const CurvedBake& b = SphereBake();
  const double exact = TotalFlux(b.report) / (ReceiverArea(b.report) * (1 - kAlbedo));
  double vertexSum = 0, texelSum = 0;
  size_t vertices = 0, texels = 0;
  for (size_t v = 0; v < b.ply.VertexCount(); ++v)
    if (IsReceiver(b.ply, v)) vertexSum += b.ply.vertex.at("irradiance_g")[v], ++vertices;
  ASSERT_EQ(b.report.maps.paths.size(), b.report.surfaces.size());
  for (size_t s = 0; s < b.report.surfaces.size(); ++s) {
    if (b.report.surfaces[s].material != "wall") continue;
    std::vector<float> coverage;
    const Image map = ReadExr(b.report.maps.paths[s], nullptr, &coverage);
    for (int j = 0; j < map.height; ++j)
      for (int i = 0; i < map.width; ++i) {
        if (coverage[size_t(j) * size_t(map.width) + size_t(i)] < 0.999f) continue;  // partly off the surface
        const double H = map.At(i, j).g;
        ASSERT_LE(std::fabs(H - exact), 5 * b.Sigma(exact, kCornerVariance) + 0.01 * exact)
            << "surface " << s << " texel (" << i << ", " << j << "): " << H << " W/m^2 against " << exact;
        texelSum += H, ++texels;
      }
  }
  ASSERT_GT(texels, 1000u);
  std::printf("%zu covered texels, mean %.5g W/m^2; %zu vertices, mean %.5g W/m^2; closed form %.5g W/m^2\n", texels,
              texelSum / double(texels), vertices, vertexSum / double(vertices), exact);
  EXPECT_NEAR(texelSum / double(texels) / (vertexSum / double(vertices)), 1.0, 0.01);
}

TEST(Curved, CylinderAndBlobBakeWithoutSeams) {
  for (const auto& [shape, name] : {std::pair{test::CurvedShape::kCylinder, "curved-cylinder"},
                                    std::pair{test::CurvedShape::kBlob, "curved-blob"}}) {
    const CurvedBake b = BakeCurved(shape, name);
    ExpectSeveralBoundedCharts(b.report);
    for (size_t v = 0; v < b.ply.VertexCount(); ++v) ASSERT_TRUE(std::isfinite(b.ply.vertex.at("irradiance_g")[v]));
    // Noise alone gives |N(0, 1)|: a median z of 0.67 and a 95th percentile of 1.96. The local linear fit
    // leaves no first-order bias across a seam, but chart corners (variance up to kCornerVariance) and the
    // charts' second-order differences widen the tail: measured medians 0.70 (cylinder) and 0.90 (blob), 95th
    // percentiles 2.04 and 2.76. These bounds catch a chart whose scale or orientation is wrong, which shifts
    // whole seams by many sigma.
    const std::vector<double> z = SeamScores(b);
    std::printf("%s: seam z median %.3f p95 %.3f max %.3f\n", name, Percentile(z, 0.5), Percentile(z, 0.95), z.back());
    EXPECT_LE(Percentile(z, 0.5), 1.0) << name;
    EXPECT_LE(Percentile(z, 0.95), 3.5) << name;
  }
}

}  // namespace
}  // namespace pb
