// Decimation that leaves the geometry exactly as it was: halfedge collapses (OpenMesh's Decimater) restricted by
// ModExactGeometryT to those that keep every face in its plane and the mesh's outline, surface boundaries and
// creases where they were. A collapse moves vertex v0 onto its neighbour v1 and is legal only when
//   - v0 is on no feature edge (an open boundary, an edge between two surfaces, or a crease: an edge whose two
//     faces do not lie in one plane) and all its faces lie in one plane; or v0 is on exactly two feature edges,
//     to neighbours a and v1, with a, v0 and v1 on one line (v0 slides along a straight feature line);
//   - v1 lies in the plane of every face that survives around v0, and none of them flips or degenerates.
// Vertices on curved or textured surfaces are locked (their faces must stay inside their base triangles; see
// mesh/half_edge_mesh.h). What may be removed is the caller's to decide, with one priority module (the
// irradiance error of baker/4_refine_mesh.h): this is the coarsening step of Walter et al. 1997, "Global
// illumination using local linear density estimation", which simplifies a mesh where the light is flat.
#pragma once

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModBaseT.hh>

#include <vector>

#include "mesh/half_edge_mesh.h"

namespace pb {

// Relative tolerance of the plane and line tests, times the length of the edges involved.
inline constexpr double kGeometryTolerance = 1e-9;

// Whether collapsing v0 -> v1 keeps the geometry exactly (see above). Locking is the Decimater's to check.
bool CollapseKeepsGeometry(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle v0v1);

template <typename MeshT>
class ModExactGeometryT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModExactGeometryT, MeshT, ExactGeometry);
  explicit ModExactGeometryT(MeshT& mesh) : Base(mesh, true) {}
  float collapse_priority(const CollapseInfo& ci) override {
    return CollapseKeepsGeometry(ci.mesh, ci.v0v1) ? Base::LEGAL_COLLAPSE : Base::ILLEGAL_COLLAPSE;
  }
};

// Locks every vertex that touches a face of a surface with lockedSurface[s] set.
void LockSurfaces(HalfEdgeMesh& mesh, const std::vector<bool>& lockedSurface);

}  // namespace pb
