#include "baker/4_refine_mesh.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <fmt/format.h>

#include "baker/option_ranges.h"
#include "baker/runtime/interrupt.h"
#include "baker/tone_map.h"
#include "mesh/memory_budget.h"
#include "mesh/decimate.h"
#include "mesh/half_edge_mesh.h"
#include "mesh/interpolation_error.h"
#include "mesh/refine.h"
#include "mesh/subdivide.h"

namespace pb {

void RefineSettings::Validate() const {
  RequireOption(tolerance > 0 && tolerance < 1, "--tolerance", "must lie in (0, 1)");
  RequireOption(subdivide >= 0 && subdivide <= 8, "--subdivide", "must lie in [0, 8]");
  RequireOption(maxVertices >= 3 && maxVertices <= 1'000'000'000, "--max-vertices", "must lie in [3, 1e9]");
}

namespace {

using Vec3d = OpenMesh::Vec3d;
using FaceHandle = HalfEdgeMesh::FaceHandle;
using VertexHandle = HalfEdgeMesh::VertexHandle;

// Lattice points per edge at most; a face longer than this many spacings is judged more coarsely, and is cut
// anyway once its error shows.
constexpr int kMaxDivisions = 32;

// Node spacing of the irradiance grid, as a fraction of the surface's h; and a cap on all grids' nodes.
constexpr double kGridFraction = 0.25;
constexpr double kMaxGridNodes = 4e6;

// The photons' H per unit chart area (PhotonIrradiance::ChartDensity) of one surface on a regular grid in its
// chart, read between nodes by bilinear interpolation. Decimation
// weighs each collapse by the error of the faces it would make, and weighs large faces again and again as their
// neighbours change: reading H there from the grid costs a fraction of the estimator's price. Nodes h/4 apart
// follow the estimate's own detail (scale h) closely, and refinement, which judges faces against the
// estimator itself, mends what the grid misses.
class IrradianceGrid {
 public:
  IrradianceGrid(const PhotonIrradiance& photons, uint32_t surface, const Bounds2& bounds, double spacing)
      : lo_(bounds.lo), spacing_(spacing), nu_(int(std::ceil((bounds.hi.u - bounds.lo.u) / spacing)) + 2),
        nv_(int(std::ceil((bounds.hi.v - bounds.lo.v) / spacing)) + 2), nodes_(size_t(nu_) * nv_) {
    tbb::parallel_for(0, nv_, [&](int j) {
      for (int i = 0; i < nu_; ++i)
        nodes_[size_t(j) * nu_ + i] = photons.ChartDensity(surface, {float(lo_.u + i * spacing_), float(lo_.v + j * spacing_)});
    });
  }

  Rgb At(Point2 uv) const {
    const double x = std::clamp((uv.u - lo_.u) / spacing_, 0.0, nu_ - 1.000001);
    const double y = std::clamp((uv.v - lo_.v) / spacing_, 0.0, nv_ - 1.000001);
    const int i = int(x), j = int(y);
    const float fx = float(x - i), fy = float(y - j);
    return (Node(i, j) * (1 - fx) + Node(i + 1, j) * fx) * (1 - fy) + (Node(i, j + 1) * (1 - fx) + Node(i + 1, j + 1) * fx) * fy;
  }

 private:
  Rgb Node(int i, int j) const { return nodes_[size_t(j) * nu_ + i]; }

  Point2 lo_;
  double spacing_;
  int nu_, nv_;
  std::vector<Rgb> nodes_;
};

std::vector<IrradianceGrid> IrradianceGrids(const IrradianceField& field) {
  const SurfaceSet& surfaces = field.Prepared().surfaces;
  std::vector<Bounds2> bounds(surfaces.surfaces.size());
  double nodes = 0;
  for (uint32_t s = 0; s < bounds.size(); ++s) {
    for (uint32_t t : surfaces.surfaces[s].triangles)
      for (Point2 c : surfaces.cornerUv[t]) bounds[s].Extend(c);
    const double spacing = kGridFraction * field.Bandwidth(s);
    nodes += (double(bounds[s].hi.u - bounds[s].lo.u) / spacing + 2) * (double(bounds[s].hi.v - bounds[s].lo.v) / spacing + 2);
  }
  const double coarsen = std::max(1.0, std::sqrt(nodes / kMaxGridNodes));
  std::vector<IrradianceGrid> grids;
  for (uint32_t s = 0; s < bounds.size(); ++s)
    grids.emplace_back(field.Photons(), s, bounds[s], coarsen * kGridFraction * field.Bandwidth(s));
  return grids;
}

// The displayed grey level of the estimated radiance at any point of a refined mesh: exact at vertices (cached
// per surface, and per base triangle on textured surfaces, whose corners may sit on a texture seam), and from
// the irradiance grid between them.
class DisplayedLight {
 public:
  explicit DisplayedLight(const RefineInputs& in)
      : in_(in), sampler_(in.field.Prepared().scene, in.field.Prepared().surfaces, in.base),
        grids_(IrradianceGrids(in.field)) {
    const PreparedScene& prepared = in.field.Prepared();
    for (const Surface& s : prepared.surfaces.surfaces)
      textured_.push_back(prepared.scene.materials[s.material].albedoTexture >= 0);
  }

  // Exact: H from the field.
  double At(uint32_t surface, uint32_t base, const Vec3d& p) const {
    return Display(in_.field.Light(sampler_.At(surface, base, {p[0], p[1], p[2]})));
  }

  // The photons' H from the grid.
  double Approximately(uint32_t surface, uint32_t base, const Vec3d& p) const {
    const SurfacePoint a = sampler_.At(surface, base, {p[0], p[1], p[2]});
    return Display(in_.field.LightWith(a, PerSurfaceArea(grids_[surface].At(a.uv), a)));
  }

  double AtCorner(const HalfEdgeMesh& mesh, FaceHandle f, VertexHandle v) {
    const uint32_t s = mesh.Surface(f);
    const uint64_t key = uint64_t(v.idx()) << 32 | (textured_[s] ? (mesh.BaseTriangle(f) | 1u << 31) : s);
    auto [it, isNew] = cache_.emplace(key, 0.0);
    if (isNew) it->second = At(s, mesh.BaseTriangle(f), mesh.point(v));
    return it->second;
  }

  // The error of face f, or of f with its corner `moved` placed at vertex `to` (a collapse being weighed),
  // judged against the grid.
  InterpolationError ApproximateFaceError(const HalfEdgeMesh& mesh, FaceHandle f, VertexHandle moved,
                                          VertexHandle to) {
    std::array<VertexHandle, 3> corners = mesh.CornerVertices(f);
    for (VertexHandle& c : corners)
      if (c == moved) c = to;
    const std::array<Vec3d, 3> p{mesh.point(corners[0]), mesh.point(corners[1]), mesh.point(corners[2])};
    const std::array<double, 3> values{AtCorner(mesh, f, corners[0]), AtCorner(mesh, f, corners[1]),
                                       AtCorner(mesh, f, corners[2])};
    const uint32_t s = mesh.Surface(f), base = mesh.BaseTriangle(f);
    return LatticeError(p, values, Divisions(s, p), [&](const Vec3d& q) { return Approximately(s, base, q); });
  }

  // The error of face f against the estimator itself.
  InterpolationError FaceError(const HalfEdgeMesh& mesh, FaceHandle f) {
    const auto corners = mesh.CornerVertices(f);
    const std::array<double, 3> values{AtCorner(mesh, f, corners[0]), AtCorner(mesh, f, corners[1]),
                                       AtCorner(mesh, f, corners[2])};
    return ExactFaceError(mesh, f, values);
  }

  // The same with no cache, for the final figures, from any thread.
  InterpolationError ExactFaceError(const HalfEdgeMesh& mesh, FaceHandle f) const {
    const auto p = mesh.Corners(f);
    const uint32_t s = mesh.Surface(f), base = mesh.BaseTriangle(f);
    return ExactFaceError(mesh, f, {At(s, base, p[0]), At(s, base, p[1]), At(s, base, p[2])});
  }

  void Forget() { cache_.clear(); }  // vertex indices change when the mesh is garbage-collected
  const std::vector<bool>& Textured() const { return textured_; }

 private:
  InterpolationError ExactFaceError(const HalfEdgeMesh& mesh, FaceHandle f, const std::array<double, 3>& values) const {
    const auto p = mesh.Corners(f);
    const uint32_t s = mesh.Surface(f), base = mesh.BaseTriangle(f);
    return LatticeError(p, values, Divisions(s, p), [&](const Vec3d& q) { return At(s, base, q); });
  }

  double Display(const SurfaceLight& light) const { return DisplayedLuminance(light.Radiance(), in_.exposure); }
  int Divisions(uint32_t s, const std::array<Vec3d, 3>& p) const {
    return LatticeDivisions(p, 0.5 * in_.field.Bandwidth(s), kMaxDivisions);
  }

  const RefineInputs& in_;
  SurfacePointSampler sampler_;
  std::vector<IrradianceGrid> grids_;
  std::vector<bool> textured_;
  std::unordered_map<uint64_t, double> cache_;
};

// Refinement's priority module: the worst faces first, until every face is within the tolerance. It keeps each
// face's latest error against the estimator, which are the final figures once refinement ends.
class DisplayErrorModule : public RefineModule {
 public:
  // `errors`: every face's error now, by face index (ExactErrors).
  DisplayErrorModule(DisplayedLight& light, double tolerance, std::vector<InterpolationError> errors)
      : light_(light), tolerance_(tolerance), errors_(std::move(errors)), stale_(errors_.size(), false) {}
  std::string_view Name() const override { return "displayed luminance error"; }
  double Priority(const HalfEdgeMesh& mesh, FaceHandle f) override {
    if (stale_[f.idx()]) errors_[f.idx()] = light_.FaceError(mesh, f), stale_[f.idx()] = false;
    return errors_[f.idx()].max > tolerance_ ? errors_[f.idx()].max : kNoSplit;
  }
  void OnSplit(const HalfEdgeMesh& mesh, HalfEdgeMesh::VertexHandle v) override {
    errors_.resize(mesh.n_faces()), stale_.resize(mesh.n_faces());
    for (FaceHandle f : mesh.vf_range(v)) stale_[f.idx()] = true;
  }
  const std::vector<InterpolationError>& Errors() const { return errors_; }

 private:
  DisplayedLight& light_;
  double tolerance_;
  std::vector<InterpolationError> errors_;
  std::vector<bool> stale_;
};

// Decimation's priority module: a collapse is legal while every face it changes stays within the tolerance;
// the smallest error goes first.
template <typename MeshT>
class ModDisplayErrorT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModDisplayErrorT, MeshT, DisplayError);
  explicit ModDisplayErrorT(MeshT& mesh) : Base(mesh, false) {}
  void Set(DisplayedLight* light, double tolerance) { light_ = light, tolerance_ = tolerance; }
  float collapse_priority(const CollapseInfo& ci) override {
    double worst = 0;
    for (FaceHandle f : ci.mesh.vf_range(ci.v0)) {
      if (f == ci.fl || f == ci.fr) continue;  // removed by the collapse
      worst = std::max(worst, light_->ApproximateFaceError(ci.mesh, f, ci.v0, ci.v1).max);
      if (worst > tolerance_) return Base::ILLEGAL_COLLAPSE;
    }
    return float(worst);
  }

 private:
  DisplayedLight* light_ = nullptr;
  double tolerance_ = 0;
};

std::vector<bool> LockedSurfaces(const Scene& scene, const SurfaceSet& surfaces) {
  std::vector<bool> locked;
  for (const Surface& s : surfaces.surfaces) locked.push_back(!s.planar || scene.materials[s.material].albedoTexture >= 0);
  return locked;
}

// Coarsening's progress: collapses done, of at most one per vertex.
class CollapseProgress : public OpenMesh::Decimater::Observer {
 public:
  CollapseProgress(const Log& log, size_t vertices) : Observer(256), progress_(log, "coarsen mesh", vertices) {}
  void notify(size_t collapses) override { progress_.Advance(collapses - reported_), reported_ = collapses; }
  bool abort() const override { return InterruptRequested(); }  // Ctrl-C: RefineMesh gives up its mesh
  // Coarsening ends when no collapse is left, before one per vertex: `collapses` is all there was.
  void Complete(size_t collapses) {
    notify(collapses);
    progress_.Complete();
  }

