#include "baker/3_surface_point.h"

#include <bit>
#include <cmath>

namespace pb {

Rng PointStream(uint64_t seed, const SurfacePoint& p) {
  const auto bits = [](float f) { return uint64_t(std::bit_cast<uint32_t>(f == 0.0f ? 0.0f : f)); };
  return Rng(seed, SplitMix64((uint64_t(p.surface) << 32) ^ bits(p.uv.u)) ^ bits(p.uv.v));
}

// On a planar surface a point within 10 steps of its region's boundary steps once inward, along the region's
// kernel centroid about it (SurfaceRegion::Moments). A step is kStepPerSpawnOffset of the rays' spawn offset, which
// is relative to the scene's size (mesh/ray_scene.h): 0.2 mm on the box, and the same share of a scene 1 mm or 1 km
// across (an absolute 0.2 mm had moved the points of a 4 mm floor 5% of the way in, and read its edges 39% high).
namespace {
constexpr double kStepPerSpawnOffset = 20, kProbeSteps = 10;
}  // namespace

SurfacePoint RayStart(const PreparedScene& scene, const SurfacePoint& p) {
  const Surface& surface = scene.surfaces.surfaces[p.surface];
  if (!surface.planar) return p;
  const double step = kStepPerSpawnOffset * scene.rays->SpawnOffset();
  const KernelMomentsAt m = scene.regions[p.surface]->Moments(p.uv, Kernel::kUniform, kProbeSteps * step);
  const double length = std::hypot(m.first[0], m.first[1]);
  if (!(length > 0)) return p;
  const float du = float(step * m.first[0] / length), dv = float(step * m.first[1] / length);
  SurfacePoint start = p;
  start.position = p.position + surface.chart.frame.s * du + surface.chart.frame.t * dv;
  start.uv = {p.uv.u + du, p.uv.v + dv};
  return start;
}

}  // namespace pb
