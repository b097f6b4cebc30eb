// accuracy: what accuracy costs in time. Bakes a closed-form scene (a square light over a black floor, whose
// irradiance Lambert's polygon formula gives exactly; tests/lambert.h) over a sweep of photon counts, estimators,
// kernels, bandwidths and boundary correction, and records for each run:
//   wall time per stage [s] and peak memory [MiB] (each run is a child process, measured by wait4);
//   relative RMSE, mean bias and max error of H over floor vertices, for all, interior and edge vertices (edge:
//   within 0.1 m of the floor's boundary); all relative to the mean exact H;
//   the split of the error into noise and bias, from a second run with another seed:
//   noise^2 = mean((H1 - H2)^2) / 2, bias^2 = max(0, RMSE^2 - noise^2).
// Writes DIR/accuracy.csv, DIR/accuracy.svg (error against seconds, log-log, with each estimator's best error per
// second) and DIR/cheapest.md (the cheapest run reaching each error target).
//
// With --scene box or office, a bundled scene instead (the Cornell box gridded at 25 mm, data/box/box_25mm.obj, or
// the office with books), measured against a path-traced bake of --truth-paths per vertex (bake --reference):
// photons only, --direct sampled, and the path tracer's own vertex bake, each a curve. The truth's own noise (its predicted sigma_H per vertex) is taken out of
// the bias column. These scenes also write DIR/objects.md and DIR/objects.csv: the error of each object (relative
// RMSE and mean bias over its vertices, relative to its own mean true H) for every run, and in the table for the
// most accurate run of each method.
//
// Usage: accuracy [--out DIR] [--quick] [--scene closed-form|box|office] [--threads T]. --quick runs a handful of
// small configurations (a smoke test); the full sweeps take minutes on 2 cores (docs/accuracy.md).
#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "baker/bake.h"
#include "baker/files/atomic_file.h"
#include "baker/option_ranges.h"
#include "tests/lambert.h"
#include "tests/test_scenes.h"
#include "tools/cli_options.h"

