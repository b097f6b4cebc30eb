// The scene's triangles as one OpenMesh half-edge mesh, for refinement and decimation (mesh/refine.h,
// mesh/decimate.h, mesh/subdivide.h). Positions are local [m] in double precision, welded by exact
// coordinates, so an edge shared by two surfaces (the floor and a wall) is one edge: splitting it splits both
// sides, and the mesh stays free of T-junctions wherever the input was watertight.
//
// Every face remembers the surface it belongs to (mesh/surfaces.h) and the scene triangle that contains it (its
// "base" triangle): refinement only ever splits faces, so each face lies inside one base triangle, and a point
// of the face has barycentrics in it. The base triangle gives curved surfaces their chart (u,v) and textured
// ones their texture coordinates. Decimation moves faces off their base triangle, so it never touches a vertex
// of a curved or textured surface.
//
// ToSplitMesh turns the result back into the display mesh the estimator and the PLY writer take
// (mesh/split_mesh.h): split where surfaces (and texture seams) meet, with each corner's chart (u,v), texture
// coordinates, normal and area ratio taken from its base triangle.
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <array>
#include <cstdint>

#include "mesh/scene.h"
#include "mesh/split_mesh.h"
#include "mesh/surfaces.h"

namespace pb {

struct HalfEdgeTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  // Status flags: deletion and locking, which the Decimater needs.
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
};
using HalfEdgeKernel = OpenMesh::TriMesh_ArrayKernelT<HalfEdgeTraits>;

class HalfEdgeMesh : public HalfEdgeKernel {
 public:
  HalfEdgeMesh();  // copies keep the face properties: their handles are the same indices

  uint32_t Surface(FaceHandle f) const { return property(surface_, f); }
  uint32_t BaseTriangle(FaceHandle f) const { return property(base_, f); }
  void SetFace(FaceHandle f, uint32_t surface, uint32_t baseTriangle) {
    property(surface_, f) = surface;
    property(base_, f) = baseTriangle;
  }
  // Unit normal of a face's plane (double precision; not stored, since faces change as the mesh is edited).
  OpenMesh::Vec3d FaceNormal(FaceHandle f) const;
  double FaceArea(FaceHandle f) const;
  std::array<OpenMesh::Vec3d, 3> Corners(FaceHandle f) const;
  std::array<VertexHandle, 3> CornerVertices(FaceHandle f) const;
  // Faces whose input edges were not manifold, and so were added with vertices of their own.
  size_t detachedFaces = 0;

 private:
  OpenMesh::FPropHandleT<uint32_t> surface_, base_;
};

// The scene's triangles, welded by exact position. A face that OpenMesh cannot add without making an edge
// non-manifold (three triangles on one edge) is added with its own copies of its vertices.
HalfEdgeMesh BuildHalfEdgeMesh(const Scene& scene, const SurfaceSet& surfaces);

// The display mesh of `mesh` (deleted elements skipped), each corner sampled by SurfacePointSampler (mesh/split_mesh.h). Vertices are ordered by surface, then by first use; faces by surface, then by index in `mesh`.
SplitMesh ToSplitMesh(const HalfEdgeMesh& mesh, const Scene& scene, const SurfaceSet& surfaces,
                      const SplitMesh& base);

}  // namespace pb
