// What one run of the accuracy tool (tools/accuracy.cpp) is and what it measured: its settings (Config), the
// relative errors of H it reached (ErrorSplit, per object ObjectError: dimensionless, relative to the mean true H),
// its seconds and peak MiB (Run), and the truth it is measured against (Truth, H in W/m^2 per vertex: Lambert's
// formula on the closed-form scene, or a path-traced reference bake on a bundled scene).
#pragma once

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "baker/bake.h"
#include "tests/lambert.h"

namespace pb::accuracy {

// The scene: box-sized, so that photon densities match a Cornell box. A 0.13 m light of radiance 50 at 0.55 m
// over a 0.56 m black floor cut into 40 x 40 cells.
constexpr float kLightSide = 0.13f, kRadiance = 50.0f, kHeight = 0.55f, kFloorSide = 0.56f;
constexpr int kFloorCells = 40;
constexpr double kEdgeBand = 0.1 * kFloorSide;  // vertices this close to the boundary count as edge vertices

// kScene: any scene file (--scene PATH), measured one configuration at a time against its own long reference.
enum class Bench { kClosedForm, kBox, kOffice, kScene };

struct Config {
  pb::EstimatorSettings estimator;  // its bandwidth none: h per surface (--h auto)
  uint64_t photons = 0;
  std::optional<float> targetNoise;  // rounds to this noise (bake --target-noise), the first of `photons`
  std::optional<float> targetError;  // rounds to this predicted error (bake --target-error), the first of `photons`
  pb::DirectSettings direct{pb::DirectLight::kPhotons};  // --direct, --direct-samples (the closed form: photons)
  uint32_t referencePaths = 0;  // > 0: a path tracer's vertex bake (--reference) instead of photons
  pb::GapSettings gaps;         // --gap-paths, with --direct sampled
  uint64_t guidePhotons = 0;    // --guide-photons: the gathered paths' first directions guided
  // The curve this run belongs to: the method on the box, the estimator on the closed form; a scene's bakes to a
  // target with h per surface are what a user asks for by --quality or --target-error.
  std::string Group(Bench bench) const {
    if (referencePaths > 0) return "path tracer";
    if (bench == Bench::kClosedForm) return pb::EstimatorName(estimator.kind);
    if ((targetError || targetNoise) && !estimator.bandwidth) return "quality targets";
    return direct.mode == pb::DirectLight::kSampled ? "sampled" : "photons";
  }
  std::string Label() const {
    const std::string guided = guidePhotons > 0 ? fmt::format(" guided {}", guidePhotons) : std::string();
    if (referencePaths > 0) return fmt::format("path tracer {} spp{}", referencePaths, guided);
    std::string s = direct.mode != pb::DirectLight::kSampled ? ""
                    : direct.noise > 0 ? fmt::format("sampled noise {} (<= {}) ", direct.noise, direct.samples)
                                       : fmt::format("sampled x{} ", direct.samples);
    s += pb::EstimatorName(estimator.kind);
    if (estimator.kind == pb::EstimatorKind::kKernel) s += "/" + pb::KernelName(estimator.kernel);
    s += estimator.kind == pb::EstimatorKind::kNearest ? fmt::format(" k={}", estimator.neighbours)
         : !estimator.bandwidth                        ? std::string(" h=auto")
                                                       : fmt::format(" h={}", *estimator.bandwidth);
    if (!estimator.edgeCorrection) s += " no-correction";
    if (direct.mode == pb::DirectLight::kSampled && gaps.paths != pb::GapSettings{}.paths)
      s += gaps.noise > 0 ? fmt::format(" gaps noise {} (<= {})", gaps.noise, gaps.paths) : fmt::format(" gaps={}", gaps.paths);
    if (direct.mode == pb::DirectLight::kSampled && gaps.smallArea > 0)
      s += fmt::format(" small<{}h2{}", gaps.smallArea, gaps.smallShare < 1 ? fmt::format(" ({:g}%)", 100 * gaps.smallShare) : "");
    if (direct.mode == pb::DirectLight::kSampled && gaps.edges) s += " edges";
    if (targetNoise) s += fmt::format(" target {}", *targetNoise);
    if (targetError) s += fmt::format(" target error {}", *targetError);
    return s + guided;
  }
};

struct ErrorSplit {
  double rmse = 0, rmseInterior = 0, rmseEdge = 0, bias = 0, maxError = 0, noise = 0, systematic = 0;
  double truthNoise = 0;  // the truth's own RMS standard error, relative like the rest (0 on the closed form)
  double edgeBias = 0;    // mean H - truth over the edge vertices
  double coveredMean = 0; // mean H over the covered vertices (whose truth is 0)
  uint32_t coveredVertices = 0, edgeVertices = 0;
  double meanTruth = 0;   // the mean exact H [W/m^2], which the rest are relative to
  pb::BakeError predicted;  // what the bake itself predicted (the first seed's report)
};

// One object's error, relative to its own mean true H.
struct ObjectError {
  double rmse = 0, bias = 0, truthNoise = 0, meanTruth = 0;  // meanTruth [W/m^2]
  uint32_t vertices = 0;
};
constexpr size_t kMaxObjects = 48;  // objects measured one by one; the rest are in the totals only

// What a child process measures and sends back through a pipe, as plain bytes.
struct Measured {
  double seconds = 0, traceSeconds = 0, estimateSeconds = 0;
  ErrorSplit error;
  std::array<ObjectError, kMaxObjects> objects{};
};

struct Run : Measured {
  Config config;
  double peakMiB = 0;
};

inline double ExactIrradiance(double x, double z) {
  const double l = kLightSide / 2;
  return pb::test::LambertPolygonIrradiance({x, 0, z}, {0, 1, 0},
                                            {{-l, kHeight, -l}, {l, kHeight, -l}, {l, kHeight, l}, {-l, kHeight, l}},
                                            kRadiance);
}

// The truth at each vertex that is measured: Lambert's formula on the closed form's floor (the light's vertices
// are left out), or a long reference bake's H on a bundled scene, every vertex.
struct Truth {
  std::vector<double> reference;  // per vertex [W/m^2] (luminance); empty on the closed form
  std::vector<double> variance;   // the reference's predicted sigma_H^2 per vertex [(W/m^2)^2]
  std::vector<uint32_t> object;   // each vertex's object (index into objects)
  std::vector<std::string> objects;
  std::vector<bool> boundary;     // on an edge of its surface that one triangle uses
  // Covered: the reference reads exactly 0 (every path and light sample from it is blocked at once: the floor
  // under a block). Edge: on the closed form, within kEdgeBand of the floor's boundary; on a scene, on its
  // surface's boundary (a contact line or an open edge) and not covered.
  bool Covered(size_t v) const { return !reference.empty() && reference[v] == 0; }
  bool Measured(pb::Point3 p) const { return !reference.empty() || std::abs(p.y) <= 1e-6f; }
  double At(size_t v, pb::Point3 p) const { return reference.empty() ? ExactIrradiance(p.x, p.z) : reference[v]; }
  double VarianceAt(size_t v) const { return variance.empty() ? 0.0 : variance[v]; }
  uint32_t ObjectAt(size_t v) const { return object.empty() ? 0 : object[v]; }
  bool Edge(size_t v, pb::Point3 p) const {
    if (!reference.empty()) return boundary[v] && !Covered(v);
    return kFloorSide / 2 - std::max(std::abs(p.x), std::abs(p.z)) < kEdgeBand;
  }
};


}  // namespace pb::accuracy
