// What a bake did, in figures: photon counts, flux balance [W], hits per surface, seconds per stage, the
// transport effects simulated, and the output. Printed as a summary on stderr and written as JSON (--report).
// A scene of millions of surfaces or lights keeps a report of bounded size: the summary prints at most 40 rows of
// each, and the JSON lists the kListed largest surfaces (by area) and brightest lights (by power), each with its
// index, in index order, with totals over all of them ("surfaces_summary", "lights_summary"); --report-all
// lists every one.
// The report is described at the end from what the stages returned (DescribeBake; meshoptimizer's analyse
// functions are the model): no stage reads it, so it never becomes a channel between stages.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "baker/files/atomic_file.h"
#include "baker/0_prepare_scene.h"
#include "baker/1_trace_photons.h"
#include "baker/2_bin_photons.h"
#include "baker/3_irradiance_field.h"
#include "baker/4_refine_mesh.h"
#include "baker/5_write_maps.h"
#include "baker/baked_mesh.h"
#include "baker/options.h"
#include "baker/photons/progressive.h"
#include "mesh/lights.h"

namespace pb {

struct LightReport {
  uint32_t surface = 0;   // area lights; kNoSurface for the others
  std::string material;   // the light's name: its material's for an area light
  std::string kind;       // LightKindName
  double area = 0;  // [m^2]
  Rgb power;        // Phi [W]
  uint64_t photons = 0;
  std::string note;  // why it got no photons; "" when it got its share
};

struct SurfaceReport {
  std::string object;  // OBJ 'o'/'g' name of the surface's first triangle
  std::string material;
  double area = 0;  // [m^2]
  uint64_t frontHits = 0, backHits = 0;
  Rgb meanIrradiance;    // the written H averaged over the surface's faces by area [W/m^2]: all its light, the
                         // sampled direct light included
  Rgb photonIrradiance;  // its front-side photons' flux / area [W/m^2], independent of the estimator; without the
                         // direct light when that is sampled
  bool planar = true;
  double areaDistortion = 1;  // worst max(A_uv / A, A / A_uv) over its triangles
  float bandwidth = 0;        // h [m] its estimate used
  double coveredArea = 0;     // [m^2] that other geometry covers (estimators/surface_cover.h)
  // Its predicted error of H over its own vertices, relative to their mean H (PredictedErrorPerSurface); zero when
  // the bake did not estimate its noise.
  BakeError predicted;
};

struct BakeReport {
  BakeOptions options;
  unsigned threads = 0;
  size_t triangles = 0, degenerateTrianglesSkipped = 0, duplicateTrianglesSkipped = 0, vertices = 0, faces = 0;
  size_t curvedCharts = 0;          // surfaces mapped by LSCM
  double worstAreaDistortion = 1;   // over all charts
  std::vector<LightReport> lights;
  std::vector<SurfaceReport> surfaces;
  TraceStats trace;
  uint64_t storedHits = 0;   // of trace.hits, those kept in the photon store; the others were binned while traced
  std::vector<std::pair<std::string, double>> stageSeconds;  // in pipeline order
  TransportPlan plan;  // the effects simulated and skipped, with reasons
  std::vector<std::string> warnings;
  float exposure = 1;
  MapsWritten maps;  // --maps: the EXR files written and their texel count
  RefineReport refine;  // --refine / --subdivide: vertices before and after, interpolation error
  ProgressiveReport progressive;  // --resume, --save-photons, --target-noise rounds, interruption
  double noise = 0;  // the bake's predicted noise: 95th percentile of sigma_L / L (baker/photons/progressive.h, BakeNoise)
  BakeError error;   // its predicted relative RMS error of H, noise and bias (baker/photons/progressive.h, PredictedError)
  NoiseParts noiseParts;  // the noise of each source alone (baker/photons/progressive.h, BakeNoiseParts)
  // The gathered vertices whose light is weighed against the photons' (in narrow gaps, on surfaces smaller than their
  // kernel), the surfaces they lie on, and the mean over those vertices of their surface's weight of the gathered
  // light (baker/3_gap_weights.h; 1: the gathered light alone).
  struct NarrowGaps {
    uint64_t vertices = 0;
    uint32_t surfaces = 0;
    double meanWeight = 1;
  } narrowGaps;
  // The sparse surfaces read from their photons pooled with their neighbours' (with --h auto; baker/3_contributions.h,
  // PhotonIrradiance), their area [m^2] and the photons pooled across them.
  struct Pooled {
    uint32_t surfaces = 0;
    double area = 0;
    uint64_t photons = 0;
    uint64_t vertices = 0;  // of the written mesh, on pooled surfaces
    double lightShare = 0;  // the pooled photons' part of their H, of all the vertices' summed H (luminance)
    double reach = 0;       // the pooled estimate's reach [m] (PhotonIrradiance::PooledRadius)
  } pooled;
  double directionNoise = 0;  // with --sh, BakeDirectionNoise of the written mesh [rad]

  double TotalSeconds() const;
};

// What the stages returned, and what the driver recorded as they ran (times, warnings).
struct BakeResults {
  const BakeOptions& options;
  unsigned threads;
  const PreparedScene& scene;
  const PhotonStore& photons;
  const SurfaceBins& bins;
  const IrradianceField& field;
  const BakedMesh& mesh;  // the written mesh
  float exposure;         // the PLY's display exposure
  const RefineReport& refine;
  const MapsWritten& maps;
  const ProgressiveReport& progressive;
  double noise;  // BakeNoise of the vertices before refinement
  BakeError error;  // PredictedError of the same vertices
  NoiseParts noiseParts;  // BakeNoiseParts of the same vertices
  const std::vector<std::pair<std::string, double>>& stageSeconds;
  const std::vector<std::string>& warnings;
};
BakeReport DescribeBake(const BakeResults& results);

void PrintSummary(const BakeReport& report, const Log& log);
inline constexpr size_t kListed = 1000;
void WriteReportJson(OutputFiles& outputs, const std::string& path, const BakeReport& report);

}  // namespace pb
