#include "baker/5_write_maps.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <set>
#include <span>

#include "baker/distribution.h"
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
// The texels of a surface's map.
size_t TexelsOn(const SurfaceRegion& region, float texel) {
  const auto [nu, nv] = TexelGrid(region.Bounds(), texel);
  return size_t(nu) * size_t(nv);
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

// One surface's map as it is made: its texel grid over the chart's box, each texel's coverage (the fraction of it on
// the surface), and H with, under --sh, the SH channels.
struct SurfaceMap {
  uint32_t surface = 0;
  Bounds2 box;
  int nu = 0, nv = 0;
  std::vector<float> coverage;
  Image image;
  std::vector<ExrChannel> channels;
  size_t Texels() const { return coverage.size(); }
};

SurfaceMap MapOf(const IrradianceField& field, uint32_t s, float texel, bool sh) {
  const SurfaceRegion& region = *field.Prepared().regions[s];
  SurfaceMap m{.surface = s, .box = region.Bounds()};
  const GridSize grid = TexelGrid(m.box, texel);
  m.nu = grid.nu, m.nv = grid.nv;
  m.image = Image(m.nu, m.nv);
  const std::vector<double> area = region.GridOverlapAreas(m.box.lo, texel, m.nu, m.nv);
  m.coverage.resize(area.size());
  for (size_t k = 0; k < area.size(); ++k) m.coverage[k] = float(std::clamp(area[k] / (double(texel) * texel), 0.0, 1.0));
  if (sh) m.channels = ShChannels(m.coverage.size());
  return m;
}

// Texel k of m (row by row): H, and the SH with --sh, at the surface point under its centre; nothing off the surface.
void EstimateTexel(SurfaceMap& m, size_t k, float texel, const IrradianceField& field, const SurfacePointSampler& sampler,
                   bool sh) {
  if (m.coverage[k] == 0) return;
  const int i = int(k % size_t(m.nu)), j = int(k / size_t(m.nu));
  const Point2 uv{m.box.lo.u + (float(i) + 0.5f) * texel, m.box.lo.v + (float(j) + 0.5f) * texel};
  const SurfacePoint p = sampler.AtChartPoint(m.surface, uv);
  m.image.At(i, j) = field.Irradiance(p);
  if (sh) StoreSh(m.channels, k, ShProjection(field.Moments(p), p.normal, m.image.At(i, j)));
}

void WriteSurfaceMap(OutputFiles& outputs, const std::string& path, float texel, const IrradianceField& field,
                     const SurfaceMap& m, bool sh) {
  const Scene& scene = field.Prepared().scene;
  const Surface& surface = field.Prepared().surfaces.surfaces[m.surface];
  const Bounds2& b = m.box;
  const SurfaceChart& chart = surface.chart;
  const std::array<double, 3> o = scene.ToWorld(chart.origin);
  const std::string& object = scene.objectNames[scene.triangles[surface.triangles.front()].object];
  std::vector<std::pair<std::string, std::string>> attributes = {
      {"quantity", "irradiance"},
      {"units", "W/m^2, linear Rec.709 RGB; A: fraction of the texel on the surface"},
      {"surface", std::to_string(m.surface)},
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
  WriteExr(outputs, path, m.image, attributes, &m.coverage, m.channels);
}

// One surface's map, made and written by this process: row by row in parallel (a map of 10^8 texels is minutes of
// work, and each texel's estimate is its own).
void MakeSurfaceMap(OutputFiles& outputs, const std::string& path, float texel, const IrradianceField& field,
                    const SurfacePointSampler& sampler, uint32_t s, bool sh, Progress& progress) {
  SurfaceMap m = MapOf(field, s, texel, sh);
  tbb::parallel_for(0, m.nv, [&](int j) {
    for (size_t k = size_t(j) * size_t(m.nu); k != size_t(j + 1) * size_t(m.nu); ++k)
      EstimateTexel(m, k, texel, field, sampler, sh);
    progress.Advance(uint64_t(m.nu));
  });
  WriteSurfaceMap(outputs, path, texel, field, m, sh);
}

// A distributed bake's maps (baker/distribution.h): the mapped surfaces in batches of about kBatchTexels texels
// (a larger surface alone), whose texels, one run across the batch's maps, are shared in chunks of kTexelChunk,
// each estimated by the process that claims it first; rank 0 gathers them and calls write(map) for each. A texel's
// value is its own, so the maps are those of one process, whoever took which chunk. Should a write fail, rank 0 still
// takes its part in every batch's exchange, so that no process is left waiting, and then throws.
constexpr size_t kBatchTexels = size_t(1) << 20, kTexelChunk = 1024;

// A batch's texels as floats, one record of H (and the SH) per texel, in the maps' order; or back into the maps.
size_t TexelFloats(bool sh) { return sh ? 15 : 3; }
void PackTexel(const SurfaceMap& m, size_t k, bool sh, float* out) {
  const Rgb& h = m.image.pixels[k];
  out[0] = h.r, out[1] = h.g, out[2] = h.b;
  if (sh)
    for (size_t c = 0; c < 12; ++c) out[3 + c] = m.channels[c].values[k];
}
void UnpackTexel(SurfaceMap& m, size_t k, bool sh, const float* in) {
  m.image.pixels[k] = Rgb{in[0], in[1], in[2]};
  if (sh)
    for (size_t c = 0; c < 12; ++c) m.channels[c].values[k] = in[3 + c];
}

template <typename Write>
void ShareSurfaceMaps(const std::vector<uint32_t>& mapped, float texel, const IrradianceField& field,
                      const SurfacePointSampler& sampler, bool sh, const Distribution& d, Progress& progress,
                      Write write) {
  std::exception_ptr failed;  // rank 0's first failure to write a map (a full disk), thrown once every batch is shared
  for (size_t first = 0, next = 0; first < mapped.size(); first = next) {
    std::vector<SurfaceMap> maps;
    std::vector<size_t> start{0};  // flat index of each map's first texel
    for (next = first; next < mapped.size() && (next == first || start.back() < kBatchTexels); ++next) {
      maps.push_back(MapOf(field, mapped[next], texel, sh));
      start.push_back(start.back() + maps.back().Texels());
    }
    const size_t texels = start.back(), chunks = (texels + kTexelChunk - 1) / kTexelChunk, floats = TexelFloats(sh);
    const auto forEach = [&](size_t c, auto f) {  // f(map, texel, flat index) over chunk c
      size_t m = size_t(std::upper_bound(start.begin(), start.end(), c * kTexelChunk) - start.begin()) - 1;
      for (size_t t = c * kTexelChunk; t < std::min(texels, (c + 1) * kTexelChunk); ++t) {
        while (t >= start[m + 1]) ++m;
        f(maps[m], t - start[m], t);
      }
    };
    std::vector<float> flat(texels * floats, 0.0f);
    d.OpenChunks(chunks);
    tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
      if (d.ClaimChunk(c))
        forEach(c, [&](SurfaceMap& m, size_t k, size_t t) {
          EstimateTexel(m, k, texel, field, sampler, sh);
          PackTexel(m, k, sh, &flat[t * floats]);
        });
      progress.Advance(std::min(texels, (c + 1) * kTexelChunk) - c * kTexelChunk);
    });
    d.CloseChunks();
    d.GatherChunks(std::as_writable_bytes(std::span(flat)), floats * sizeof(float), kTexelChunk);
    if (!d.Root() || failed) continue;  // a failed write waits for the batches left, whose collectives the others await
    for (size_t c = 0; c < chunks; ++c)
      forEach(c, [&](SurfaceMap& m, size_t k, size_t t) { UnpackTexel(m, k, sh, &flat[t * floats]); });
    try {
      for (const SurfaceMap& m : maps) write(m);
    } catch (...) {
      failed = std::current_exception();
    }
  }
  if (failed) std::rethrow_exception(failed);
}

}  // namespace

