#include "mesh/lights.h"

namespace pb {

std::vector<AreaLight> CollectLights(const Scene& scene, const SurfaceSet& surfaces) {
  std::vector<AreaLight> lights;
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
    const Surface& surface = surfaces.surfaces[s];
    const Material& material = scene.materials[surface.material];
    if (!material.IsEmissive()) continue;
    AreaLight light{s, material.emission, surface.triangles, {}, 0.0};
    for (uint32_t t : light.triangles) {
      light.area += scene.Area(t);
      light.triangleCdf.push_back(light.area);
    }
    for (double& c : light.triangleCdf) c /= light.area;
    light.triangleCdf.back() = 1.0;
    lights.push_back(std::move(light));
  }
  return lights;
}

}  // namespace pb
