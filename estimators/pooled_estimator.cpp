#include "estimators/pooled_estimator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "estimators/warps.h"
#include "mesh/octahedral.h"

namespace pb {

namespace {
// Triangles smaller than an area sample, gathered per lattice cell and orientation octant.
struct Gathered {
  double area = 0;
  double position[3] = {0, 0, 0};  // area-weighted sums
  Vector3 normal{0, 0, 0};
};

// Normals gathered together: an 8 x 8 grid on the octahedral map (mesh/octahedral.h), cells of about 25 degrees.
int64_t NormalBin(Normal3 n) {
  const uint32_t bits = EncodeOctahedral(AsVector(n));
  const auto cell = [](uint32_t snorm) { return std::min<int64_t>(7, int64_t(snorm & 0xFFFFu) * 8 / 65535); };
  return cell(bits) * 8 + cell(bits >> 16);
}

// Points spread over triangle t, `count` of them, each standing for an equal share of its area.
void SpreadOver(const Scene& scene, uint32_t t, uint64_t count, std::vector<MapPhoton>& samples) {
  const float each = float(scene.Area(t) / double(count));
  const Normal3 normal = scene.FrontNormal(t);
  for (uint64_t k = 0; k < count; ++k) {
    // The plastic sequence (R2, Roberts 2018): a low-discrepancy point set of any count, without randomness.
    const double u = std::fmod(0.5 + 0.7548776662466927 * double(k), 1.0);
    const double v = std::fmod(0.5 + 0.5698402909980532 * double(k), 1.0);
    const Barycentrics b = count == 1 ? Barycentrics{1.0f / 3, 1.0f / 3} : SampleUniformTriangle({float(u), float(v)});
    samples.push_back({scene.PointAt(t, b.b1, b.b2), Vector3{0, 0, 0}, Rgb{each, each, each}, normal});
  }
}
}  // namespace

AreaSamples SampleArea(const Scene& scene, const std::vector<uint32_t>& triangles, double density) {
  AreaSamples out;
  if (!(density > 0)) return out;
  const double spacing = 1 / std::sqrt(density);
  std::map<std::array<int64_t, 4>, Gathered> cells;  // ordered: the samples come out the same on every run
  std::vector<std::pair<uint32_t, const Gathered*>> members;
  for (uint32_t t : triangles) {
    const double area = scene.Area(t);
    if (!(area > 0)) continue;
    const Normal3 n = scene.FrontNormal(t);
    if (area * density >= 1) {
      SpreadOver(scene, t, uint64_t(std::ceil(area * density)), out.samples);
      out.normalOf[t] = n;
      continue;
    }
    const Point3 c = scene.PointAt(t, 1.0f / 3, 1.0f / 3);
    Gathered& g = cells[{int64_t(std::floor(c.x / spacing)), int64_t(std::floor(c.y / spacing)),
                         int64_t(std::floor(c.z / spacing)), NormalBin(n)}];
    g.area += area;
    g.position[0] += area * c.x, g.position[1] += area * c.y, g.position[2] += area * c.z;
    g.normal = g.normal + AsVector(n) * float(area);
    members.emplace_back(t, &g);
  }
  for (const auto& [key, g] : cells) {
    const auto a = float(g.area);
    const Point3 centroid{float(g.position[0] / g.area), float(g.position[1] / g.area), float(g.position[2] / g.area)};
    out.samples.push_back({centroid, Vector3{0, 0, 0}, Rgb{a, a, a}, NormalFrom(g.normal)});
  }
  for (const auto& [t, g] : members) out.normalOf[t] = NormalFrom(g->normal);
  return out;
}

namespace {
// Times the reach may double for the area below the photons.
constexpr int kMostDoublings = 3;

// The weight of a side of normal m for a point of normal n: 1 when parallel, 0 beyond kPooledCosine.
float Orientation(Normal3 m, Normal3 n) { return std::max(0.0f, (Dot(m, n) - kPooledCosine) / (1 - kPooledCosine)); }

// The angle [rad] whose cosine is c, for c slightly outside [-1, 1] by rounding too.
double Angle(double c) { return std::acos(std::clamp(c, -1.0, 1.0)); }
}  // namespace

PooledEstimator::PooledEstimator(std::vector<MapPhoton> photons, std::vector<MapPhoton> area, PooledSettings settings)
    : photonCount_(photons.size()), areaCount_(area.size()), settings_(settings) {
  // Both kinds of point binned by the same normal grid, so a point's photons and their area are searched alike.
  std::map<int64_t, std::pair<std::vector<MapPhoton>, std::vector<MapPhoton>>> cells;  // ordered: deterministic
  for (MapPhoton& p : photons) cells[NormalBin(p.normal)].first.push_back(p);
  for (MapPhoton& a : area) cells[NormalBin(a.normal)].second.push_back(a);
  const double reach = Angle(kPooledCosine);
  for (auto& [key, members] : cells) {
    Vector3 sum{0, 0, 0};
    for (const auto* list : {&members.first, &members.second})
      for (const MapPhoton& p : *list) sum = sum + AsVector(p.normal);
    const Normal3 axis = NormalFrom(sum);
    double spread = 0;  // the widest angle of a member from the axis [rad]
    for (const auto* list : {&members.first, &members.second})
      for (const MapPhoton& p : *list) spread = std::max(spread, Angle(Dot(p.normal, axis)));
    // A little slack (1e-3 rad) for the rounding of the dot products against the cone's edge.
    const double widest = reach + spread + 1e-3;
    const auto leastCosine = float(widest >= kPi ? -2.0 : std::cos(widest));
    directions_.push_back({axis, leastCosine, PhotonMap(std::move(members.first)), PhotonMap(std::move(members.second))});
  }
}

void PooledEstimator::Collect(const std::vector<const Direction*>& directions, PhotonMap Direction::*map, Point3 x,
                              float radius, Normal3 n, std::vector<Near>& found) {
  thread_local std::vector<std::pair<uint32_t, float>> within;
  found.clear();
  for (const Direction* d : directions) {
    const PhotonMap& points = d->*map;
    points.Within(x, radius, within);
    for (const auto& [i, d2] : within)
      if (const float o = Orientation(points[i].normal, n); o > 0) found.push_back({d2, o, &points[i]});
  }
}

namespace {
// The kernel of the estimate: 1 - d^2 / r^2 within r.
double Falloff(float distance2, float r2) { return std::max(0.0, double(1 - distance2 / r2)); }
}  // namespace

NoisyIrradiance PooledEstimator::Estimate(Point3 x, Normal3 n) const {
  thread_local std::vector<const Direction*> facing;  // the directions that can hold a side within 60 degrees of n
  thread_local std::vector<Near> photons, area;
  facing.clear();
  for (const Direction& d : directions_)
    if (Dot(n, d.axis) >= d.leastCosine) facing.push_back(&d);
  if (facing.empty()) return {};
  const float r = Reach(facing, x, n, photons);
  return r > 0 ? RatioWithin(facing, x, n, r, photons, area) : NoisyIrradiance{};
}

float PooledEstimator::Reach(const std::vector<const Direction*>& facing, Point3 x, Normal3 n,
                             std::vector<Near>& photons) const {
  const size_t wanted = settings_.neighbours;
  Collect(facing, &Direction::photons, x, settings_.maxRadius, n, photons);
  if (photons.empty()) return 0;  // nothing of like orientation within reach: no light to divide, no area to count
  if (photons.size() < wanted) return settings_.maxRadius;
  const auto nth = photons.begin() + std::ptrdiff_t(wanted - 1);
  std::nth_element(photons.begin(), nth, photons.end(),
                   [](const Near& a, const Near& b) { return a.distance2 < b.distance2; });
  return std::sqrt(nth->distance2);
}

NoisyIrradiance PooledEstimator::RatioWithin(const std::vector<const Direction*>& facing, Point3 x, Normal3 n, float r,
                                             std::vector<Near>& photons, std::vector<Near>& area) const {
  for (int doubling = 0;; ++doubling) {
    const float r2 = r * r;
    double areaSum = 0, areaWeight = 0;
    Collect(facing, &Direction::area, x, r, n, area);
    for (const Near& a : area) {
      const double w = Falloff(a.distance2, r2) * a.orientation;
      areaSum += double(a.point->flux.r) * w, areaWeight += w;
    }
    if (areaWeight < kMinAreaSamples && doubling < kMostDoublings) {  // the area is a sliver: reach further
      r *= 2;
      Collect(facing, &Direction::photons, x, r, n, photons);
      continue;
    }
    if (!(areaSum > 0)) return {};
    double sum[3] = {0, 0, 0}, luminance = 0, luminance2 = 0;
    for (const Near& p : photons) {
      const double w = Falloff(p.distance2, r2) * p.orientation;
      const Rgb& phi = p.point->flux;
      sum[0] += phi.r * w, sum[1] += phi.g * w, sum[2] += phi.b * w;
      const double l = double(Luminance(phi)) * w;
      luminance += l, luminance2 += l * l;
    }
    const Rgb irradiance{float(sum[0] / areaSum), float(sum[1] / areaSum), float(sum[2] / areaSum)};
    return {irradiance, luminance > 0 ? std::sqrt(luminance2) / luminance : 0.0};
  }
}

}  // namespace pb