 private:
  Progress progress_;
  size_t reported_ = 0;
};

SplitMesh ToSplitMesh(const HalfEdgeMesh& mesh, const RefineInputs& in) {
  return ToSplitMesh(mesh, in.field.Prepared().scene, in.field.Prepared().surfaces, in.base);
}

size_t DisplayVertices(const HalfEdgeMesh& mesh, const RefineInputs& in) { return ToSplitMesh(mesh, in).VertexCount(); }

// Collapses while every changed face stays within the tolerance, the smallest error first; then, if the mesh
// still has more display vertices than the budget, goes on past the tolerance (still the smallest error first)
// until it fits or no collapse keeps the geometry. Returns the display vertex count it leaves.
size_t Coarsen(HalfEdgeMesh& mesh, DisplayedLight& light, const RefineInputs& in, const RefineSettings& settings,
               RefineReport& report, const Log& log) {
  LockSurfaces(mesh, LockedSurfaces(in.field.Prepared().scene, in.field.Prepared().surfaces));
  OpenMesh::Decimater::DecimaterT<HalfEdgeMesh> decimater(mesh);
  CollapseProgress progress(log, mesh.n_vertices());
  decimater.set_observer(&progress);
  ModExactGeometryT<HalfEdgeMesh>::Handle geometry;
  ModDisplayErrorT<HalfEdgeMesh>::Handle error;
  decimater.add(geometry);
  decimater.add(error);
  decimater.module(error).Set(&light, settings.tolerance);
  decimater.initialize();
  report.collapses = decimater.decimate();
  decimater.module(error).Set(&light, INFINITY);
  size_t count = DisplayVertices(mesh, in);
  while (count > settings.maxVertices) {
    const size_t forced = decimater.decimate(count - settings.maxVertices);
    if (forced == 0) break;
    report.collapses += forced;
    report.collapsesPastTolerance += forced;
    count = DisplayVertices(mesh, in);
  }
  progress.Complete(report.collapses);
  mesh.garbage_collection();
  light.Forget();
  return count;
}

// After a Ctrl-C, refuses every cut, so that refinement ends at once; RefineMesh then gives up its mesh.
class UntilInterrupted : public RefineModule {
 public:
  std::string_view Name() const override { return "Ctrl-C"; }
  bool AllowsSplit(const HalfEdgeMesh&, HalfEdgeMesh::EdgeHandle) override { return !InterruptRequested(); }
};

// Every `stride`-th face's error against the estimator itself (the others' are left empty), in parallel over faces;
// after a Ctrl-C, no more (RefineMesh then gives up its mesh).
std::vector<InterpolationError> ExactErrors(const HalfEdgeMesh& mesh, const DisplayedLight& light, const Log& log,
                                            size_t stride = 1) {
  std::vector<InterpolationError> errors(mesh.n_faces());
  const size_t measured = (errors.size() + stride - 1) / stride;
  Progress progress(log, "measure mesh error", measured);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, measured, 64), [&](const tbb::blocked_range<size_t>& r) {
    if (InterruptRequested()) return;
    for (size_t k = r.begin(); k != r.end(); ++k) errors[k * stride] = light.ExactFaceError(mesh, FaceHandle{int(k * stride)});
    progress.Advance(r.size());
  });
  return errors;
}