namespace {

// The scene: box-sized, so that photon densities match a Cornell box. A 0.13 m light of radiance 50 at 0.55 m
// over a 0.56 m black floor cut into 40 x 40 cells.
constexpr float kLightSide = 0.13f, kRadiance = 50.0f, kHeight = 0.55f, kFloorSide = 0.56f;
constexpr int kFloorCells = 40;
constexpr double kEdgeBand = 0.1 * kFloorSide;  // vertices this close to the boundary count as edge vertices

enum class Bench { kClosedForm, kBox, kOffice };

struct Config {
  pb::EstimatorSettings estimator;
  bool autoBandwidth = false;
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
    if ((targetError || targetNoise) && autoBandwidth) return "quality targets";
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
         : autoBandwidth                               ? std::string(" h=auto")
                                                       : fmt::format(" h={}", estimator.bandwidth);
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

double ExactIrradiance(double x, double z) {
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

// Measured vertices' H (luminance) from one bake, and the stage times.
struct Sample {
  std::vector<double> h, exact, truthVariance;
  std::vector<uint32_t> object;
  std::vector<bool> edge, covered;
  double seconds = 0, trace = 0, estimate = 0;
  pb::BakeError predicted;  // the bake's own prediction of its error (BakeReport::error)
};

pb::BakeOptions OptionsOf(const std::string& scene, const Config& c, uint64_t seed, unsigned threads) {
  pb::BakeOptions o;
  o.scenePath = scene;
  o.direct = c.direct;
  o.referencePaths = c.referencePaths;
  o.gaps = c.gaps;
  o.guidePhotons = c.guidePhotons;
  o.estimator = c.estimator;
  o.autoBandwidth = c.autoBandwidth;
  o.photons = c.photons;
  o.targetNoise = c.targetNoise;
  o.targetError = c.targetError;
  o.seed = seed;
  o.threads = threads;
  return o;
}

pb::BakeResult BakeMesh(const std::string& scene, const Config& c, uint64_t seed, unsigned threads) {
  return pb::BakeMesh(OptionsOf(scene, c, seed, threads), pb::Log(true));
}

Sample BakeOnce(const std::string& scene, const Truth& truth, const Config& c, uint64_t seed, unsigned threads) {
  const pb::BakeResult r = BakeMesh(scene, c, seed, threads);
  Sample s;
  for (const auto& [stage, seconds] : r.report.stageSeconds) {
    s.seconds += seconds;
    if (stage == "trace") s.trace = seconds;
    if (stage == "estimate" || stage == "estimators" || stage == "bandwidth") s.estimate += seconds;
  }
  s.predicted = r.report.error;
  const pb::SplitMesh& mesh = r.mesh.mesh;
  for (size_t v = 0; v < mesh.VertexCount(); ++v) {
    const pb::Point3 p = mesh.positions[v];
    if (!truth.Measured(p)) continue;
    s.h.push_back(pb::Luminance(r.mesh.irradiance[v]));
    s.exact.push_back(truth.At(v, p));
    s.truthVariance.push_back(truth.VarianceAt(v));
    s.object.push_back(truth.ObjectAt(v));
    s.edge.push_back(truth.Edge(v, p));
    s.covered.push_back(truth.Covered(v));
  }
  return s;
}

ErrorSplit Errors(const Sample& a, const Sample& b) {
  double meanExact = 0;
  for (double e : a.exact) meanExact += e;
  meanExact /= double(a.exact.size());
  double all = 0, interior = 0, edge = 0, bias = 0, worst = 0, noise = 0, truthNoise = 0, edgeBias = 0, covered = 0;
  size_t nInterior = 0, nEdge = 0, nCovered = 0;
  for (size_t i = 0; i < a.h.size(); ++i) {
    const double d = a.h[i] - a.exact[i], d2 = d * d;
    all += d2;
    if (a.edge[i]) edgeBias += d;
    if (a.covered[i]) covered += a.h[i], ++nCovered;
    truthNoise += a.truthVariance[i];
    (a.edge[i] ? edge : interior) += d2;
    ++(a.edge[i] ? nEdge : nInterior);
    bias += d;
    worst = std::max(worst, std::abs(d));
    noise += (a.h[i] - b.h[i]) * (a.h[i] - b.h[i]) / 2;
  }
  const double n = double(a.h.size());
  ErrorSplit e;
  e.meanTruth = meanExact;
  e.rmse = std::sqrt(all / n) / meanExact;
  e.rmseInterior = std::sqrt(interior / double(std::max<size_t>(nInterior, 1))) / meanExact;
  e.rmseEdge = std::sqrt(edge / double(std::max<size_t>(nEdge, 1))) / meanExact;
  e.bias = bias / n / meanExact;
  e.maxError = worst / meanExact;
  e.noise = std::sqrt(noise / n) / meanExact;
  e.truthNoise = std::sqrt(truthNoise / n) / meanExact;
  e.edgeVertices = uint32_t(nEdge), e.coveredVertices = uint32_t(nCovered);
  e.edgeBias = edgeBias / double(std::max<size_t>(nEdge, 1)) / meanExact;
  e.coveredMean = covered / double(std::max<size_t>(nCovered, 1)) / meanExact;
  e.systematic = std::sqrt(std::max(0.0, e.rmse * e.rmse - e.noise * e.noise - e.truthNoise * e.truthNoise));
  e.predicted = a.predicted;
  return e;
}

// Each object's relative RMSE, mean bias and truth noise, over its own vertices and relative to its own mean.
std::array<ObjectError, kMaxObjects> ObjectErrors(const Sample& a) {
  std::array<ObjectError, kMaxObjects> sums{};
  std::array<double, kMaxObjects> squares{}, variances{};
  for (size_t i = 0; i < a.h.size(); ++i) {
    if (a.object[i] >= kMaxObjects) continue;
    ObjectError& o = sums[a.object[i]];
    const double d = a.h[i] - a.exact[i];
    ++o.vertices, o.meanTruth += a.exact[i], o.bias += d;
    squares[a.object[i]] += d * d, variances[a.object[i]] += a.truthVariance[i];
  }
  for (size_t k = 0; k < kMaxObjects; ++k) {
    ObjectError& o = sums[k];
    if (o.vertices == 0) continue;
    const double n = o.vertices;
    o.meanTruth /= n;
    const double scale = o.meanTruth > 0 ? 1 / o.meanTruth : 0.0;
    o.rmse = std::sqrt(squares[k] / n) * scale, o.bias = o.bias / n * scale;
    o.truthNoise = std::sqrt(variances[k] / n) * scale;
  }
  return sums;
}

// Runs `work` in a child process and returns the bytes it produced, and the child's peak memory [MiB]. Every bake
// runs in a child: its peak memory is its own, and the parent never starts TBB's worker threads, which a forked
// child would not inherit (a child forked after them ran its bakes on about one core).
template <class Work>
std::string InChild(const std::string& what, Work work, double* peakMiB = nullptr) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
  const pid_t child = fork();
  if (child == 0) {
    close(fds[0]);
    const std::string bytes = work();
    for (size_t done = 0; done < bytes.size();) {
      const ssize_t n = write(fds[1], bytes.data() + done, bytes.size() - done);
      if (n <= 0) _exit(1);
      done += size_t(n);
    }
    _exit(0);
  }
  close(fds[1]);
  std::string bytes;
  char buffer[65536];
  for (ssize_t n; (n = read(fds[0], buffer, sizeof buffer)) > 0;) bytes.append(buffer, size_t(n));
  close(fds[0]);
  int status = 0;
  rusage usage{};
  wait4(child, &status, 0, &usage);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) throw std::runtime_error("run failed: " + what);
  if (peakMiB) *peakMiB = double(usage.ru_maxrss) / 1024.0;  // kilobytes on Linux
  return bytes;
}

// One configuration (two seeds), in a child process.
Run Measure(const std::string& scene, const Truth& truth, const Config& c, unsigned threads) {
  Run run;
  run.config = c;
  const std::string bytes = InChild(c.Label(), [&] {
    const Sample a = BakeOnce(scene, truth, c, 1, threads), b = BakeOnce(scene, truth, c, 2, threads);
    const Measured m{a.seconds, a.trace, a.estimate, Errors(a, b), ObjectErrors(a)};
    return std::string(reinterpret_cast<const char*>(&m), sizeof m);
  }, &run.peakMiB);
  if (bytes.size() != sizeof(Measured)) throw std::runtime_error("run failed: " + c.Label());
  std::memcpy(static_cast<Measured*>(&run), bytes.data(), sizeof(Measured));
  return run;
}

std::vector<Config> ClosedFormConfigs(bool quick) {
  using pb::EstimatorKind;
  using pb::Kernel;
  std::vector<Config> configs;
  const std::vector<uint64_t> counts = quick ? std::vector<uint64_t>{10'000, 100'000}
                                             : std::vector<uint64_t>{10'000, 100'000, 1'000'000, 10'000'000};
  for (uint64_t n : counts) {
    const auto add = [&](EstimatorKind kind, Kernel kernel, float h, uint32_t k, bool correction, bool automatic) {
      configs.push_back({{kind, kernel, h, k, correction}, automatic, n});
    };
    add(EstimatorKind::kKernel, Kernel::kEpanechnikov, 0.05f, 50, true, true);
    if (quick) continue;
    for (Kernel kernel : pb::kAllKernels) add(EstimatorKind::kKernel, kernel, 0.05f, 50, true, false);
    for (float h : {0.02f, 0.03f, 0.1f}) add(EstimatorKind::kKernel, Kernel::kEpanechnikov, h, 50, true, false);
    add(EstimatorKind::kKernel, Kernel::kEpanechnikov, 0.05f, 50, false, false);
    for (float h : {0.02f, 0.05f, 0.1f}) add(EstimatorKind::kHistogram, Kernel::kEpanechnikov, h, 50, true, false);
    add(EstimatorKind::kHistogram, Kernel::kEpanechnikov, 0.05f, 50, true, true);
    for (uint32_t k : {20u, 50u, 200u}) add(EstimatorKind::kNearest, Kernel::kEpanechnikov, 0.05f, k, true, false);
    add(EstimatorKind::kNearest, Kernel::kEpanechnikov, 0.05f, 50, false, false);
  }
  return configs;
}

// A bundled scene's sweep: photons only (the paper's method) and --direct sampled over photon counts, h and direct
// samples, the path tracer's vertex bake over samples per vertex, and the quality presets with further error
// targets (each as production, with its target).
struct SceneSweep {
  std::vector<uint64_t> photonsOnly;
  std::vector<float> photonsOnlyH;
  std::vector<uint64_t> sampled;
  std::vector<float> sampledH;
  std::vector<uint32_t> shadowRays, paths;
  std::vector<double> directNoise;  // --direct-noise targets, each at every sampled count and h, up to 1,024 rays
  std::vector<std::string> presets;
  std::vector<float> errorTargets;  // --quality production --target-error E
  // The settings that meet the accuracy issue's targets (docs/accuracy.md): photons, h, shadow rays, and the edges
  // gathered with this many paths.
  struct Recipe {
    uint64_t photons;
    float h;
    uint32_t shadowRays, edgePaths;
  };
  std::vector<Recipe> recipes;
};

// --quality NAME as bake applies it, with bake's defaults for what is not given: the preset's target and first
// round, h per surface unless --h, and the smallest surfaces gathered.
void ApplyQuality(const std::string& name, const pb::GivenOptions& given, Config& c) {
  pb::BakeOptions o = OptionsOf("", c, 1, 0);
  pb::ApplyDefaults(o, given, name, true);
  c.photons = o.photons, c.targetNoise = o.targetNoise, c.targetError = o.targetError, c.gaps = o.gaps, c.direct = o.direct;
  c.autoBandwidth = o.autoBandwidth;
}

std::vector<Config> Sweep(const SceneSweep& sweep) {
  std::vector<Config> configs;
  const auto add = [&](pb::DirectLight mode, uint32_t samples, float h, uint64_t n, uint32_t paths) {
    Config c;
    c.estimator.bandwidth = h;
    c.photons = n;
    c.direct = {mode, samples};
    c.referencePaths = paths;
    configs.push_back(c);
  };
  for (uint64_t n : sweep.photonsOnly)
    for (float h : sweep.photonsOnlyH) add(pb::DirectLight::kPhotons, 64, h, n, 0);
  for (uint64_t n : sweep.sampled)
    for (float h : sweep.sampledH)
      for (uint32_t samples : sweep.shadowRays) add(pb::DirectLight::kSampled, samples, h, n, 0);
  for (uint64_t n : sweep.sampled)
    for (float h : sweep.sampledH)
      for (double noise : sweep.directNoise) {
        add(pb::DirectLight::kSampled, 1024, h, n, 0);
        configs.back().direct.noise = noise;
      }
  for (uint32_t paths : sweep.paths) add(pb::DirectLight::kPhotons, 64, 0.05f, 1, paths);
  const auto preset = [&](const std::string& name, std::optional<float> targetError) {
    Config c;
    c.direct.mode = pb::DirectLight::kSampled;
    c.targetError = targetError;
    ApplyQuality(name, {}, c);  // a target set before is kept (bake: --target-error given wins)
    configs.push_back(c);
  };
  for (const SceneSweep::Recipe& r : sweep.recipes) {
    add(pb::DirectLight::kSampled, r.shadowRays, r.h, r.photons, 0);
    configs.back().gaps.edges = true, configs.back().gaps.paths = r.edgePaths;
  }
  for (const std::string& name : sweep.presets) preset(name, std::nullopt);
  for (float e : sweep.errorTargets) preset("production", e);
  return configs;
}

std::vector<Config> SceneConfigs(Bench bench, bool quick) {
  const std::vector<std::string> kPresets = {"draft", "medium", "high", "production"};
  if (quick) return Sweep({{}, {}, {100'000}, {0.05f}, {16}, {64}, {}, {}});
  if (bench == Bench::kBox)
    return Sweep({{1'000'000, 4'000'000, 16'000'000}, {0.01f, 0.02f, 0.03f}, {250'000, 1'000'000, 4'000'000},
                  {0.05f, 0.08f, 0.12f}, {64, 100, 256, 1024}, {64, 256, 1024, 4096}, {0.02, 0.01}, kPresets, {0.015f, 0.01f},
                  {{8'000'000, 0.04f, 400, 3072}}});
  // The office is 5 x 4 x 3 m: about 30 times the box's area, so wider kernels and more photons.
  return Sweep({{4'000'000, 16'000'000}, {0.03f, 0.05f, 0.1f}, {1'000'000, 4'000'000, 16'000'000},
                {0.05f, 0.1f, 0.2f}, {64, 256}, {64, 256, 1024, 4096}, {}, kPresets, {0.015f},
                {{16'000'000, 0.1f, 400, 3072}}});
}

// Plain bytes of a Truth, to bring it back from the child that computed it.
template <class T>
void Put(std::string& out, const std::vector<T>& v) {
  const uint64_t n = v.size();
  out.append(reinterpret_cast<const char*>(&n), sizeof n);
  out.append(reinterpret_cast<const char*>(v.data()), n * sizeof(T));
}
template <class T>
std::vector<T> Take(std::string_view& in) {
  uint64_t n = 0;
  std::memcpy(&n, in.data(), sizeof n);
  std::vector<T> v(n);
  std::memcpy(v.data(), in.data() + sizeof n, n * sizeof(T));
  in.remove_prefix(sizeof n + n * sizeof(T));
  return v;
}
std::string Serialise(const Truth& t) {
  std::string out;
  Put(out, t.reference), Put(out, t.variance), Put(out, t.object);
  Put(out, std::vector<uint8_t>(t.boundary.begin(), t.boundary.end()));
  std::string names;
  for (const std::string& o : t.objects) names += o + '\n';
  Put(out, std::vector<char>(names.begin(), names.end()));
  return out;
}
Truth Deserialise(std::string_view in) {
  Truth t;
  t.reference = Take<double>(in), t.variance = Take<double>(in), t.object = Take<uint32_t>(in);
  const std::vector<uint8_t> boundary = Take<uint8_t>(in);
  t.boundary.assign(boundary.begin(), boundary.end());
  const std::vector<char> names = Take<char>(in);
  std::string name;
  for (char ch : names) (ch == '\n') ? (t.objects.push_back(name), name.clear()) : name.push_back(ch);
  return t;
}

Truth ComputeSceneTruth(const std::string& scene, uint32_t paths, unsigned threads);

// A bundled scene's truth, computed in a child process (see InChild), or read from `cache` if it exists there,
// which it is written to otherwise (a cache is only valid for the same scene and paths).
Truth SceneTruth(const std::string& scene, uint32_t paths, unsigned threads, const std::string& cache) {
  if (!cache.empty() && std::filesystem::exists(cache)) {
    std::ifstream in(cache, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return Deserialise(bytes);
  }
  const std::string bytes = InChild("the truth", [&] { return Serialise(ComputeSceneTruth(scene, paths, threads)); });
  if (!cache.empty()) pb::WriteFileAtomically(cache, [&](std::ostream& out) { out << bytes; });
  return Deserialise(bytes);
}

// A path-traced bake with `paths` per vertex (seed 99, unlike every measured run), its predicted noise per vertex,
// each vertex's object, and the vertices on a surface's boundary.
Truth ComputeSceneTruth(const std::string& scene, uint32_t paths, unsigned threads) {
  Config c;
  c.photons = 1;
  c.referencePaths = paths;
  const pb::BakeResult r = BakeMesh(scene, c, 99, threads);
  Truth truth;
  truth.objects = r.names.objects;
  for (size_t v = 0; v < r.mesh.irradiance.size(); ++v) {
    const double h = pb::Luminance(r.mesh.irradiance[v]), sigma = h * r.mesh.irradianceNoise[v];
    truth.reference.push_back(h);
    truth.variance.push_back(sigma * sigma);
    truth.object.push_back(r.names.objectOfSurface[r.mesh.mesh.surface[v]]);
  }
  std::map<std::pair<uint32_t, uint32_t>, int> uses;  // the split mesh's edges (a surface's own vertices)
  for (const auto& f : r.mesh.mesh.faces)
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(f[k], f[(k + 1) % 3])];
  truth.boundary.assign(truth.reference.size(), false);
  for (const auto& [edge, count] : uses)
    if (count == 1) truth.boundary[edge.first] = truth.boundary[edge.second] = true;
  return truth;
}

void WriteCsv(const std::string& path, const std::vector<Run>& runs) {
  pb::WriteFileAtomically(path, [&](std::ostream& out) {
    out << "estimator,kernel,h_m,auto_h,k,edge_correction,photons,seconds,trace_s,estimate_s,peak_mib,rmse_rel,"
           "rmse_interior_rel,rmse_edge_rel,mean_bias_rel,max_error_rel,noise_rel,bias_rel,direct,direct_samples,"
           "reference_paths,truth_noise_rel,edge_vertices,edge_bias_rel,covered_vertices,covered_mean_rel,direct_noise,target_noise,"
           "predicted_rel,predicted_noise_rel,predicted_bias_rel\n";
    for (const Run& r : runs) {
      const pb::EstimatorSettings& e = r.config.estimator;
      out << fmt::format("{},{},{},{},{},{},{},{:.4f},{:.4f},{:.4f},{:.1f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},"
                         "{},{},{},{:.5f},{},{:.5f},{},{:.5f},{},{},{:.5f},{:.5f},{:.5f}\n",
                         pb::EstimatorName(e.kind), pb::KernelName(e.kernel), e.bandwidth, r.config.autoBandwidth,
                         e.neighbours, e.edgeCorrection, r.config.photons, r.seconds, r.traceSeconds,
                         r.estimateSeconds, r.peakMiB, r.error.rmse, r.error.rmseInterior, r.error.rmseEdge,
                         r.error.bias, r.error.maxError, r.error.noise, r.error.systematic,
                         pb::DirectLightName(r.config.direct.mode), r.config.direct.samples, r.config.referencePaths,
                         r.error.truthNoise, r.error.edgeVertices, r.error.edgeBias, r.error.coveredVertices,
                         r.error.coveredMean, r.config.direct.noise, r.config.targetNoise.value_or(0),
                         r.error.predicted.Total(), r.error.predicted.noise, r.error.predicted.bias);
    }
  });
}

// Log-log SVG of relative RMSE against seconds: every run as a dot, and each estimator's lower envelope (the
// best error reachable in a given time) as a line.
void WriteSvg(const std::string& path, const std::vector<Run>& runs, Bench bench) {
  constexpr double kW = 720, kH = 480, kLeft = 70, kBottom = 50, kTop = 20, kRight = 160;
  double t0 = 1e9, t1 = 0, e0 = 1e9, e1 = 0;
  for (const Run& r : runs) {
    t0 = std::min(t0, r.seconds), t1 = std::max(t1, r.seconds);
    e0 = std::min(e0, r.error.rmse), e1 = std::max(e1, r.error.rmse);
  }
  const double lt0 = std::floor(std::log10(t0)), lt1 = std::ceil(std::log10(t1));
  const double le0 = std::floor(std::log10(e0)), le1 = std::ceil(std::log10(e1));
  const auto X = [&](double t) { return kLeft + (std::log10(t) - lt0) / (lt1 - lt0) * (kW - kLeft - kRight); };
  const auto Y = [&](double e) { return kH - kBottom - (std::log10(e) - le0) / (le1 - le0) * (kH - kBottom - kTop); };
  std::vector<std::string> groups;  // in order of first appearance
  for (const Run& r : runs)
    if (std::find(groups.begin(), groups.end(), r.config.Group(bench)) == groups.end()) groups.push_back(r.config.Group(bench));
  const std::vector<std::string> colours = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"};
  std::string svg = fmt::format("<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' font-family='sans-serif' "
                                "font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n", kW, kH);
  for (double l = lt0; l <= lt1; ++l)
    svg += fmt::format("<line x1='{0}' x2='{0}' y1='{1}' y2='{2}' stroke='#ddd'/><text x='{0}' y='{3}' "
                       "text-anchor='middle'>{4:g} s</text>\n", X(std::pow(10, l)), kTop, kH - kBottom,
                       kH - kBottom + 16, std::pow(10, l));
  for (double l = le0; l <= le1; ++l)
    svg += fmt::format("<line x1='{0}' x2='{1}' y1='{2}' y2='{2}' stroke='#ddd'/><text x='{3}' y='{2}' "
                       "text-anchor='end'>{4:g}%</text>\n", kLeft, kW - kRight, Y(std::pow(10, l)), kLeft - 6,
                       100 * std::pow(10, l));
  svg += fmt::format("<text x='{}' y='{}' text-anchor='middle'>wall time of one bake (2 cores)</text>\n",
                     (kLeft + kW - kRight) / 2, kH - 10);
  svg += fmt::format("<text x='14' y='{}' transform='rotate(-90 14 {})' text-anchor='middle'>relative RMSE of H</text>\n",
                     kH / 2, kH / 2);
  int legend = 0;
  for (size_t g = 0; g < groups.size(); ++g) {
    const std::string& c = colours[g % colours.size()];
    std::vector<const Run*> mine;
    for (const Run& r : runs)
      if (r.config.Group(bench) == groups[g]) mine.push_back(&r);
    std::sort(mine.begin(), mine.end(), [](const Run* a, const Run* b) { return a->seconds < b->seconds; });
    std::string envelope;
    double best = 1e300;
    for (const Run* r : mine) {
      svg += fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='3' fill='{}' fill-opacity='0.45'/>\n", X(r->seconds),
                         Y(r->error.rmse), c);
      if (r->error.rmse < best) {
        best = r->error.rmse;
        envelope += fmt::format("{:.1f},{:.1f} ", X(r->seconds), Y(best));
      }
    }
    svg += fmt::format("<polyline points='{}' fill='none' stroke='{}' stroke-width='2'/>\n", envelope, c);
    svg += fmt::format("<rect x='{}' y='{}' width='12' height='12' fill='{}'/><text x='{}' y='{}'>{}</text>\n",
                       kW - kRight + 12, kTop + 20 * legend, c, kW - kRight + 30, kTop + 20 * legend + 11,
                       groups[g]);
    ++legend;
  }
  svg += "</svg>\n";
  pb::WriteFileAtomically(path, [&](std::ostream& out) { out << svg; });
}

// The cheapest run reaching each error target.
void WriteCheapest(const std::string& path, const std::vector<Run>& runs) {
  std::string md = "| target RMSE | cheapest run | photons | seconds | RMSE | peak MiB |\n|---|---|---|---|---|---|\n";
  for (double target : {0.10, 0.05, 0.03, 0.02, 0.01}) {
    const Run* cheapest = nullptr;
    for (const Run& r : runs)
      if (r.error.rmse <= target && (!cheapest || r.seconds < cheapest->seconds)) cheapest = &r;
    md += cheapest ? fmt::format("| {:.0f}% | {} | {} | {:.3f} | {:.2f}% | {:.0f} |\n", 100 * target,
                                 cheapest->config.Label(),
                                 cheapest->config.referencePaths > 0 ? std::string("-") : std::to_string(cheapest->config.photons),
                                 cheapest->seconds,
                                 100 * cheapest->error.rmse, cheapest->peakMiB)
                   : fmt::format("| {:.0f}% | none in the sweep | | | | |\n", 100 * target);
  }
  pb::WriteFileAtomically(path, [&](std::ostream& out) { out << md; });
}

// Every run's error per object (objects.csv), and a table of each object's error in the most accurate run of each
// method (objects.md).
void WriteObjects(const std::string& dir, const std::vector<Run>& runs, const Truth& truth, Bench bench) {
  const size_t count = std::min(truth.objects.size(), kMaxObjects);
  pb::WriteFileAtomically(dir + "/objects.csv", [&](std::ostream& out) {
    out << "run,photons,seconds,object,vertices,mean_truth_w_m2,rmse_rel,mean_bias_rel,truth_noise_rel\n";
    for (const Run& r : runs)
      for (size_t k = 0; k < count; ++k)
        if (const ObjectError& o = r.objects[k]; o.vertices > 0)
          out << fmt::format("{},{},{:.4f},{},{},{:.6g},{:.5f},{:.5f},{:.5f}\n", r.config.Label(), r.config.photons,
                             r.seconds, truth.objects[k], o.vertices, o.meanTruth, o.rmse, o.bias, o.truthNoise);
  });
  std::vector<const Run*> best;  // the least RMSE of each method, in order of first appearance
  for (const Run& r : runs) {
    const auto same = std::find_if(best.begin(), best.end(),
                                   [&](const Run* b) { return b->config.Group(bench) == r.config.Group(bench); });
    if (same == best.end()) best.push_back(&r);
    else if (r.error.rmse < (*same)->error.rmse) *same = &r;
  }
  std::string md = "| object | vertices | mean true H [W/m²] | truth's noise |";
  for (const Run* r : best) md += fmt::format(" {} ({:.2f} s): RMSE, bias |", r->config.Label(), r->seconds);
  md += "\n|---|---|---|---|";
  for (size_t b = 0; b < best.size(); ++b) md += "---|";
  md += "\n";
  const auto row = [&](const std::string& name, uint32_t vertices, double mean, double truthNoise,
                       const auto& errorOf) {
    md += fmt::format("| {} | {} | {:.4g} | {:.2f}% |", name, vertices, mean, 100 * truthNoise);
    for (const Run* r : best) {
      const auto [rmse, bias] = errorOf(*r);
      md += fmt::format(" {:.2f}%, {:+.2f}% |", 100 * rmse, 100 * bias);
    }
    md += "\n";
  };
  for (size_t k = 0; k < count; ++k) {
    const ObjectError& o = best.front()->objects[k];
    if (o.vertices == 0) continue;
    row(truth.objects[k], o.vertices, o.meanTruth, o.truthNoise,
        [&](const Run& r) { return std::pair{r.objects[k].rmse, r.objects[k].bias}; });
  }
  const ErrorSplit& all = best.front()->error;
  row("**all**", uint32_t(truth.reference.size()), all.meanTruth, all.truthNoise,
      [](const Run& r) { return std::pair{r.error.rmse, r.error.bias}; });
  md += fmt::format("| **edge vertices**: mean bias, of the mean H | {} | | |", all.edgeVertices);
  for (const Run* r : best) md += fmt::format(" {:+.2f}% |", 100 * r->error.edgeBias);
  md += fmt::format("\n| **covered vertices** (true H = 0): mean H, of the mean H | {} | 0 | |", all.coveredVertices);
  for (const Run* r : best) md += fmt::format(" {:.2f}% |", 100 * r->error.coveredMean);
  md += "\n";
  pb::WriteFileAtomically(dir + "/objects.md", [&](std::ostream& out) { out << md; });
}

Bench ParseBench(const std::string& name) {
  if (name == "closed-form") return Bench::kClosedForm;
  if (name == "box") return Bench::kBox;
  return Bench::kOffice;
}

std::string ScenePath(Bench bench, const std::string& out) {
  switch (bench) {
    case Bench::kBox: return PB_SOURCE_DIR "/data/box/box_25mm.obj";
    case Bench::kOffice: return PB_SOURCE_DIR "/data/office_books/office_books.obj";
    default:
      return pb::test::WriteSquareLightOverFloor(out, kLightSide, kRadiance, kHeight, kFloorSide, kFloorCells);
  }
}


}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"accuracy: error of H against time, on a closed-form scene or a bundled scene (photonbake)"};
  std::string out = "out/accuracy", sceneName = "closed-form";
  bool quick = false;
  unsigned threads = 0;
  uint32_t truthPaths = 16384;
  app.add_option("--out", out, "folder for accuracy.csv, accuracy.svg and cheapest.md")->capture_default_str();
  app.add_flag("--quick", quick, "a handful of small runs, as a smoke test");
  app.add_option("--threads", threads, "worker threads per bake; 0 = all cores")->capture_default_str();
  app.add_option("--scene", sceneName, "closed-form, or box / office: a bundled scene against a long path-traced bake")
      ->check(CLI::IsMember({"closed-form", "box", "office"}))
      ->capture_default_str();
  app.add_option("--truth-paths", truthPaths, "box, office: paths per vertex of the truth")->capture_default_str();
  std::string truthCache;
  app.add_option("--truth-cache", truthCache,
                 "box, office: read the truth from this file if it exists, else write it there (same scene and "
                 "--truth-paths only)");
  // One sampled bake instead of the sweep (box, office).
  Config one;
  one.direct.mode = pb::DirectLight::kSampled;
  app.add_option("--photons", one.photons, "box, office: measure only --direct sampled with this many photons");
  app.add_option("--h", one.estimator.bandwidth, "with --photons: h [m]")->capture_default_str();
  app.add_option("--target-noise", one.targetNoise, "with --photons: rounds to this noise, the first of --photons (bake --target-noise)");
  app.add_option("--target-error", one.targetError,
                 "with --photons: rounds to this predicted error, the first of --photons (bake --target-error)");
  std::string quality;
  app.add_option("--quality", quality, "box, office: one bake of this preset, as bake --quality (" + pb::QualityNames() +
                                       "; h per surface unless --h)");
  app.add_flag("--h-auto", one.autoBandwidth, "with --photons: h chosen per surface from its photons (bake --h auto)");
  app.add_option("--direct-samples", one.direct.samples,
                 "with --photons: shadow rays per point (with --direct-noise: at most)")
      ->capture_default_str();
  app.add_option("--direct-noise", one.direct.noise,
                 "with --photons: the points' noise target (0: fixed --direct-samples)")
      ->capture_default_str();
  app.add_option("--gap-paths", one.gaps.paths, "with --photons: paths gathered in narrow gaps")->capture_default_str();
  app.add_option("--gap-noise", one.gaps.noise, "with --photons: the gathered points' noise target (0: --gap-paths)")
      ->capture_default_str();
  app.add_option("--gap-facing", one.gaps.facing, "with --photons: the gaps' probe fraction")->capture_default_str();
  app.add_option("--gap-reach", one.gaps.reach, "with --photons: the gaps' probe reach, in h")->capture_default_str();
  app.add_flag("--gap-edges", one.gaps.edges, "with --photons: every point on a flat surface's boundary is gathered");
  app.add_option("--gap-small-area", one.gaps.smallArea, "with --photons: surfaces below this many h^2 are gathered")
      ->capture_default_str();
  app.add_option("--reference", one.referencePaths,
                 "box, office: measure only the path tracer's vertex bake (bake --reference) with this many paths");
  app.add_option("--guide-photons", one.guidePhotons,
                 "with --photons or --reference: the gathered paths' first directions from importance maps of this "
                 "many photons (bake --guide-photons)");
  const auto validate = [&] {  // with bake's ranges (baker/option_ranges.h)
    pb::RequireThreads(threads);
    if (!quality.empty())
      ApplyQuality(quality, {.bandwidth = app.count("--h") > 0, .photons = app.count("--photons") > 0,
                             .shadowRays = app.count("--direct-samples") + app.count("--direct-noise") > 0,
                             .gapPaths = app.count("--gap-paths") > 0, .smallArea = app.count("--gap-small-area") > 0},
                   one);
    pb::RequireOption(truthPaths >= 1 && truthPaths <= 10'000'000, "--truth-paths",
                      "must lie in [1, 10000000] paths per point");
    if (one.referencePaths > 0 && one.photons == 0) one.photons = 1;  // a reference traces none; the count is unused
    if (one.photons > 0) OptionsOf(sceneName, one, 1, threads).Validate();
  };
  return pb::tools::RunTool(app, argc, argv, validate, [&] {
    std::filesystem::create_directories(out);
    const Bench bench = ParseBench(sceneName);
    const std::string scene = ScenePath(bench, out);
    const bool closedForm = bench == Bench::kClosedForm;
    const Truth truth = closedForm ? Truth{} : SceneTruth(scene, quick ? 256 : truthPaths, threads, truthCache);
    std::vector<Run> runs;
    const std::vector<Config> configs = closedForm    ? ClosedFormConfigs(quick)
                                        : one.photons ? std::vector<Config>{one}
                                                      : SceneConfigs(bench, quick);
    for (size_t i = 0; i < configs.size(); ++i) {
      runs.push_back(Measure(scene, truth, configs[i], threads));
      const Run& r = runs.back();
      fmt::print(stderr,
                 "[{}/{}] {:<32} {:>9} photons  {:7.3f} s  RMSE {:6.2f}% (noise {:.2f}%, bias {:.2f}%; predicted {:.2f}%: "
                 "{:.2f}% and {:.2f}%)  {:.0f} MiB{}\n",
                 i + 1, configs.size(), r.config.Label(), r.config.referencePaths > 0 ? 0 : r.config.photons, r.seconds,
                 100 * r.error.rmse, 100 * r.error.noise, 100 * r.error.systematic, 100 * r.error.predicted.Total(),
                 100 * r.error.predicted.noise, 100 * r.error.predicted.bias, r.peakMiB,
                 closedForm ? std::string()
                            : fmt::format("  edges {:+.2f}%, covered {:.2f}%", 100 * r.error.edgeBias,
                                          100 * r.error.coveredMean));
    }
    WriteCsv(out + "/accuracy.csv", runs);
    WriteSvg(out + "/accuracy.svg", runs, bench);
    WriteCheapest(out + "/cheapest.md", runs);
    if (!closedForm) WriteObjects(out, runs, truth, bench);
    fmt::print(stderr, "wrote {0}/accuracy.csv, {0}/accuracy.svg and {0}/cheapest.md{1}\n", out,
               closedForm ? "" : fmt::format(", {0}/objects.csv and {0}/objects.md", out));
  });
}
