#include "baker/5_write_maps.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "baker/atomic_file.h"
#include "baker/image_io.h"
#include "mesh/errors.h"

namespace pb {
namespace {

constexpr int kMaxTexelsPerSide = 8192;

// The chart's area ratio (surface area / chart area) at uv: that of the triangle containing it; 1 if none does.
float AreaRatioAt(const Scene& scene, const SurfaceSet& surfaces, const Surface& surface, Point2 uv) {
  if (surface.planar) return 1.0f;
  for (uint32_t t : surface.triangles) {
    const Triangle2& c = surfaces.cornerUv[t];
    const double a = SignedArea(c[0], c[1], c[2]);
    const double w0 = SignedArea(uv, c[1], c[2]), w1 = SignedArea(c[0], uv, c[2]), w2 = SignedArea(c[0], c[1], uv);
    const bool inside = a > 0 ? (w0 >= 0 && w1 >= 0 && w2 >= 0) : (w0 <= 0 && w1 <= 0 && w2 <= 0);
    if (inside && a != 0) return float(scene.Area(t) / std::abs(a));
  }
  return 1.0f;
}

struct GridSize {
  int nu, nv;
};
GridSize TexelGrid(const Bounds2& b, float texel) {
  return {std::max(1, int(std::ceil((b.hi.u - b.lo.u) / texel))), std::max(1, int(std::ceil((b.hi.v - b.lo.v) / texel)))};
}

std::string Vec(double x, double y, double z) { return fmt::format("{:.9g} {:.9g} {:.9g}", x, y, z); }

void WriteSurfaceMap(const std::string& path, float texel, const Scene& scene, const SurfaceSet& surfaces,
                     uint32_t s, const SurfaceRegion& region, const DensityEstimator& estimator) {
  const Surface& surface = surfaces.surfaces[s];
  const Bounds2 b = region.Bounds();
  const auto [nu, nv] = TexelGrid(b, texel);
  Image image(nu, nv);
  std::vector<float> coverage(size_t(nu) * size_t(nv));
  const std::vector<double> area = region.GridOverlapAreas(b.lo, texel, nu, nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const size_t k = size_t(j) * size_t(nu) + size_t(i);
      coverage[k] = float(std::clamp(area[k] / (double(texel) * texel), 0.0, 1.0));
      if (coverage[k] == 0) continue;
      const Point2 uv{b.lo.u + (float(i) + 0.5f) * texel, b.lo.v + (float(j) + 0.5f) * texel};
      image.At(i, j) = estimator.Estimate(uv) * AreaRatioAt(scene, surfaces, surface, uv);
    }
  const SurfaceChart& chart = surface.chart;
  const std::array<double, 3> o = scene.ToWorld(chart.origin);
  const std::string& object = scene.objectNames[scene.triangles[surface.triangles.front()].object];
  WriteExr(path, image,
           {{"quantity", "irradiance"},
            {"units", "W/m^2, linear Rec.709 RGB; A: fraction of the texel on the surface"},
            {"surface", std::to_string(s)},
            {"object", object},
            {"material", scene.materials[surface.material].name},
            {"chart", surface.planar ? "planar projection" : "least-squares conformal map"},
            {"texel_size_m", fmt::format("{:.9g}", texel)},
            {"uv_corner_m", fmt::format("{:.9g} {:.9g}", b.lo.u, b.lo.v)},
            {"chart_origin_m", Vec(o[0], o[1], o[2])},
            {"chart_u_axis", Vec(chart.frame.s.x, chart.frame.s.y, chart.frame.s.z)},
            {"chart_v_axis", Vec(chart.frame.t.x, chart.frame.t.y, chart.frame.t.z)}},
           &coverage);
}

}  // namespace

MapsWritten WriteIrradianceMaps(const std::string& directory, float texel, const Scene& scene,
                                const SurfaceSet& surfaces, const SurfaceRegions& regions,
                                const SurfaceEstimators& estimators, const Log& log) {
  if (!(texel > 0) || !std::isfinite(texel)) throw InputError("--texel", 0, "must be a finite length > 0 m");
  RequireWritableLocation(directory + "/surface_0.exr");
  MapsWritten written;
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
    const Bounds2 b = regions[s]->Bounds();
    const double side = std::max(b.hi.u - b.lo.u, b.hi.v - b.lo.v) / texel;
    if (side > kMaxTexelsPerSide)
      throw InputError("--texel", 0, fmt::format("surface {} would need {:.0f} texels on a side (at most {}); "
                                                 "use a larger --texel", s, side, kMaxTexelsPerSide));
    const auto [nu, nv] = TexelGrid(b, texel);
    written.texels += size_t(nu) * size_t(nv);
    written.paths.push_back(fmt::format("{}/surface_{}.exr", directory, s));
  }
  Progress progress(log, "irradiance maps", surfaces.surfaces.size());
  tbb::parallel_for(size_t(0), surfaces.surfaces.size(), [&](size_t s) {
    WriteSurfaceMap(written.paths[s], texel, scene, surfaces, uint32_t(s), *regions[s], *estimators[s]);
    progress.Advance(1);
  });
  return written;
}

}  // namespace pb