// Without refinement the face errors only fill the report's figures: a uniform sample of this many faces gives
// them (each face costs about ten estimates: a subdivided office's 1.2M faces took 225 s of a 249 s bake).
constexpr size_t kMostFacesMeasured = 16384;
size_t MeasuredFaceStride(size_t faces) { return std::max<size_t>(1, (faces + kMostFacesMeasured - 1) / kMostFacesMeasured); }

// Returns every face's final error.
std::vector<InterpolationError> Refine(HalfEdgeMesh& mesh, DisplayedLight& light, const RefineInputs& in,
                                       const RefineSettings& settings, size_t displayVertices, RefineReport& report,
                                       const Log& log) {
  std::vector<double> minimumEdge;
  for (float h : in.field.Photons().Bandwidths()) minimumEdge.push_back(settings.minimumEdgeFraction * h);
  DisplayErrorModule error(light, settings.tolerance, ExactErrors(mesh, light, log));
  MinimumEdgeLength edgeLength(std::move(minimumEdge));
  VertexBudget budget(settings.maxVertices, displayVertices, light.Textured());
  UntilInterrupted interrupt;
  RefineModule* constraints[] = {&budget, &edgeLength, &interrupt};
  const RefineStats stats = RefineAdaptive(mesh, error, constraints);
  report.splits = stats.splits;
  for (const auto& [name, count] : stats.refusedBy) {
    if (name == budget.Name()) report.refusedByBudget = count;
    if (name == edgeLength.Name()) report.refusedByEdgeLength = count;
  }
  return error.Errors();
}

