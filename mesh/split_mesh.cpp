#include "mesh/split_mesh.h"

#include <fmt/format.h>
#include <fnmatch.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "mesh/errors.h"

namespace pb {
namespace {

template <typename T>
T Interpolate(const std::array<T, 3>& c, const std::array<double, 2>& b) {
  const double b0 = 1 - b[0] - b[1];
  return c[0] * float(b0) + c[1] * float(b[0]) + c[2] * float(b[1]);
}
Point2 Interpolate(const std::array<Point2, 3>& c, const std::array<double, 2>& b) {
  const double b0 = 1 - b[0] - b[1];
  return {float(b0 * c[0].u + b[0] * c[1].u + b[1] * c[2].u), float(b0 * c[0].v + b[0] * c[1].v + b[1] * c[2].v)};
}

double Dot3(const Point3d& a, const Point3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point3d Minus(const Point3d& a, const Point3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Point3d ToPoint3d(Point3 p) { return {p.x, p.y, p.z}; }

// The base mesh's face of each scene triangle: SplitBySurface orders its faces by surface, then by the surface's
// (ascending) triangles.
std::vector<uint32_t> SplitFaceOfTriangle(const Scene& scene, const SurfaceSet& surfaces) {
  std::vector<uint32_t> face(scene.triangles.size());
  uint32_t next = 0;
  for (const Surface& s : surfaces.surfaces)
    for (uint32_t t : s.triangles) face[t] = next++;
  return face;
}

// The point of segment [a, b] nearest to p.
Point2 NearestOnSegment(Point2 p, Point2 a, Point2 b) {
  const double du = double(b.u) - a.u, dv = double(b.v) - a.v, length2 = du * du + dv * dv;
  const double t = length2 > 0 ? std::clamp(((double(p.u) - a.u) * du + (double(p.v) - a.v) * dv) / length2, 0.0, 1.0) : 0.0;
  return {float(a.u + t * du), float(a.v + t * dv)};
}

double Distance2(Point2 a, Point2 b) {
  const double du = double(a.u) - b.u, dv = double(a.v) - b.v;
  return du * du + dv * dv;
}

// Barycentrics (b1, b2) of uv in chart triangle c, and whether uv lies inside it (edges included).
struct ChartBarycentrics {
  std::array<double, 2> b;
  bool inside;
};
ChartBarycentrics BarycentricsInChart(const std::array<Point2, 3>& c, Point2 uv) {
  const double area = SignedArea(c[0], c[1], c[2]);
  if (area == 0) return {{0, 0}, false};
  const double b1 = SignedArea(c[0], uv, c[2]) / area, b2 = SignedArea(c[0], c[1], uv) / area;
  return {{b1, b2}, b1 >= 0 && b2 >= 0 && b1 + b2 <= 1};
}

// Smooth normals and local area ratios of a curved surface's vertices, from the triangles around each.
void FinishCurvedVertices(const Scene& scene, const SurfaceSet& surfaces, const Surface& surface, size_t first,
                          SplitMesh& mesh) {
  const size_t count = mesh.positions.size() - first;
  std::vector<Vector3> normalSum(count);
  std::vector<double> uvArea(count, 0), area(count, 0);
  for (size_t f = mesh.faces.size() - surface.triangles.size(), i = 0; f < mesh.faces.size(); ++f, ++i) {
    const uint32_t t = surface.triangles[i];
    for (uint32_t v : mesh.faces[f]) {
      normalSum[v - first] = normalSum[v - first] + scene.AreaVector(t);
      uvArea[v - first] += std::fabs(SignedArea(surfaces.cornerUv[t][0], surfaces.cornerUv[t][1], surfaces.cornerUv[t][2]));
      area[v - first] += scene.Area(t);
    }
  }
  for (size_t v = 0; v < count; ++v) {
    mesh.normals[first + v] = NormalFrom(normalSum[v]);
    mesh.uvAreaRatio[first + v] = area[v] > 0 ? float(uvArea[v] / area[v]) : 1.0f;
  }
}

}  // namespace

SplitMesh SplitBySurface(const Scene& scene, const SurfaceSet& surfaces, const std::vector<bool>& keep) {
  SplitMesh mesh;
  mesh.origin = scene.origin;
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
    if (!keep.empty() && !keep[s]) continue;
    const Surface& surface = surfaces.surfaces[s];
    const size_t first = mesh.positions.size();
    // (scene position, texture coordinate) -> this surface's copy: a textured surface is also split at texture
    // seams, where one position has two texture coordinates (and so two albedos).
    std::unordered_map<uint64_t, uint32_t> splitIndexOf;
    const bool textured = scene.materials[surface.material].albedoTexture >= 0;
    for (uint32_t t : surface.triangles) {
      std::array<uint32_t, 3> face{};
      for (int k = 0; k < 3; ++k) {
        const uint32_t original = scene.triangles[t].v[k], vt = textured ? scene.triangles[t].vt[k] : 0;
        auto [it, isNew] = splitIndexOf.emplace(uint64_t(original) << 32 | vt, uint32_t(mesh.positions.size()));
        if (isNew)
          mesh.AddVertex(scene.positions[original], surface.chart.frame.n, surfaces.cornerUv[t][k],
                         textured ? scene.Texcoord(t, k) : Point2{}, s, 1.0f);
        face[k] = it->second;
      }
      mesh.faces.push_back(face);
    }
    if (!surface.planar) FinishCurvedVertices(scene, surfaces, surface, first, mesh);
  }
  return mesh;
}

std::vector<bool> SurfacesNamed(const Scene& scene, const SurfaceSet& surfaces, std::string_view patterns,
                                const char* option) {
  std::vector<std::string> globs;
  for (size_t start = 0; start <= patterns.size();) {
    const size_t end = std::min(patterns.find(',', start), patterns.size());
    if (end > start) globs.emplace_back(patterns.substr(start, end - start));
    start = end + 1;
  }
  const auto matches = [&](const std::string& name) {
    for (const std::string& glob : globs)
      if (!name.empty() && fnmatch(glob.c_str(), name.c_str(), 0) == 0) return true;
    return false;
  };
  std::vector<bool> keep(surfaces.surfaces.size(), false);
  bool any = false;
  for (size_t s = 0; s < keep.size(); ++s) {
    const Surface& surface = surfaces.surfaces[s];
    const uint32_t object = scene.triangles[surface.triangles.front()].object;
    keep[s] = (object < scene.objectNames.size() && matches(scene.objectNames[object])) ||
              matches(scene.materials[surface.material].name);
    any = any || keep[s];
  }
  if (!any)
    throw InputError(option, 0, fmt::format("'{}' names no object or material of the scene", patterns));
  return keep;
}

std::array<double, 2> BarycentricsIn(const Scene& scene, uint32_t t, const Point3d& p) {
  const Point3d a = ToPoint3d(scene.Corner(t, 0));
  const Point3d e1 = Minus(ToPoint3d(scene.Corner(t, 1)), a), e2 = Minus(ToPoint3d(scene.Corner(t, 2)), a);
  const Point3d d = Minus(p, a);
  const double d11 = Dot3(e1, e1), d12 = Dot3(e1, e2), d22 = Dot3(e2, e2), d1 = Dot3(d, e1), d2 = Dot3(d, e2);
  const double det = d11 * d22 - d12 * d12;
  return {(d22 * d1 - d12 * d2) / det, (d11 * d2 - d12 * d1) / det};
}

SurfacePointSampler::SurfacePointSampler(const Scene& scene, const SurfaceSet& surfaces, const SplitMesh& base)
    : scene_(scene), surfaces_(surfaces), base_(base), splitFace_(SplitFaceOfTriangle(scene, surfaces)) {
  for (const Surface& s : surfaces.surfaces) grids_.push_back(BuildChartGrid(surfaces, s));
}

SurfacePointSampler::ChartGrid SurfacePointSampler::BuildChartGrid(const SurfaceSet& surfaces, const Surface& surface) {
  ChartGrid g;
  for (uint32_t t : surface.triangles)
    for (const Point2& p : surfaces.cornerUv[t]) g.bounds.Extend(p);
  const double su = double(g.bounds.hi.u) - g.bounds.lo.u, sv = double(g.bounds.hi.v) - g.bounds.lo.v;
  const int perAxis = std::clamp(int(std::ceil(std::sqrt(double(surface.triangles.size())))), 1, 1024);
  g.cell = float(std::max({su, sv, 1e-30}) / perAxis);
  g.nu = std::clamp(int(su / g.cell) + 1, 1, perAxis + 1);
  g.nv = std::clamp(int(sv / g.cell) + 1, 1, perAxis + 1);
  const auto cellOf = [&](float c, float lo, int n) { return std::clamp(int(std::floor((c - lo) / g.cell)), 0, n - 1); };
  std::vector<std::vector<uint32_t>> cells(size_t(g.nu) * g.nv);
  for (uint32_t t : surface.triangles) {
    Bounds2 b;
    for (const Point2& p : surfaces.cornerUv[t]) b.Extend(p);
    for (int j = cellOf(b.lo.v, g.bounds.lo.v, g.nv); j <= cellOf(b.hi.v, g.bounds.lo.v, g.nv); ++j)
      for (int i = cellOf(b.lo.u, g.bounds.lo.u, g.nu); i <= cellOf(b.hi.u, g.bounds.lo.u, g.nu); ++i)
        cells[size_t(j) * g.nu + i].push_back(t);
  }
  g.start.push_back(0);
  for (const auto& c : cells) {
    g.triangles.insert(g.triangles.end(), c.begin(), c.end());
    g.start.push_back(uint32_t(g.triangles.size()));
  }
  return g;
}

std::optional<uint32_t> SurfacePointSampler::TriangleHolding(uint32_t surface, Point2 uv) const {
  const ChartGrid& g = grids_[surface];
  const float fu = (uv.u - g.bounds.lo.u) / g.cell, fv = (uv.v - g.bounds.lo.v) / g.cell;
  if (!(fu >= 0 && fv >= 0)) return std::nullopt;
  const int i = std::min(int(fu), g.nu - 1), j = std::min(int(fv), g.nv - 1);
  const size_t c = size_t(j) * g.nu + i;
  for (uint32_t k = g.start[c]; k < g.start[c + 1]; ++k)  // ascending: the first that holds uv, as a scan finds
    if (BarycentricsInChart(surfaces_.cornerUv[g.triangles[k]], uv).inside) return g.triangles[k];
  return std::nullopt;
}

SurfacePoint SurfacePointSampler::Interpolated(uint32_t surface, uint32_t triangle, const std::array<double, 2>& b) const {
  const Surface& s = surfaces_.surfaces[surface];
  SurfacePoint a;
  a.surface = surface;
  if (scene_.materials[s.material].albedoTexture >= 0)
    a.texcoord = Interpolate({scene_.Texcoord(triangle, 0), scene_.Texcoord(triangle, 1), scene_.Texcoord(triangle, 2)}, b);
  a.uv = Interpolate(surfaces_.cornerUv[triangle], b);
  if (s.planar) {
    a.normal = s.chart.frame.n;
    return a;
  }
  const auto& face = base_.faces[splitFace_[triangle]];
  a.normal = NormalFrom(Interpolate<Vector3>(
      {AsVector(base_.normals[face[0]]), AsVector(base_.normals[face[1]]), AsVector(base_.normals[face[2]])}, b));
  a.areaRatio = Interpolate<float>({base_.uvAreaRatio[face[0]], base_.uvAreaRatio[face[1]], base_.uvAreaRatio[face[2]]}, b);
  return a;
}

SurfacePoint SurfacePointSampler::At(uint32_t surface, uint32_t triangle, const Point3d& p) const {
  SurfacePoint a = Interpolated(surface, triangle, BarycentricsIn(scene_, triangle, p));
  a.position = {float(p[0]), float(p[1]), float(p[2])};
  const Surface& s = surfaces_.surfaces[surface];
  if (s.planar) a.uv = s.chart.ToUv(a.position);
  return a;
}

SurfacePoint SurfacePointSampler::AtChartPoint(uint32_t surface, Point2 uv) const {
  uint32_t best = surfaces_.surfaces[surface].triangles.front();
  Point2 nearest = uv;
  double bestDistance2 = INFINITY;
  if (const std::optional<uint32_t> holding = TriangleHolding(surface, uv)) best = *holding, bestDistance2 = 0;
  for (uint32_t t : surfaces_.surfaces[surface].triangles) {
    if (bestDistance2 == 0) break;
    const std::array<Point2, 3>& c = surfaces_.cornerUv[t];
    if (BarycentricsInChart(c, uv).inside) {
      best = t, nearest = uv, bestDistance2 = 0;
      break;
    }
    for (int k = 0; k < 3; ++k) {
      const Point2 q = NearestOnSegment(uv, c[k], c[(k + 1) % 3]);
      if (const double d2 = Distance2(q, uv); d2 < bestDistance2) best = t, nearest = q, bestDistance2 = d2;
    }
  }
  std::array<double, 2> b = BarycentricsInChart(surfaces_.cornerUv[best], nearest).b;
  b = {std::clamp(b[0], 0.0, 1.0), std::clamp(b[1], 0.0, 1.0 - std::clamp(b[0], 0.0, 1.0))};
  SurfacePoint a = Interpolated(surface, best, b);
  a.uv = nearest;
  a.position = scene_.PointAt(best, float(b[0]), float(b[1]));
  return a;
}

std::vector<double> VertexAreas(const SplitMesh& mesh) {
  std::vector<double> area(mesh.VertexCount(), 0.0);
  for (const auto& f : mesh.faces) {
    const double a = 0.5 * Length(Cross(mesh.positions[f[1]] - mesh.positions[f[0]], mesh.positions[f[2]] - mesh.positions[f[0]]));
    for (uint32_t v : f) area[v] += a / 3.0;
  }
  return area;
}

}  // namespace pb
