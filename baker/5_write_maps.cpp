#include "baker/5_write_maps.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "baker/files/atomic_file.h"
#include "baker/files/image_io.h"
#include "mesh/memory_budget.h"
#include "mesh/errors.h"

namespace pb {
namespace {

constexpr int kMaxTexelsPerSide = 8192;

struct GridSize {
  int nu, nv;
};
GridSize TexelGrid(const Bounds2& b, float texel) {
  return {std::max(1, int(std::ceil((b.hi.u - b.lo.u) / texel))), std::max(1, int(std::ceil((b.hi.v - b.lo.v) / texel)))};
}

std::string Vec(double x, double y, double z) { return fmt::format("{:.9g} {:.9g} {:.9g}", x, y, z); }

// The planes sh_r0..sh_r3, sh_g0..sh_g3, sh_b0..sh_b3 of `texels` texels, named as the PLY's properties.
std::vector<ExrChannel> ShChannels(size_t texels) {
  std::vector<ExrChannel> channels;
  for (const char c : {'r', 'g', 'b'})
    for (int k = 0; k < 4; ++k) channels.push_back({fmt::format("sh_{}{}", c, k), std::vector<float>(texels)});
  return channels;
}

void StoreSh(std::vector<ExrChannel>& channels, size_t texel, const ShL1& sh) {
  for (size_t k = 0; k < 4; ++k) {
    channels[k].values[texel] = sh.c[k].r;
    channels[4 + k].values[texel] = sh.c[k].g;
    channels[8 + k].values[texel] = sh.c[k].b;
  }
}

void WriteSurfaceMap(OutputFiles& outputs, const std::string& path, float texel, const IrradianceField& field,
                     const SurfacePointSampler& sampler, uint32_t s, bool sh, Progress& progress) {
  const Scene& scene = field.Prepared().scene;
  const Surface& surface = field.Prepared().surfaces.surfaces[s];
  const SurfaceRegion& region = *field.Prepared().regions[s];
  const Bounds2 b = region.Bounds();
  const GridSize grid = TexelGrid(b, texel);
  const int nu = grid.nu, nv = grid.nv;  // named, not bound: clang 14's lambdas cannot capture a binding
  Image image(nu, nv);
  std::vector<float> coverage(size_t(nu) * size_t(nv));
  const std::vector<double> area = region.GridOverlapAreas(b.lo, texel, nu, nv);
  std::vector<ExrChannel> channels = sh ? ShChannels(coverage.size()) : std::vector<ExrChannel>{};
  // Row by row, in parallel: a map of 10^8 texels is minutes of work, and each texel's estimate is its own.
  tbb::parallel_for(0, nv, [&](int j) {
    for (int i = 0; i < nu; ++i) {
      const size_t k = size_t(j) * size_t(nu) + size_t(i);
      coverage[k] = float(std::clamp(area[k] / (double(texel) * texel), 0.0, 1.0));
      if (coverage[k] == 0) continue;
      const Point2 uv{b.lo.u + (float(i) + 0.5f) * texel, b.lo.v + (float(j) + 0.5f) * texel};
      const SurfacePoint p = sampler.AtChartPoint(s, uv);
      image.At(i, j) = field.Irradiance(p);
      if (sh) StoreSh(channels, k, ShProjection(field.Moments(p), p.normal, image.At(i, j)));
    }
    progress.Advance(uint64_t(nu));
  });
  const SurfaceChart& chart = surface.chart;
  const std::array<double, 3> o = scene.ToWorld(chart.origin);
  const std::string& object = scene.objectNames[scene.triangles[surface.triangles.front()].object];
  std::vector<std::pair<std::string, std::string>> attributes = {
      {"quantity", "irradiance"},
      {"units", "W/m^2, linear Rec.709 RGB; A: fraction of the texel on the surface"},
      {"surface", std::to_string(s)},
      {"object", object},
      {"material", scene.materials[surface.material].name},
      {"chart", surface.planar ? "planar projection" : "least-squares conformal map"},
      {"texel_size_m", fmt::format("{:.9g}", texel)},
      {"uv_corner_m", fmt::format("{:.9g} {:.9g}", b.lo.u, b.lo.v)},
      {"chart_origin_m", Vec(o[0], o[1], o[2])},
      {"chart_u_axis", Vec(chart.frame.s.x, chart.frame.s.y, chart.frame.s.z)},
      {"chart_v_axis", Vec(chart.frame.t.x, chart.frame.t.y, chart.frame.t.z)}};
  if (sh)
    attributes.emplace_back("sh", "sh_C0..sh_C3: L1 spherical harmonics of the incident radiance [W/(m^2 sr)] per "
                                  "channel C: L00 and L1 along world x, y, z; E(n) = 2.0466534 (sh_C1 nx + sh_C2 ny + "
                                  "sh_C3 nz)");
  WriteExr(outputs, path, image, attributes, &coverage, channels);
}

}  // namespace

double MapTexelCount(float texel, const SurfaceRegions& regions) {
  double texels = 0;
  for (const auto& region : regions) {
    const auto [nu, nv] = TexelGrid(region->Bounds(), texel);
    texels += double(nu) * double(nv);
  }
  return texels;
}

std::vector<std::string> MapTimeWarnings(float texel, const SurfaceRegions& regions, double secondsPerPoint) {
  const double texels = MapTexelCount(texel, regions);
  return LongWorkWarnings(fmt::format("--texel {}", texel), fmt::format("the maps hold {:.3g} texels", texels), texels,
                          secondsPerPoint, [&](double seconds) {  // texels go as 1 / texel^2
                            return fmt::format("--texel {:.2g} would take about a minute", texel * std::sqrt(seconds / 60));
                          });
}

double MapMemoryBytes(float texel, const SurfaceRegions& regions, unsigned threads) {
  constexpr double kBytesPerTexel = 40;
  std::vector<double> texels;
  for (const auto& region : regions) {
    const auto [nu, nv] = TexelGrid(region->Bounds(), texel);
    texels.push_back(double(nu) * double(nv));
  }
  std::sort(texels.rbegin(), texels.rend());
  double bytes = 0;
  for (size_t i = 0; i < texels.size() && i < threads; ++i) bytes += texels[i] * kBytesPerTexel;
  return bytes;
}

void CheckMapTexels(float texel, const SurfaceRegions& regions, unsigned threads) {
  for (size_t s = 0; s < regions.size(); ++s) {
    const Bounds2 b = regions[s]->Bounds();
    const double side = std::max(b.hi.u - b.lo.u, b.hi.v - b.lo.v) / texel;
    if (side > kMaxTexelsPerSide)
      throw InputError("--texel", 0, fmt::format("surface {} would need {:.0f} texels on a side (at most {}); "
                                                 "use a larger --texel", s, side, kMaxTexelsPerSide));
  }
  RequireMemory("--texel", MapMemoryBytes(texel, regions, threads), fmt::format("maps of {} m texels", texel));
}

std::vector<std::string> MapPaths(const std::string& directory, size_t surfaces) {
  std::vector<std::string> paths;
  for (size_t s = 0; s < surfaces; ++s) paths.push_back(fmt::format("{}/surface_{}.exr", directory, s));
  return paths;
}

bool IsMapName(const std::string& name) { return name.rfind("surface_", 0) == 0 && name.ends_with(".exr"); }

std::vector<std::string> StaleMapWarnings(const std::string& directory, const std::vector<std::string>& written) {
  std::set<std::string> ours;
  for (const std::string& path : written) ours.insert(std::filesystem::path(path).filename().string());
  std::vector<std::string> stale;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory, error)) {
    const std::string name = entry.path().filename().string();
    if (IsMapName(name) && !ours.count(name)) stale.push_back(name);
  }
  if (stale.empty()) return {};
  std::sort(stale.begin(), stale.end());
  const size_t named = std::min<size_t>(stale.size(), 3);
  return {fmt::format("{}: warning: {} map{} in this folder {} not this bake's ({}{}; it writes {}): an earlier "
                      "bake's, left as {} {}", directory, stale.size(), stale.size() == 1 ? "" : "s",
                      stale.size() == 1 ? "is" : "are", fmt::join(stale.begin(), stale.begin() + ptrdiff_t(named), ", "),
                      stale.size() > named ? ", ..." : "", written.size(), stale.size() == 1 ? "it" : "they",
                      stale.size() == 1 ? "was" : "were")};
}

