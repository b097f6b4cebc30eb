#include "mesh/split_mesh.h"

#include <cmath>
#include <unordered_map>

namespace pb {
namespace {

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

SplitMesh SplitBySurface(const Scene& scene, const SurfaceSet& surfaces) {
  SplitMesh mesh;
  mesh.origin = scene.origin;
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
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

}  // namespace pb