// The report's figures from every face's error. The mean and the 99th percentile weigh each face by its area,
// so that small faces, which refinement makes many of, count for the surface they cover. Summed in face order,
// so the figures do not depend on the thread count.
void SummariseErrors(const HalfEdgeMesh& mesh, const std::vector<InterpolationError>& errors, double tolerance,
                     RefineReport& report, size_t stride = 1) {
  struct FaceFigures {
    double max, mean, area;
  };
  std::vector<FaceFigures> faces;
  for (FaceHandle f : mesh.faces()) {
    if (f.idx() % stride != 0) continue;  // not measured
    const InterpolationError& e = errors[f.idx()];
    faces.push_back({e.max, e.points ? e.sum / double(e.points) : 0.0, mesh.FaceArea(f)});
  }
  double area = 0, weighted = 0, above = 0;
  for (const FaceFigures& f : faces) {
    report.maxError = std::max(report.maxError, f.max);
    area += f.area, weighted += f.area * f.mean, above += f.max > tolerance ? f.area : 0;
  }
  report.meanError = area > 0 ? weighted / area : 0;
  report.areaAboveTolerance = area > 0 ? above / area : 0;
  std::sort(faces.begin(), faces.end(), [](const FaceFigures& a, const FaceFigures& b) { return a.max < b.max; });
  double covered = 0;
  for (const FaceFigures& f : faces)
    if ((covered += f.area) >= 0.99 * area) {
      report.p99Error = f.max;
      break;
    }
}