double MapTexelCount(float texel, const SurfaceRegions& regions) {
  double texels = 0;
  for (const auto& region : regions) texels += double(TexelsOn(*region, texel));
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
  for (const auto& region : regions) texels.push_back(double(TexelsOn(*region, texel)));
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

namespace {

// The surfaces whose maps are made (`only`'s, or every one), and their texels.
std::vector<uint32_t> MappedSurfaces(const SurfaceSet& surfaces, const std::vector<bool>& only) {
  std::vector<uint32_t> mapped;
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s)
    if (only.empty() || only[s]) mapped.push_back(s);
  return mapped;
}
size_t TexelsOf(const std::vector<uint32_t>& mapped, const SurfaceRegions& regions, float texel) {
  size_t texels = 0;
  for (uint32_t s : mapped) texels += TexelsOn(*regions[s], texel);
  return texels;
}

}  // namespace

MapsWritten WriteIrradianceMaps(OutputFiles& outputs, const std::string& directory, float texel, const IrradianceField& field,
                                const SplitMesh& base, const Log& log, const std::vector<bool>& only, bool sh,
                                const Distribution* distribution) {
  const PreparedScene& prepared = field.Prepared();
  RequireWritableLocation(directory + "/surface_0.exr");
  CheckMapTexels(texel, prepared.regions, 1);
  const std::vector<std::string> paths = MapPaths(directory, prepared.surfaces.surfaces.size());
  const std::vector<uint32_t> mapped = MappedSurfaces(prepared.surfaces, only);
  MapsWritten written{.texels = TexelsOf(mapped, prepared.regions, texel)};
  for (uint32_t s : mapped) written.paths.push_back(paths[s]);
  const SurfacePointSampler sampler(prepared.scene, prepared.surfaces, base);
  Progress progress(log, "irradiance maps (texels)", written.texels);
  if (distribution != nullptr) {
    ShareSurfaceMaps(mapped, texel, field, sampler, sh, *distribution, progress,
                     [&](const SurfaceMap& m) { WriteSurfaceMap(outputs, paths[m.surface], texel, field, m, sh); });
    return written;
  }
  tbb::parallel_for(size_t(0), mapped.size(), [&](size_t i) {
    MakeSurfaceMap(outputs, written.paths[i], texel, field, sampler, mapped[i], sh, progress);
  });
  return written;
}

void ShareIrradianceMaps(float texel, const IrradianceField& field, const SplitMesh& base, const std::vector<bool>& only,
                         bool sh, const Distribution& distribution) {
  const PreparedScene& prepared = field.Prepared();
  const SurfacePointSampler sampler(prepared.scene, prepared.surfaces, base);
  const std::vector<uint32_t> mapped = MappedSurfaces(prepared.surfaces, only);
  Progress progress(Log(true), "irradiance maps (texels)", TexelsOf(mapped, prepared.regions, texel));
  ShareSurfaceMaps(mapped, texel, field, sampler, sh, distribution, progress,
                   [](const SurfaceMap&) {});
}

}  // namespace pb
