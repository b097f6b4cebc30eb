#include "baker/render/render.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "baker/0_prepare_scene.h"
#include "baker/files/json_file.h"
#include "mesh/memory_budget.h"
#include "baker/option_ranges.h"
#include "baker/runtime/stage_clock.h"
#include "baker/runtime/threads.h"
#include "baker/tone_map.h"
#include "mesh/errors.h"

namespace pb {
namespace {

constexpr uint32_t kMostSamplesPerPixel = 1u << 24;

std::string WithSuffix(const std::string& exrPath, const std::string& suffix, const std::string& extension) {
  const bool exr = exrPath.size() > 4 && exrPath.compare(exrPath.size() - 4, 4, ".exr") == 0;
  return (exr ? exrPath.substr(0, exrPath.size() - 4) : exrPath) + suffix + extension;
}

// The EXR and PNG of the image of `spp` samples per pixel: -o, with _sppN before the extension in a sweep.
std::pair<std::string, std::string> ImagePaths(const RenderOptions& o, uint32_t spp) {
  const std::string suffix = o.sppSweep.empty() ? "" : fmt::format("_spp{}", spp);
  return {WithSuffix(o.outputPath, suffix, ".exr"), WithSuffix(o.outputPath, suffix, ".png")};
}
std::string StripPath(const RenderOptions& o) { return WithSuffix(o.outputPath, "_strip", ".png"); }

// Every file a render writes, by option.
std::vector<std::pair<std::string, std::string>> OutputFilesOf(const RenderOptions& o) {
  std::vector<std::pair<std::string, std::string>> files;
  for (uint32_t spp : o.sppSweep.empty() ? std::vector<uint32_t>{o.spp} : o.sppSweep) {
    const auto [exr, png] = ImagePaths(o, spp);
    files.insert(files.end(), {{"-o", exr}, {"-o", png}});
  }
  if (!o.sppSweep.empty()) files.emplace_back("-o", StripPath(o));
  if (!o.reportPath.empty()) files.emplace_back("--report", o.reportPath);
  return files;
}

}  // namespace

void RenderOptions::Validate() const {
  RequireImageSize(width, height, "--size", 16384);
  RequireOption(spp >= 1 && spp <= kMostSamplesPerPixel, "--spp", "must lie in [1, 2^24]");
  for (uint32_t s : sppSweep)
    RequireOption(s >= 1 && s <= kMostSamplesPerPixel, "--spp-sweep", "every count must lie in [1, 2^24]");
  RequireOption(path.neighbours >= 1 && path.neighbours <= 1'000'000, "--neighbours", "must lie in [1, 1000000]");
  RequireOption(Within(path.floorFraction, 0, 1), "--floor", "must lie in [0, 1]");
  const auto powerOfTwo = [](int n) { return n > 0 && (n & (n - 1)) == 0; };
  RequireOption(path.thetaRegions >= 1 && path.phiRegions >= 1 && int64_t(path.thetaRegions) * path.phiRegions <= 65536,
                "--regions", "needs ROWSxCOLS with 1 <= ROWS x COLS <= 65536");
  RequireOption(path.warp != ImportanceWarp::kMipmap || (powerOfTwo(path.thetaRegions) && powerOfTwo(path.phiRegions)),
                "--regions", "--warp mipmap needs power-of-two ROWS and COLS (use --warp inversion otherwise)");
  RequirePhotons(photons, "--photons");
  RequireThreads(threads);
  RequireScale(scale);
  RequireExposure(exposure);
  // Each image kept until written: mean RGB and variance (16 bytes a pixel), and the PNG's 8-bit copy.
  const double images = sppSweep.empty() ? 1.0 : double(sppSweep.size()) + 1.0;
  RequireMemory("--size", images * double(width) * double(height) * 19.0,
                fmt::format("{} image(s) of {}x{} pixels", int(images), width, height));
  // The photon map holds every stored hit twice (the store, then the map); a photon in a closed scene is stored
  // at least once.
  if (path.sampling == DirectionSampling::kPhotons)
    RequireMemory("--photons", double(photons) * double(sizeof(PhotonHit) + sizeof(MapPhoton)),
                  fmt::format("a photon map of {} photons (one hit each at least)", photons));
}

namespace {

// Accumulates one pixel's samples: the mean, and the variance of the mean's luminance.
struct PixelMoments {
  RgbSum sum;
  double luminance = 0, luminanceSquares = 0;
  void Add(Rgb x) {
    sum.Add(x);
    const double y = Luminance(x);
    luminance += y;
    luminanceSquares += y * y;
  }
  void Finish(uint32_t n, Rgb& mean, float& meanVariance) const {
    const double inv = 1.0 / n;
    mean = {float(sum.r * inv), float(sum.g * inv), float(sum.b * inv)};
    const double variance = n > 1 ? std::max(0.0, (luminanceSquares - luminance * luminance * inv) / (n - 1)) : 0.0;
    meanVariance = float(variance * inv);
  }
};

Image StripOf(const std::vector<const Image*>& images) {
  int width = 0, height = 0;
  for (const Image* i : images) {
    width += i->width;
    height = std::max(height, i->height);
  }
  Image strip(width, height);
  int x0 = 0;
  for (const Image* i : images) {
    for (int y = 0; y < i->height; ++y)
      for (int x = 0; x < i->width; ++x) strip.At(x0 + x, y) = i->At(x, y);
    x0 += i->width;
  }
  return strip;
}

// The camera file is in world coordinates; the scene may be re-centred (mesh/scene.h).
Camera InLocalCoordinates(Camera c, const Scene& scene) {
  c.position = scene.ToLocal(c.position.x, c.position.y, c.position.z);
  c.lookAt = scene.ToLocal(c.lookAt.x, c.lookAt.y, c.lookAt.z);
  return c;
}

std::vector<std::pair<std::string, std::string>> ExrAttributes(const RenderOptions& o, uint32_t spp) {
  return {{"scene", o.scenePath},
          {"sampling", SamplingName(o.path.sampling)},
          {"light_sampling", o.path.lightSampling ? "on" : "off"},
          {"spp", std::to_string(spp)},
          {"photons", o.path.sampling == DirectionSampling::kPhotons ? std::to_string(o.photons) : "0"},
          {"warp", WarpName(o.path.warp)},
          {"regions", fmt::format("{}x{}", o.path.thetaRegions, o.path.phiRegions)},
          {"map_domain", DomainName(o.path.domain)},
          {"floor", fmt::format("{}", o.path.floorFraction)},
          {"seed", std::to_string(o.seed)}};
}

void WriteRenderReport(OutputFiles& outputs, const std::string& path, const RenderReport& r) {
  nlohmann::json j;
  j["scene"] = r.options.scenePath;
  j["sampling"] = SamplingName(r.options.path.sampling);
  j["light_sampling"] = r.options.path.lightSampling;
  j["warp"] = WarpName(r.options.path.warp);
  j["regions"] = {r.options.path.thetaRegions, r.options.path.phiRegions};
  j["map_domain"] = DomainName(r.options.path.domain);
  j["floor"] = r.options.path.floorFraction;
  j["neighbours"] = r.options.path.neighbours;
  j["photons_stored"] = r.photonsStored;
  j["map_cache"] = r.options.path.mapCache;
  j["cached_maps"] = r.cachedMaps;
  j["cache_cell_m"] = r.cacheCell;
  j["threads"] = r.threads;
  for (const auto& [name, seconds] : r.stageSeconds) j["seconds"][name] = seconds;
  for (const auto& [spp, image] : r.images)
    j["images"].push_back({{"spp", spp}, {"seconds", image.seconds}, {"paths", image.stats.paths},
                           {"rays", image.stats.rays}, {"importance_maps", image.stats.importanceMaps},
                           {"cosine_fallbacks", image.stats.cosineFallbacks},
                           {"importance_thread_seconds", image.stats.importanceSeconds}});
  j["outputs"] = r.outputs;
  WriteJsonFile(outputs, path, j);
}

}  // namespace

RenderedImage RenderImage(const PathTracer& tracer, const PathSettings& settings, const PinholeCamera& camera,
                          int width, int height, uint32_t spp, uint64_t seed, const Log& log) {
  RenderedImage result{Image(width, height), std::vector<float>(size_t(width) * size_t(height)), {}, 0};
  std::vector<PathStats> rowStats(static_cast<size_t>(height));
  Progress progress(log, fmt::format("render {} spp", spp), uint64_t(height));
  // Pixels draw from their own family of streams: with the bare seed, pixel i would repeat photon i's numbers.
  const uint64_t pixelSeed = SplitMix64(seed ^ 0x7069786656C73ull);
  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 1), [&](const tbb::blocked_range<int>& rows) {
    PathScratch scratch(settings);
    for (int y = rows.begin(); y != rows.end(); ++y) {
      for (int x = 0; x < width; ++x) {
        Rng rng(pixelSeed, uint64_t(y) * uint64_t(width) + uint64_t(x));
        PixelMoments moments;
        for (uint32_t s = 0; s < spp; ++s) {
          const Point2 jitter = rng.Uniform2();
          const Vector3 d = camera.Direction(float(x) + jitter.u, float(y) + jitter.v);
          moments.Add(tracer.Trace(camera.Origin(), d, rng, scratch, rowStats[size_t(y)]));
        }
        moments.Finish(spp, result.mean.At(x, y), result.luminanceVariance[size_t(y) * size_t(width) + size_t(x)]);
      }
      progress.Advance(1);
    }
  });
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const PathStats& s : rowStats) result.stats.Add(s);
  return result;
}

