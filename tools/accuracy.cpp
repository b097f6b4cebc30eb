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
// With --scene PATH, any scene file (a real interior, docs/real-assets.md), measured the same way one bake at a time:
// --defaults (bake SCENE -o OUT as it is), --quality, --photons or --reference (the path tracer at a given time).
//
// Usage: accuracy [--out DIR] [--quick] [--scene closed-form|box|office|PATH] [--threads T]. --quick runs a handful of
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
#include "baker/presets.h"
#include "baker/files/atomic_file.h"
#include "baker/option_ranges.h"
#include "tests/lambert.h"
#include "tests/test_scenes.h"
#include "tools/accuracy_report.h"
#include "tools/accuracy_runs.h"
#include "tools/cli_options.h"

namespace {

using namespace pb::accuracy;

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
      configs.push_back({{kind, kernel, automatic ? std::nullopt : std::optional(h), k, correction}, n});
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
  pb::ApplyDefaults(o, given, name);
  c.photons = o.photons, c.targetNoise = o.targetNoise, c.targetError = o.targetError, c.gaps = o.gaps, c.direct = o.direct;
  c.estimator.bandwidth = o.estimator.bandwidth;
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

Bench ParseBench(const std::string& name) {
  if (name == "closed-form") return Bench::kClosedForm;
  if (name == "box") return Bench::kBox;
  if (name == "office") return Bench::kOffice;
  return Bench::kScene;
}

std::string ScenePath(Bench bench, const std::string& name, const std::string& out) {
  switch (bench) {
    case Bench::kBox: return PB_SOURCE_DIR "/data/box/box_25mm.obj";
    case Bench::kOffice: return PB_SOURCE_DIR "/data/office_books/office_books.obj";
    case Bench::kScene: return name;
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
  app.add_option("--scene", sceneName,
                 "closed-form, or box / office: a bundled scene against a long path-traced bake; or a scene file "
                 "(OBJ, glTF), measured one bake at a time (--defaults, --quality, --photons or --reference)")
      ->check(CLI::IsMember({"closed-form", "box", "office"}) | CLI::ExistingFile)
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
  float h = *pb::EstimatorSettings{}.bandwidth;
  app.add_option("--h", h, "with --photons: h [m]")->capture_default_str();
  app.add_option("--target-noise", one.targetNoise, "with --photons: rounds to this noise, the first of --photons (bake --target-noise)");
  app.add_option("--target-error", one.targetError,
                 "with --photons: rounds to this predicted error, the first of --photons (bake --target-error)");
  bool defaults = false;
  app.add_flag("--defaults", defaults, "box, office or a scene file: one bake at bake's defaults (bake SCENE -o OUT)");
  std::string quality;
  app.add_option("--quality", quality, "box, office: one bake of this preset, as bake --quality (" + pb::QualityNames() +
                                       "; h per surface unless --h)");
  bool hAuto = false;
  app.add_flag("--h-auto", hAuto, "with --photons: h chosen per surface from its photons (bake --h auto)");
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
    one.estimator.bandwidth = hAuto ? std::nullopt : std::optional(h);
    pb::RequireOption(!defaults || quality.empty(), "--defaults", "goes without --quality");
    if (defaults) one.photons = pb::BakeOptions{}.photons, ApplyQuality("", {}, one);  // bake's first round
    if (!quality.empty())
      ApplyQuality(quality, {.bandwidth = app.count("--h") > 0, .photons = app.count("--photons") > 0,
                             .shadowRays = app.count("--direct-samples") + app.count("--direct-noise") > 0,
                             .gapPaths = app.count("--gap-paths") > 0, .smallArea = app.count("--gap-small-area") > 0},
                   one);
    pb::RequireOption(truthPaths >= 1 && truthPaths <= 10'000'000, "--truth-paths",
                      "must lie in [1, 10000000] paths per point");
    if (one.referencePaths > 0 && one.photons == 0) one.photons = 1;  // a reference traces none; the count is unused
    if (one.photons > 0) OptionsOf(sceneName, one, 1, threads).Validate();
    pb::RequireOption(one.photons > 0 || ParseBench(sceneName) != Bench::kScene, "--scene",
                      "a scene file is measured one bake at a time: give --defaults, --quality, --photons or --reference");
  };
  return pb::tools::RunTool(app, argc, argv, validate, [&] {
    std::filesystem::create_directories(out);
    const Bench bench = ParseBench(sceneName);
    const std::string scene = ScenePath(bench, sceneName, out);
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
