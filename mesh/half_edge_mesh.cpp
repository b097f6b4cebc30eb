#include "mesh/half_edge_mesh.h"

#include <cmath>
#include <cstring>
#include <map>
#include <unordered_map>

namespace pb {
namespace {

using Vec3d = OpenMesh::Vec3d;

Vec3d ToVec(Point3 p) { return {p.x, p.y, p.z}; }

// Welds scene positions by exact coordinates, so that surfaces whose OBJ vertices are separate copies still
// share their edges.
std::vector<HalfEdgeMesh::VertexHandle> WeldedVertices(const Scene& scene, HalfEdgeMesh& mesh) {
  std::map<std::array<float, 3>, HalfEdgeMesh::VertexHandle> byPosition;
  std::vector<HalfEdgeMesh::VertexHandle> handles(scene.positions.size());
  for (size_t i = 0; i < scene.positions.size(); ++i) {
    const Point3 p = scene.positions[i];
    auto [it, isNew] = byPosition.emplace(std::array<float, 3>{p.x, p.y, p.z}, HalfEdgeMesh::VertexHandle());
    if (isNew) it->second = mesh.add_vertex(ToVec(p));
    handles[i] = it->second;
  }
  return handles;
}

// The corner values of the base split mesh, by scene triangle: SplitBySurface orders its faces by surface,
// then by the surface's (ascending) triangles.
std::vector<uint32_t> SplitFaceOfTriangle(const Scene& scene, const SurfaceSet& surfaces) {
  std::vector<uint32_t> face(scene.triangles.size());
  uint32_t next = 0;
  for (const Surface& s : surfaces.surfaces)
    for (uint32_t t : s.triangles) face[t] = next++;
  return face;
}

template <typename T>
T Interpolate(const std::array<T, 3>& c, const std::array<double, 2>& b) {
  const double b0 = 1 - b[0] - b[1];
  return c[0] * float(b0) + c[1] * float(b[0]) + c[2] * float(b[1]);
}
Point2 Interpolate(const std::array<Point2, 3>& c, const std::array<double, 2>& b) {
  const double b0 = 1 - b[0] - b[1];
  return {float(b0 * c[0].u + b[0] * c[1].u + b[1] * c[2].u), float(b0 * c[0].v + b[0] * c[1].v + b[1] * c[2].v)};
}

}  // namespace

SurfacePointSampler::SurfacePointSampler(const Scene& scene, const SurfaceSet& surfaces, const SplitMesh& base)
    : scene_(scene), surfaces_(surfaces), base_(base), splitFace_(SplitFaceOfTriangle(scene, surfaces)) {}

SurfacePoint SurfacePointSampler::At(uint32_t surface, uint32_t triangle, const Vec3d& p) const {
  const Surface& s = surfaces_.surfaces[surface];
  SurfacePoint a;
  const std::array<double, 2> b = BarycentricsIn(scene_, triangle, p);
  if (scene_.materials[s.material].albedoTexture >= 0)
    a.texcoord = Interpolate({scene_.Texcoord(triangle, 0), scene_.Texcoord(triangle, 1), scene_.Texcoord(triangle, 2)}, b);
  if (s.planar) {
    a.uv = s.chart.ToUv({float(p[0]), float(p[1]), float(p[2])});
    a.normal = s.chart.frame.n;
    return a;
  }
  const auto& face = base_.faces[splitFace_[triangle]];
  a.uv = Interpolate(surfaces_.cornerUv[triangle], b);
  a.normal = NormalFrom(Interpolate<Vector3>(
      {AsVector(base_.normals[face[0]]), AsVector(base_.normals[face[1]]), AsVector(base_.normals[face[2]])}, b));
  a.areaRatio = Interpolate<float>({base_.uvAreaRatio[face[0]], base_.uvAreaRatio[face[1]], base_.uvAreaRatio[face[2]]}, b);
  return a;
}

HalfEdgeMesh::HalfEdgeMesh() {
  add_property(surface_, "pb:surface");
  add_property(base_, "pb:base_triangle");
}

std::array<HalfEdgeMesh::VertexHandle, 3> HalfEdgeMesh::CornerVertices(FaceHandle f) const {
  auto it = cfv_begin(f);
  const VertexHandle a = *it, b = *++it, c = *++it;
  return {a, b, c};
}

std::array<Vec3d, 3> HalfEdgeMesh::Corners(FaceHandle f) const {
  const auto v = CornerVertices(f);
  return {point(v[0]), point(v[1]), point(v[2])};
}

Vec3d HalfEdgeMesh::FaceNormal(FaceHandle f) const {
  const auto p = Corners(f);
  const Vec3d n = OpenMesh::cross(p[1] - p[0], p[2] - p[0]);
  const double length = n.norm();
  return length > 0 ? n / length : Vec3d(0, 0, 0);
}

double HalfEdgeMesh::FaceArea(FaceHandle f) const {
  const auto p = Corners(f);
  return 0.5 * OpenMesh::cross(p[1] - p[0], p[2] - p[0]).norm();
}

std::array<double, 2> BarycentricsIn(const Scene& scene, uint32_t t, const Vec3d& p) {
  const Vec3d a = ToVec(scene.Corner(t, 0)), e1 = ToVec(scene.Corner(t, 1)) - a, e2 = ToVec(scene.Corner(t, 2)) - a;
  const Vec3d d = p - a;
  const double d11 = e1 | e1, d12 = e1 | e2, d22 = e2 | e2, d1 = d | e1, d2 = d | e2;
  const double det = d11 * d22 - d12 * d12;
  return {(d22 * d1 - d12 * d2) / det, (d11 * d2 - d12 * d1) / det};
}

HalfEdgeMesh BuildHalfEdgeMesh(const Scene& scene, const SurfaceSet& surfaces) {
  HalfEdgeMesh mesh;
  const std::vector<HalfEdgeMesh::VertexHandle> welded = WeldedVertices(scene, mesh);
  for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
    const auto& v = scene.triangles[t].v;
    HalfEdgeMesh::FaceHandle f = mesh.add_face(welded[v[0]], welded[v[1]], welded[v[2]]);
    if (!f.is_valid()) {  // a non-manifold edge: this face gets vertices of its own
      f = mesh.add_face(mesh.add_vertex(mesh.point(welded[v[0]])), mesh.add_vertex(mesh.point(welded[v[1]])),
                        mesh.add_vertex(mesh.point(welded[v[2]])));
      ++mesh.detachedFaces;
    }
    mesh.SetFace(f, surfaces.surfaceOfTriangle[t], t);
  }
  return mesh;
}

