#include "mesh/decimate.h"

#include <cmath>

namespace pb {
namespace {

using Vec3d = OpenMesh::Vec3d;
using HalfedgeHandle = HalfEdgeMesh::HalfedgeHandle;
using VertexHandle = HalfEdgeMesh::VertexHandle;

bool InPlane(const HalfEdgeMesh& mesh, HalfEdgeMesh::FaceHandle f, const Vec3d& p) {
  const auto c = mesh.Corners(f);
  const double scale = std::max({(c[1] - c[0]).norm(), (c[2] - c[0]).norm(), (p - c[0]).norm()});
  return std::fabs((p - c[0]) | mesh.FaceNormal(f)) <= kGeometryTolerance * scale;
}

// A feature edge bounds what a collapse may not move: the outline, a surface boundary or a crease.
bool IsFeature(const HalfEdgeMesh& mesh, HalfEdgeMesh::EdgeHandle e) {
  if (mesh.is_boundary(e)) return true;
  const auto h = mesh.halfedge_handle(e, 0);
  const auto f = mesh.face_handle(h), g = mesh.face_handle(mesh.opposite_halfedge_handle(h));
  if (mesh.Surface(f) != mesh.Surface(g)) return true;
  return !InPlane(mesh, f, mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(h)))));
}

// p lies on the segment from a to b.
bool OnSegment(const Vec3d& a, const Vec3d& p, const Vec3d& b) {
  const Vec3d ab = b - a;
  const double t = ((p - a) | ab) / ab.sqrnorm();
  return t > 0 && t < 1 && (a + t * ab - p).norm() <= kGeometryTolerance * ab.norm();
}

// v0 slides along a straight feature line onto v1, or sits inside one plane.
bool FeaturesAllow(const HalfEdgeMesh& mesh, HalfedgeHandle v0v1) {
  const VertexHandle v0 = mesh.from_vertex_handle(v0v1), v1 = mesh.to_vertex_handle(v0v1);
  std::vector<VertexHandle> featureNeighbours;
  for (HalfedgeHandle h : mesh.voh_range(v0))
    if (IsFeature(mesh, mesh.edge_handle(h))) featureNeighbours.push_back(mesh.to_vertex_handle(h));
  if (featureNeighbours.empty()) return true;
  if (featureNeighbours.size() != 2) return false;
  const VertexHandle other = featureNeighbours[0] == v1 ? featureNeighbours[1] : featureNeighbours[0];
  if (featureNeighbours[0] != v1 && featureNeighbours[1] != v1) return false;
  return OnSegment(mesh.point(other), mesh.point(v0), mesh.point(v1));
}

// Every face around v0 that survives keeps its plane and its orientation once v0 sits at v1.
bool FacesKeepTheirPlanes(const HalfEdgeMesh& mesh, HalfedgeHandle v0v1) {
  const VertexHandle v0 = mesh.from_vertex_handle(v0v1), v1 = mesh.to_vertex_handle(v0v1);
  const Vec3d p1 = mesh.point(v1);
  for (auto f : mesh.vf_range(v0)) {
    const auto corners = mesh.CornerVertices(f);
    if (corners[0] == v1 || corners[1] == v1 || corners[2] == v1) continue;  // removed by the collapse
    if (!InPlane(mesh, f, p1)) return false;
    std::array<Vec3d, 3> moved = mesh.Corners(f);
    for (int k = 0; k < 3; ++k)
      if (corners[k] == v0) moved[k] = p1;
    const Vec3d n = OpenMesh::cross(moved[1] - moved[0], moved[2] - moved[0]);
    if ((n | mesh.FaceNormal(f)) <= kGeometryTolerance * n.norm() || n.norm() == 0) return false;
  }
  return true;
}

}  // namespace

bool CollapseKeepsGeometry(const HalfEdgeMesh& mesh, HalfedgeHandle v0v1) {
  return FeaturesAllow(mesh, v0v1) && FacesKeepTheirPlanes(mesh, v0v1);
}

void LockSurfaces(HalfEdgeMesh& mesh, const std::vector<bool>& lockedSurface) {
  for (auto f : mesh.faces())
    if (lockedSurface[mesh.Surface(f)])
      for (auto v : mesh.fv_range(f)) mesh.status(v).set_locked(true);
}

}  // namespace pb