MapsWritten WriteIrradianceMaps(OutputFiles& outputs, const std::string& directory, float texel, const IrradianceField& field,
                                const SplitMesh& base, const Log& log, const std::vector<bool>& only, bool sh) {
  const PreparedScene& prepared = field.Prepared();
  const SurfaceSet& surfaces = prepared.surfaces;
  const SurfaceRegions& regions = prepared.regions;
  RequireWritableLocation(directory + "/surface_0.exr");
  CheckMapTexels(texel, regions, 1);
  const std::vector<std::string> paths = MapPaths(directory, surfaces.surfaces.size());
  std::vector<uint32_t> mapped;  // the surfaces whose maps are written
  MapsWritten written;
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
    if (!only.empty() && !only[s]) continue;
    mapped.push_back(s);
    written.paths.push_back(paths[s]);
    const auto [nu, nv] = TexelGrid(regions[s]->Bounds(), texel);
    written.texels += size_t(nu) * size_t(nv);
  }
  const SurfacePointSampler sampler(prepared.scene, surfaces, base);
  Progress progress(log, "irradiance maps (texels)", written.texels);
  tbb::parallel_for(size_t(0), mapped.size(), [&](size_t i) {
    WriteSurfaceMap(outputs, written.paths[i], texel, field, sampler, mapped[i], sh, progress);
  });
  return written;
}

}  // namespace pb
