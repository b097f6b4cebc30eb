#include "mesh/subdivide.h"

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <memory>
#include <vector>

namespace pb {
namespace {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

// A position in the form OpenSubdiv's primvar interpolation asks for.
struct VaryingPoint {
  OpenMesh::Vec3d p{0, 0, 0};
  void Clear() { p = {0, 0, 0}; }
  void AddWithWeight(const VaryingPoint& src, float weight) { p += double(weight) * src.p; }
};

struct FaceData {
  uint32_t surface = 0, base = 0;
};

std::unique_ptr<Far::TopologyRefiner> RefinerOf(const HalfEdgeMesh& mesh, int levels) {
  std::vector<int> vertsPerFace(mesh.n_faces(), 3);
  std::vector<Far::Index> indices;
  indices.reserve(3 * mesh.n_faces());
  for (auto f : mesh.faces())
    for (auto v : mesh.CornerVertices(f)) indices.push_back(v.idx());
  Far::TopologyDescriptor descriptor;
  descriptor.numVertices = int(mesh.n_vertices());
  descriptor.numFaces = int(mesh.n_faces());
  descriptor.numVertsPerFace = vertsPerFace.data();
  descriptor.vertIndicesPerFace = indices.data();
  // Loop: the scheme whose topology splits a triangle into four triangles. Its smoothing weights are never used.
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(descriptor, Factory::Options(Sdc::SCHEME_LOOP)));
  refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
  return refiner;
}

}  // namespace

HalfEdgeMesh SubdivideUniform(const HalfEdgeMesh& mesh, int levels, const std::function<void(uint64_t faces)>& built) {
  if (levels <= 0) return mesh;
  const std::unique_ptr<Far::TopologyRefiner> refiner = RefinerOf(mesh, levels);
  std::vector<VaryingPoint> points(refiner->GetNumVerticesTotal());
  std::vector<FaceData> faces(refiner->GetNumFacesTotal());
  for (auto v : mesh.vertices()) points[v.idx()].p = mesh.point(v);
  for (auto f : mesh.faces()) faces[f.idx()] = {mesh.Surface(f), mesh.BaseTriangle(f)};
  // Level by level: each level's values follow the previous level's in one buffer.
  const Far::PrimvarRefiner primvars(*refiner);
  VaryingPoint* pointSrc = points.data();
  FaceData* faceSrc = faces.data();
  for (int level = 1; level <= levels; ++level) {
    VaryingPoint* pointDst = pointSrc + refiner->GetLevel(level - 1).GetNumVertices();
    FaceData* faceDst = faceSrc + refiner->GetLevel(level - 1).GetNumFaces();
    primvars.InterpolateVarying(level, pointSrc, pointDst);
    primvars.InterpolateFaceUniform(level, faceSrc, faceDst);
    pointSrc = pointDst, faceSrc = faceDst;
  }

  const Far::TopologyLevel& finest = refiner->GetLevel(levels);
  HalfEdgeMesh out;
  out.detachedFaces = mesh.detachedFaces;
  std::vector<HalfEdgeMesh::VertexHandle> handles(finest.GetNumVertices());
  for (int v = 0; v < finest.GetNumVertices(); ++v) handles[v] = out.add_vertex(pointSrc[v].p);
  for (int f = 0; f < finest.GetNumFaces(); ++f) {
    const Far::ConstIndexArray corners = finest.GetFaceVertices(f);
    const auto face = out.add_face(handles[corners[0]], handles[corners[1]], handles[corners[2]]);
    out.SetFace(face, faceSrc[f].surface, faceSrc[f].base);
    if (built && (f + 1) % 65536 == 0) built(65536);
  }
  if (built) built(uint64_t(finest.GetNumFaces()) % 65536);
  return out;
}

}  // namespace pb