SplitMesh ToSplitMesh(const HalfEdgeMesh& mesh, const Scene& scene, const SurfaceSet& surfaces,
                      const SplitMesh& base) {
  const SurfacePointSampler sampler(scene, surfaces, base);
  std::vector<std::vector<HalfEdgeMesh::FaceHandle>> facesOf(surfaces.surfaces.size());
  for (auto f : mesh.faces()) facesOf[mesh.Surface(f)].push_back(f);
  SplitMesh out;
  out.origin = scene.origin;
  for (uint32_t s = 0; s < facesOf.size(); ++s) {
    // (mesh vertex, texture coordinates) -> this surface's copy: textured surfaces split at texture seams.
    std::unordered_map<uint64_t, std::unordered_map<uint64_t, uint32_t>> copyOf;
    for (auto f : facesOf[s]) {
      std::array<uint32_t, 3> face{};
      const auto corners = mesh.CornerVertices(f);
      for (int k = 0; k < 3; ++k) {
        const Vec3d& p = mesh.point(corners[k]);
        const SurfacePoint a = sampler.At(s, mesh.BaseTriangle(f), p);
        uint64_t texKey = 0;
        std::memcpy(&texKey, &a.texcoord, sizeof texKey);
        auto [it, isNew] = copyOf[corners[k].idx()].emplace(texKey, uint32_t(out.positions.size()));
        if (isNew) out.AddVertex({float(p[0]), float(p[1]), float(p[2])}, a.normal, a.uv, a.texcoord, s, a.areaRatio);
        face[k] = it->second;
      }
      out.faces.push_back(face);
    }
  }
  return out;
}

}  // namespace pb
