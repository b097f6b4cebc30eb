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

}  // namespace

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
        const SurfacePoint a = sampler.At(s, mesh.BaseTriangle(f), {p[0], p[1], p[2]});
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
