// Area lights as plain data. A light is one emissive surface: radiance Ke [W/(m^2 sr)] leaving its front side
// with a cosine distribution, area A [m^2], flux Phi = pi * Ke * A [W]. The triangle CDF (by area) lets
// estimators/emission.h pick a point uniformly over the light's area (pdf 1/A per unit area).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/color.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

struct AreaLight {
  uint32_t surface = 0;
  Rgb radiance;                     // Ke [W/(m^2 sr)]
  std::vector<uint32_t> triangles;  // Scene::triangles indices
  std::vector<double> triangleCdf;  // cumulative area fraction; back() == 1
  double area = 0;                  // [m^2]
  Rgb Power() const { return radiance * float(kPi * area); }  // Phi [W]
};

// The name of the light's material, for messages and reports.
inline const std::string& MaterialName(const Scene& scene, const AreaLight& light) {
  return scene.materials[scene.triangles[light.triangles.front()].material].name;
}

// One light per surface whose material has Ke > 0, in surface order.
std::vector<AreaLight> CollectLights(const Scene& scene, const SurfaceSet& surfaces);

}  // namespace pb