RenderReport Render(const RenderOptions& o, const Log& log) {
  o.Validate();
  for (const auto& [option, path] : OutputFilesOf(o)) RequireWritableLocation(path);
  RequireDistinctFiles(OutputFilesOf(o), {{"the scene", o.scenePath}, {"--camera", o.cameraPath}});
  const ThreadScope threads(o.threads);
  RenderReport report{o, threads.Count()};
  StageClock clock(report.stageSeconds);

  Camera cameraData = LoadCamera(o.cameraPath.empty() ? CameraSidecarPath(o.scenePath) : o.cameraPath);
  const PreparedScene scene = PrepareScene(SceneSettings{o.scenePath, o.scale, {}}, clock);
  RequireDistinctFiles(OutputFilesOf(o), scene.scene.InputFiles());
  for (const std::string& w : scene.warnings) log.Warning(w);
  if (!scene.scene.analyticLights.empty() && !o.path.lightSampling)
    log.Warning(fmt::format("{}: warning: without light sampling render finds light by hitting emissive surfaces, so "
                            "its {} point, spot, sun and sky lights are not rendered; bake sees them", o.scenePath,
                            scene.scene.analyticLights.size()));
  cameraData = InLocalCoordinates(cameraData, scene.scene);
  std::optional<PhotonMap> photonMap;
  std::optional<ImportanceCache> cache;
  if (o.path.sampling == DirectionSampling::kPhotons) {
    std::vector<MapPhoton> photons = clock.Time("trace photons", [&] {
      // With light sampling a path collects only light that has scattered once at least after a diffuse hit: the
      // map is built from those photons alone, not from first hits, whose light the shadow rays bring.
      return MapPhotonsOf(scene.scene,
                          TracePhotons(scene, {o.photons, o.seed, kDefaultMaxBounces, !o.path.lightSampling}, log));
    });
    report.photonsStored = photons.size();
    if (o.path.mapCache) {
      cache.emplace(clock.Time("importance cache", [&] { return ImportanceCache(photons, o.path.Map()); }));
      report.cachedMaps = cache->Size();
      report.cacheCell = cache->CellSide();
    } else {
      photonMap.emplace(clock.Time("photon map", [&] { return PhotonMap(std::move(photons)); }));
    }
  }
  std::optional<LightSampler> lights;
  if (o.path.lightSampling) lights.emplace(scene.scene, scene.lights, *scene.rays);
  const PathTracer tracer(scene.scene, *scene.rays, photonMap ? &*photonMap : nullptr, lights ? &*lights : nullptr,
                          o.path, cache ? &*cache : nullptr);
  const PinholeCamera camera(cameraData, o.width, o.height);

  const std::vector<uint32_t> counts = o.sppSweep.empty() ? std::vector<uint32_t>{o.spp} : o.sppSweep;
  for (uint32_t spp : counts)
    report.images.emplace_back(spp, clock.Time(fmt::format("paths {} spp", spp), [&] {
      return RenderImage(tracer, o.path, camera, o.width, o.height, spp, o.seed, log);
    }));

  const Image& last = report.images.back().second.mean;
  report.exposure = o.exposure ? *o.exposure : AutoExposure(last.pixels);
  OutputFiles outputs;
  clock.Time("write", [&] {
    std::vector<const Image*> strip;
    for (const auto& [spp, image] : report.images) {
      const auto [exr, png] = ImagePaths(o, spp);
      WriteExr(outputs, exr, image.mean, ExrAttributes(o, spp));
      WritePng(outputs, png, image.mean, report.exposure);
      report.outputs.insert(report.outputs.end(), {exr, png});
      strip.push_back(&image.mean);
    }
    if (!o.sppSweep.empty()) {
      const std::string path = StripPath(o);
      WritePng(outputs, path, StripOf(strip), report.exposure);
      report.outputs.push_back(path);
    }
  });
  if (!o.reportPath.empty()) WriteRenderReport(outputs, o.reportPath, report);
  outputs.Commit();
  return report;
}

