#include "estimators/emission.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "estimators/warps.h"
#include "mesh/errors.h"

namespace pb {

EmissionSample SampleEmission(const Scene& scene, const AreaLight& light, Rng& rng) {
  const auto pick = SampleDiscreteCdf(light.triangleCdf, rng.Uniform());
  PB_CHECK(pick.has_value(), "a light has at least one triangle");
  const uint32_t triangle = light.triangles[pick->index];
  const Barycentrics b = SampleUniformTriangle(rng.Uniform2());
  const Normal3 n = scene.FrontNormal(triangle);
  const DirectionSample d = SampleCosineHemisphere(rng.Uniform2());
  return {scene.PointAt(triangle, b.b1, b.b2), n, Frame::FromNormal(n).ToWorld(d.direction), triangle,
          float(1.0 / light.area), d.pdf};
}


std::vector<uint64_t> AllocatePhotons(const std::vector<AreaLight>& lights, uint64_t n,
                                      const std::vector<bool>& eligible) {
  std::vector<double> power(lights.size());
  for (size_t i = 0; i < lights.size(); ++i) power[i] = eligible.empty() || eligible[i] ? lights[i].Power().Mean() : 0.0;
  const double total = std::accumulate(power.begin(), power.end(), 0.0);
  std::vector<uint64_t> count(lights.size(), 0);
  if (!(total > 0)) return count;
  for (size_t i = 0; i < lights.size(); ++i) count[i] = uint64_t(std::floor(double(n) * (power[i] / total)));
  return count;
}

}  // namespace pb
