#include "mesh/split_mesh.h"

#include <unordered_map>

namespace pb {

SplitMesh SplitBySurface(const Scene& scene, const SurfaceSet& surfaces) {
  SplitMesh mesh;
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
    const Surface& surface = surfaces.surfaces[s];
    std::unordered_map<uint32_t, uint32_t> splitIndexOf;  // scene position index -> this surface's copy
    for (uint32_t t : surface.triangles) {
      std::array<uint32_t, 3> face{};
      for (int k = 0; k < 3; ++k) {
        const uint32_t original = scene.triangles[t].v[k];
        auto [it, isNew] = splitIndexOf.emplace(original, uint32_t(mesh.positions.size()));
        if (isNew) {
          mesh.positions.push_back(scene.positions[original]);
          mesh.normals.push_back(surface.chart.frame.n);
          mesh.uv.push_back(surfaces.cornerUv[t][k]);
          mesh.surface.push_back(s);
        }
        face[k] = it->second;
      }
      mesh.faces.push_back(face);
    }
  }
  return mesh;
}

}  // namespace pb