void PrintRenderSummary(const RenderReport& r, const Log& log) {
  if (log.Quiet()) return;
  const RenderOptions& o = r.options;
  std::string s = fmt::format("\nrender summary: {} ({}x{}, {} threads)\n", o.scenePath, o.width, o.height, r.threads);
  s += fmt::format("  sampling  {}{}", SamplingName(o.path.sampling), o.path.lightSampling ? " with light sampling" : "");
  if (o.path.sampling == DirectionSampling::kPhotons)
    s += fmt::format(": {} photons stored, N = {}, {}x{} {} regions, floor {}, warp {}, {}", r.photonsStored,
                     o.path.neighbours, o.path.thetaRegions, o.path.phiRegions, DomainName(o.path.domain),
                     o.path.floorFraction,
                     WarpName(o.path.warp),
                     o.path.mapCache ? fmt::format("{} cached maps in cells of {:.3g} m", r.cachedMaps, r.cacheCell)
                                     : std::string("a map at every hit"));
  s += "\n  seconds  ";
  for (const auto& [name, seconds] : r.stageSeconds) s += fmt::format(" {} {:.3f} |", name, seconds);
  s += "\n";
  for (const auto& [spp, image] : r.images) {
    const double threadSeconds = image.seconds * r.threads;
    RgbSum mean;
    for (const Rgb& p : image.mean.pixels) mean.Add(p, 1.0 / double(image.mean.pixels.size()));
    s += fmt::format("  {:>5} spp {:.3f} s: mean L {:.5g} W/(m^2 sr), {} paths, {:.2f} M rays/s", spp, image.seconds,
                     Luminance(mean.ToRgb()), image.stats.paths, image.stats.rays / std::max(1e-9, image.seconds) * 1e-6);
    if (image.stats.importanceMaps)
      s += fmt::format(", {} importance maps found (for the next direction and the light samples' weights) at {:.2f} us "
                       "each ({:.0f}% of path time; {} where none faced the hit, the cosine lobe instead)",
                       image.stats.importanceMaps,
                       1e6 * image.stats.importanceSeconds / double(image.stats.importanceMaps),
                       100.0 * image.stats.importanceSeconds / std::max(1e-9, threadSeconds), image.stats.cosineFallbacks);
    s += "\n";
  }
  for (const std::string& out : r.outputs) s += "  wrote     " + out + "\n";
  s += fmt::format("  exposure  {:.4g} (PNG only; the EXR holds radiance in W/(m^2 sr))\n", r.exposure);
  log.Info(s);
}

}  // namespace pb