// --subdivide's levels, with progress over the faces built (22M on the office at 5 levels).
HalfEdgeMesh Subdivide(const HalfEdgeMesh& mesh, int levels, const Log& log) {
  if (levels <= 0) return mesh;
  Progress progress(log, "subdivide (faces)", uint64_t(mesh.n_faces()) << (2 * levels));
  return SubdivideUniform(mesh, levels, [&](uint64_t faces) { progress.Advance(faces); });
}

}  // namespace

std::vector<std::string> SubdivisionTimeWarnings(size_t triangles, int levels, double secondsPerPoint) {
  if (levels <= 0) return {};
  // A closed triangle mesh has about half as many vertices as faces; each is estimated once.
  const double vertices = 0.5 * double(triangles) * std::pow(4.0, levels);
  return LongWorkWarnings(fmt::format("--subdivide {}", levels), fmt::format("about {:.3g} vertices to estimate", vertices),
                          vertices, secondsPerPoint, [](double) { return "each level fewer takes a quarter"; });
}

void CheckSubdivisionMemory(size_t triangles, int levels) {
  constexpr double kBytesPerFace = 400;
  const double faces = double(triangles) * std::pow(4.0, levels);
  RequireMemory("--subdivide", faces * kBytesPerFace, fmt::format("{} levels of {} triangles ({:.3g} faces)", levels,
                                                                  triangles, faces));
}

