// The `render` pipeline: load the scene and its camera, trace photons and build the photon map (for
// --sampling photons), path-trace the image, and write it as linear OpenEXR plus a tone-mapped PNG beside it.
// With an spp sweep it renders one image per sample count and a strip of them side by side, as the paper shows
// for the box. Units: radiance W/(m^2 sr) per pixel; times in seconds.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "baker/1_trace_photons.h"
#include "baker/files/image_io.h"
#include "baker/render/path_tracer.h"
#include "baker/runtime/progress.h"
#include "mesh/camera.h"

namespace pb {

struct RenderOptions {
  std::string scenePath;
  std::string outputPath;  // .exr; the PNG goes beside it with the extension .png
  std::string cameraPath;  // empty: the scene's sidecar (mesh/camera.h)
  std::string reportPath;  // JSON; empty for none
  int width = 256, height = 256;  // pixels, >= 1
  uint32_t spp = 16;              // samples per pixel, >= 1
  std::vector<uint32_t> sppSweep; // when set, one image per count (and a strip) instead of one at `spp`
  PathSettings path;
  uint64_t photons = 250'000;     // photons for the importance maps (--sampling photons only)
  uint64_t seed = 1;
  unsigned threads = 0;
  float scale = 1.0f;             // metres per scene unit
  std::optional<float> exposure;  // PNG exposure; unset = automatic
  bool quiet = false;

  // Checks every range, and that the images and the photon map fit in this machine's memory, before any work
  // (InputError naming the option; the ranges bake shares are in baker/option_ranges.h).
  void Validate() const;
};

// One image: the per-pixel mean radiance, and the variance of each pixel mean's luminance (the sample variance
// of the samples' luminance / spp) [(W/(m^2 sr))^2], for tests and error estimates.
struct RenderedImage {
  Image mean;
  std::vector<float> luminanceVariance;  // row-major, as Image::pixels
  PathStats stats;
  double seconds = 0;
};

struct RenderReport {
  RenderOptions options;
  unsigned threads = 0;
  size_t photonsStored = 0;
  size_t cachedMaps = 0;   // importance maps cached (estimators/importance_cache.h)
  float cacheCell = 0;     // the cache's cell side [m]
  std::vector<std::pair<std::string, double>> stageSeconds;  // in order
  std::vector<std::pair<uint32_t, RenderedImage>> images;    // spp -> image (pixels dropped after writing)
  std::vector<std::string> outputs;
  float exposure = 1;
};

// Renders `spp` samples per pixel with `tracer`; pixel i draws from Rng(SplitMix64(seed ^ c), i), a family of
// streams apart from the photons' Rng(seed, i).
RenderedImage RenderImage(const PathTracer& tracer, const PathSettings& settings, const PinholeCamera& camera,
                          int width, int height, uint32_t spp, uint64_t seed, const Log& log);

RenderReport Render(const RenderOptions& options, const Log& log);
void PrintRenderSummary(const RenderReport& report, const Log& log);

}  // namespace pb
