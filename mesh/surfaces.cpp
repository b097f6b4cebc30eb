#include "mesh/surfaces.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "mesh/errors.h"
#include "mesh/lscm.h"

namespace pb {
namespace {

float CosDegrees(float degrees) { return std::cos(degrees * kPi / 180.0f); }

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

uint64_t EdgeKey(uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); }

// For each triangle, the triangles that share one of its edges (after welding), ascending.
// The (edge, triangle) pairs are sorted rather than hashed into a map of vectors, whose allocations and cache
// misses grew faster than the triangles.
std::vector<std::vector<uint32_t>> EdgeNeighbours(const Scene& scene, const std::vector<uint32_t>& weld) {
  std::vector<std::pair<uint64_t, uint32_t>> edges;
  edges.reserve(3 * scene.triangles.size());
  for (uint32_t t = 0; t < scene.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      edges.push_back({EdgeKey(weld[scene.triangles[t].v[k]], weld[scene.triangles[t].v[(k + 1) % 3]]), t});
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<uint32_t>> neighbours(scene.triangles.size());
  for (size_t first = 0, end; first < edges.size(); first = end) {
    for (end = first; end < edges.size() && edges[end].first == edges[first].first;) ++end;
    for (size_t a = first; a < end; ++a)
      for (size_t b = first; b < end; ++b)
        if (edges[a].second != edges[b].second) neighbours[edges[a].second].push_back(edges[b].second);
  }
  for (auto& n : neighbours) std::sort(n.begin(), n.end());  // deterministic flood order.
  return neighbours;
}

// The triangles reachable from `seed` through `neighbours` for which `joins(from, to)` holds, ascending.
template <typename Joins>
std::vector<uint32_t> Flood(uint32_t seed, const std::vector<std::vector<uint32_t>>& neighbours,
                            std::vector<uint8_t>& taken, Joins&& joins) {
  std::vector<uint32_t> group, stack{seed};
  taken[seed] = 1;
  while (!stack.empty()) {
    const uint32_t t = stack.back();
    stack.pop_back();
    group.push_back(t);
    for (uint32_t n : neighbours[t])
      if (!taken[n] && joins(t, n)) taken[n] = 1, stack.push_back(n);
  }
  std::sort(group.begin(), group.end());
  return group;
}

// Whether the triangle's normal means anything: its corners are floats, each rounded by up to half an ulp of the
// largest coordinate, and a sliver's cross product can turn by more than `sinAngle` under that rounding (a fan of
// 40,000 triangles cut from one polygon has slivers whose rounding flips them over). Such a triangle follows its
// neighbours into their surface and does not vote on planarity.
bool NormalIsReliable(const Scene& scene, uint32_t t, float sinAngle) {
  const Point3 a = scene.Corner(t, 0), b = scene.Corner(t, 1), c = scene.Corner(t, 2);
  float largest = 0;
  for (const Point3& p : {a, b, c}) largest = std::max({largest, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  const float rounding = largest * 0x1p-24f;
  const float crossError = 4 * rounding * (Length(b - a) + Length(c - a) + Length(c - b));
  return crossError < sinAngle * Length(scene.AreaVector(t));
}

std::vector<std::vector<uint32_t>> SmoothGroups(const Scene& scene, const std::vector<std::vector<uint32_t>>& neighbours,
                                                const SurfaceOptions& o) {
  const float minCrease = CosDegrees(o.creaseDegrees), minCone = CosDegrees(o.coneDegrees);
  const float sinPlanar = std::sin(o.planarDegrees * kPi / 180.0f);
  std::vector<uint8_t> reliable(scene.triangles.size());
  for (uint32_t t = 0; t < scene.triangles.size(); ++t) reliable[t] = NormalIsReliable(scene, t, sinPlanar);
  std::vector<uint8_t> taken(scene.triangles.size(), 0);
  std::vector<std::vector<uint32_t>> groups;
  const auto grow = [&](uint32_t seed) {
    const Normal3 seedNormal = scene.FrontNormal(seed);
    groups.push_back(Flood(seed, neighbours, taken, [&](uint32_t from, uint32_t to) {
      if (scene.triangles[to].material != scene.triangles[seed].material) return false;
      if (!reliable[to]) return true;
      const Normal3 n = scene.FrontNormal(to);
      return Dot(n, reliable[from] ? scene.FrontNormal(from) : seedNormal) >= minCrease && Dot(n, seedNormal) >= minCone;
    }));
  };
  for (uint32_t seed = 0; seed < scene.triangles.size(); ++seed)  // groups grow from triangles with a normal
    if (!taken[seed] && reliable[seed]) grow(seed);
  for (uint32_t seed = 0; seed < scene.triangles.size(); ++seed)  // then slivers that no such group reached
    if (!taken[seed]) grow(seed);
  return groups;
}

Vector3 AreaVectorSum(const Scene& scene, const std::vector<uint32_t>& triangles) {
  Vector3 sum;
  for (uint32_t t : triangles) sum = sum + scene.AreaVector(t);
  return sum;
}

bool IsPlanar(const Scene& scene, const std::vector<uint32_t>& triangles, float planarDegrees) {
  // No mean normal: a closed group of slivers (a tiny box whose every triangle's normal rounding can turn) has
  // area vectors that sum to nothing, and no plane.
  const Vector3 sum = AreaVectorSum(scene, triangles);
  if (!(Length(sum) > 0) || !std::isfinite(Length(sum))) return false;
  const Normal3 mean = NormalFrom(sum);
  const float minCos = CosDegrees(planarDegrees), sinPlanar = std::sin(planarDegrees * kPi / 180.0f);
  return std::all_of(triangles.begin(), triangles.end(), [&](uint32_t t) {
    return !NormalIsReliable(scene, t, sinPlanar) || Dot(scene.FrontNormal(t), mean) >= minCos;
  });
}

Surface MakeSurface(const Scene& scene, std::vector<uint32_t> triangles) {
  Surface s;
  s.material = scene.triangles[triangles.front()].material;
  s.triangles = std::move(triangles);
  for (uint32_t t : s.triangles) s.area += scene.Area(t);
  s.chart = {scene.Corner(s.triangles.front(), 0), Frame::FromNormal(NormalFrom(AreaVectorSum(scene, s.triangles)))};
  return s;
}

// A curved group mapped by LSCM: per-triangle corner (u,v) and the worst area distortion; nothing if the group
// is not a disc or CGAL fails.
struct CurvedChart {
  std::vector<std::array<Point2, 3>> cornerUv;  // parallel to the group's triangles
  double areaDistortion = 1;
};

std::optional<CurvedChart> MapCurved(const Scene& scene, const std::vector<uint32_t>& weld,
                                     const std::vector<uint32_t>& triangles) {
  std::unordered_map<uint32_t, uint32_t> local;  // welded id -> patch vertex
  std::vector<Point3> positions;
  std::vector<std::array<uint32_t, 3>> faces;
  std::unordered_set<uint64_t> edges;
  for (uint32_t t : triangles) {
    std::array<uint32_t, 3> f{};
    for (int k = 0; k < 3; ++k) {
      const uint32_t w = weld[scene.triangles[t].v[k]];
      auto [it, isNew] = local.emplace(w, uint32_t(positions.size()));
      if (isNew) positions.push_back(scene.Corner(t, k));
      f[k] = it->second;
    }
    for (int k = 0; k < 3; ++k) edges.insert(EdgeKey(f[k], f[(k + 1) % 3]));
    faces.push_back(f);
  }
  if (int64_t(positions.size()) - int64_t(edges.size()) + int64_t(faces.size()) != 1) return std::nullopt;  // not a disc
  const auto uv = ConformalMap(positions, faces);
  if (!uv) return std::nullopt;
  CurvedChart chart;
  for (size_t i = 0; i < faces.size(); ++i) {
    const auto& f = faces[i];
    chart.cornerUv.push_back({(*uv)[f[0]], (*uv)[f[1]], (*uv)[f[2]]});
    const Point2 a = (*uv)[f[0]], b = (*uv)[f[1]], c = (*uv)[f[2]];
    const double uvArea = SignedArea(a, b, c);
    const double area = scene.Area(triangles[i]);
    if (!(uvArea > 0)) return std::nullopt;  // a folded triangle
    chart.areaDistortion = std::max({chart.areaDistortion, uvArea / area, area / uvArea});
  }
  return chart;
}

// Cuts a group at the median of its triangle centroids along their longest extent; returns its connected parts.
std::vector<std::vector<uint32_t>> Split(const Scene& scene, const std::vector<std::vector<uint32_t>>& neighbours,
                                         const std::vector<uint32_t>& triangles) {
  std::unordered_map<uint32_t, std::array<float, 3>> centroid;
  std::array<float, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (uint32_t t : triangles) {
    const Point3 a = scene.Corner(t, 0), b = scene.Corner(t, 1), c = scene.Corner(t, 2);
    const std::array<float, 3> m{(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3, (a.z + b.z + c.z) / 3};
    centroid[t] = m;
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], m[k]), hi[k] = std::max(hi[k], m[k]);
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
  std::vector<uint32_t> order = triangles;
  const auto less = [&](uint32_t x, uint32_t y) {
    const float cx = centroid.at(x)[axis], cy = centroid.at(y)[axis];
    return cx < cy || (cx == cy && x < y);
  };
  std::nth_element(order.begin(), order.begin() + order.size() / 2, order.end(), less);
  std::unordered_map<uint32_t, uint8_t> half;  // triangle -> 0 or 1
  for (size_t i = 0; i < order.size(); ++i) half[order[i]] = i < order.size() / 2 ? 0 : 1;

  std::vector<uint8_t> taken(scene.triangles.size(), 1);
  for (uint32_t t : triangles) taken[t] = 0;
  std::vector<std::vector<uint32_t>> parts;
  for (uint32_t t : triangles)
    if (!taken[t]) parts.push_back(Flood(t, neighbours, taken, [&](uint32_t from, uint32_t to) { return half.at(from) == half.at(to); }));
  return parts;
}

}  // namespace

size_t SurfaceSet::CurvedCount() const {
  return size_t(std::count_if(surfaces.begin(), surfaces.end(), [](const Surface& s) { return !s.planar; }));
}

double SurfaceSet::WorstAreaDistortion() const {
  double worst = 1;
  for (const Surface& s : surfaces) worst = std::max(worst, s.areaDistortion);
  return worst;
}

SurfaceSet BuildSurfaces(const Scene& scene, const SurfaceOptions& options, const WorkProgress& placed) {
  const uint64_t passes = 2 * uint64_t(scene.triangles.size());
  if (placed) placed(0, passes);  // the clock starts
  const std::vector<uint32_t> weld = WeldedPositionIds(scene);
  const auto neighbours = EdgeNeighbours(scene, weld);
  SurfaceSet set;
  set.surfaceOfTriangle.assign(scene.triangles.size(), 0);
  set.cornerUv.resize(scene.triangles.size());
  std::deque<std::vector<uint32_t>> pending;
  for (auto& g : SmoothGroups(scene, neighbours, options)) pending.push_back(std::move(g));
  if (placed) placed(scene.triangles.size(), passes);
  while (!pending.empty()) {
    std::vector<uint32_t> group = std::move(pending.front());
    pending.pop_front();
    const uint32_t id = uint32_t(set.surfaces.size());
    if (group.size() == 1 || IsPlanar(scene, group, options.planarDegrees)) {  // Split cannot cut one triangle
      Surface s = MakeSurface(scene, std::move(group));
      for (uint32_t t : s.triangles)
        for (int k = 0; k < 3; ++k) set.cornerUv[t][k] = s.chart.ToUv(scene.Corner(t, k));
      for (uint32_t t : s.triangles) set.surfaceOfTriangle[t] = id;
      if (placed) placed(s.triangles.size(), passes);
      set.surfaces.push_back(std::move(s));
      continue;
    }
    const std::optional<CurvedChart> chart = MapCurved(scene, weld, group);
    if (!chart || chart->areaDistortion > options.maxAreaDistortion) {
      auto parts = Split(scene, neighbours, group);
      for (auto it = parts.rbegin(); it != parts.rend(); ++it) pending.push_front(std::move(*it));
      continue;
    }
    for (size_t i = 0; i < group.size(); ++i) set.cornerUv[group[i]] = chart->cornerUv[i], set.surfaceOfTriangle[group[i]] = id;
    Surface s = MakeSurface(scene, std::move(group));
    s.planar = false;
    s.areaDistortion = chart->areaDistortion;
    if (placed) placed(s.triangles.size(), passes);
    set.surfaces.push_back(std::move(s));
  }
  return set;
}

}  // namespace pb
