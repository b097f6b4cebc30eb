#include "mesh/surfaces.h"

#include <cmath>
#include <cstring>
#include <unordered_map>

#include "mesh/errors.h"

namespace pb {
namespace {

// Position indices welded by exact coordinates, so that files with one vertex per face corner still connect.
std::vector<uint32_t> WeldedPositionIds(const Scene& scene) {
  struct Key {
    uint32_t bits[3];
    bool operator==(const Key& o) const { return std::memcmp(bits, o.bits, sizeof bits) == 0; }
  };
  struct Hash {
    size_t operator()(const Key& k) const {
      return (size_t(k.bits[0]) * 73856093u) ^ (size_t(k.bits[1]) * 19349663u) ^ (size_t(k.bits[2]) * 83492791u);
    }
  };
  std::unordered_map<Key, uint32_t, Hash> idOf;
  std::vector<uint32_t> ids(scene.positions.size());
  for (size_t i = 0; i < scene.positions.size(); ++i) {
    const Point3 p = scene.positions[i];
    Key key{};
    const float c[3] = {p.x + 0.0f, p.y + 0.0f, p.z + 0.0f};  // + 0.0f maps -0 to +0.
    std::memcpy(key.bits, c, sizeof c);
    ids[i] = idOf.emplace(key, uint32_t(idOf.size())).first->second;
  }
  return ids;
}

// For each triangle, the triangles that share one of its edges (after welding).
std::vector<std::vector<uint32_t>> EdgeNeighbours(const Scene& scene) {
  const std::vector<uint32_t> weld = WeldedPositionIds(scene);
  std::unordered_map<uint64_t, std::vector<uint32_t>> trianglesOfEdge;
  for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = weld[scene.triangles[t].v[k]], b = weld[scene.triangles[t].v[(k + 1) % 3]];
      trianglesOfEdge[(uint64_t(std::min(a, b)) << 32) | std::max(a, b)].push_back(t);
    }
  }
  std::vector<std::vector<uint32_t>> neighbours(scene.triangles.size());
  for (const auto& [edge, tris] : trianglesOfEdge)
    for (uint32_t a : tris)
      for (uint32_t b : tris)
        if (a != b) neighbours[a].push_back(b);
  for (auto& n : neighbours) std::sort(n.begin(), n.end());  // deterministic flood order.
  return neighbours;
}

SurfaceChart ChartFor(const Scene& scene, const Surface& surface) {
  Vector3 areaSum;
  for (uint32_t t : surface.triangles) areaSum = areaSum + scene.AreaVector(t);
  return {scene.Corner(surface.triangles.front(), 0), Frame::FromNormal(NormalFrom(areaSum))};
}

}  // namespace

SurfaceSet BuildSurfaces(const Scene& scene, float maxNormalAngleDegrees) {
  const float minCos = std::cos(maxNormalAngleDegrees * kPi / 180.0f);
  const auto neighbours = EdgeNeighbours(scene);
  constexpr uint32_t kUnassigned = ~0u;
  SurfaceSet set;
  set.surfaceOfTriangle.assign(scene.triangles.size(), kUnassigned);
  for (uint32_t seed = 0; seed < scene.triangles.size(); ++seed) {
    if (set.surfaceOfTriangle[seed] != kUnassigned) continue;
    const uint32_t id = uint32_t(set.surfaces.size());
    const Normal3 seedNormal = scene.FrontNormal(seed);
    Surface surface;
    surface.material = scene.triangles[seed].material;
    std::vector<uint32_t> stack{seed};
    set.surfaceOfTriangle[seed] = id;
    while (!stack.empty()) {
      const uint32_t t = stack.back();
      stack.pop_back();
      surface.triangles.push_back(t);
      for (uint32_t n : neighbours[t]) {
        if (set.surfaceOfTriangle[n] != kUnassigned || scene.triangles[n].material != surface.material) continue;
        if (Dot(scene.FrontNormal(n), seedNormal) < minCos) continue;
        set.surfaceOfTriangle[n] = id;
        stack.push_back(n);
      }
    }
    std::sort(surface.triangles.begin(), surface.triangles.end());
    for (uint32_t t : surface.triangles) surface.area += scene.Area(t);
    surface.chart = ChartFor(scene, surface);
    set.surfaces.push_back(std::move(surface));
  }
  set.cornerUv.resize(scene.triangles.size());
  for (uint32_t t = 0; t < scene.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) set.cornerUv[t][k] = set.surfaces[set.surfaceOfTriangle[t]].chart.ToUv(scene.Corner(t, k));
  return set;
}

}  // namespace pb