std::vector<std::string> NoiseWarnings(const IrradianceField& field, const SurfaceBins& bins, float exposure,
                                       float tolerance) {
  const PreparedScene& prepared = field.Prepared();
  std::vector<std::string> warnings;
  for (uint32_t s = 0; s < prepared.surfaces.surfaces.size(); ++s) {
    const Surface& surface = prepared.surfaces.surfaces[s];
    if (bins.FrontHits(s) == 0) continue;
    const double relative = field.Photons().UniformNoise(s, bins.FrontHits(s), surface.area);
    const Material& material = prepared.scene.materials[surface.material];
    const Rgb meanIrradiance = bins.FrontFlux(s) / float(surface.area);
    const Rgb mean = OutgoingRadiance(material.emission, material.albedo, meanIrradiance);
    const Rgb noisy = mean + material.albedo * meanIrradiance * float(kInvPi * relative);
    const double noise = DisplayedLuminance(noisy, exposure) - DisplayedLuminance(mean, exposure);
    if (noise <= tolerance) continue;
    warnings.push_back(fmt::format("{}: warning: surface {} ({}): the estimate's noise, about {:.3f} in grey level "
                                   "({:.1f}% of H), is above --tolerance {:.3g}: refinement there follows the noise; "
                                   "raise --photons or --h, or the tolerance",
                                   prepared.scene.path, s, material.name, noise, 100 * relative, tolerance));
  }
  return warnings;
}

RefinedMesh RefineMesh(const RefineInputs& in, const RefineSettings& settings, const Log& log) {
  RefineReport report;
  report.ran = true;
  report.verticesBefore = in.base.VertexCount();
  report.facesBefore = in.base.faces.size();
  const PreparedScene& prepared = in.field.Prepared();
  HalfEdgeMesh mesh = Subdivide(BuildHalfEdgeMesh(prepared.scene, prepared.surfaces), settings.subdivide, log);
  report.detachedFaces = mesh.detachedFaces;
  DisplayedLight light(in);
  std::vector<InterpolationError> errors;
  size_t stride = 1;
  if (settings.adaptive) {
    const size_t coarse = Coarsen(mesh, light, in, settings, report, log);
    errors = Refine(mesh, light, in, settings, coarse, report, log);
  } else {
    stride = MeasuredFaceStride(mesh.n_faces());
    errors = ExactErrors(mesh, light, log, stride);
  }
  SummariseErrors(mesh, errors, settings.tolerance, report, stride);
  std::atomic<bool> stopped{false};
  BakedMesh baked = EstimateIrradiance(in.field, ToSplitMesh(mesh, in), log, /*withNoise=*/false, [&](size_t) {
    if (InterruptRequested()) stopped = true;
    return !stopped;
  });
  if (stopped) return {{}, RefineReport{.interrupted = true}};
  report.verticesAfter = baked.mesh.VertexCount();
  report.facesAfter = baked.mesh.faces.size();
  if (report.refusedByBudget || report.collapsesPastTolerance)
    report.warnings.push_back(fmt::format("{}: warning: the vertex budget ({} vertices) left faces above the "
                                          "tolerance ({} collapses past it, {} cuts refused); raise --max-vertices "
                                          "or --tolerance", prepared.scene.path, settings.maxVertices,
                                          report.collapsesPastTolerance, report.refusedByBudget));
  if (report.verticesAfter > settings.maxVertices)
    report.warnings.push_back(fmt::format("{}: warning: the mesh keeps {} vertices, over the budget of {}: no "
                                          "further collapse leaves the geometry unchanged", prepared.scene.path,
                                          report.verticesAfter, settings.maxVertices));
  return {std::move(baked), std::move(report)};
}

}  // namespace pb
