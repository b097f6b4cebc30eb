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
// Times the reach may grow beyond the nearest photons'.
constexpr int kMostReaches = 4;

// The weight of a side of normal m for a point of normal n: 1 when parallel, 0 beyond kPooledCosine.
float Orientation(Normal3 m, Normal3 n) { return std::max(0.0f, (Dot(m, n) - kPooledCosine) / (1 - kPooledCosine)); }
}  // namespace

PooledEstimator::PooledEstimator(std::vector<MapPhoton> photons, std::vector<MapPhoton> area, PooledSettings settings)
    : photons_(std::move(photons)), area_(std::move(area)), settings_(settings) {}

NoisyIrradiance PooledEstimator::Estimate(Point3 x, Normal3 n) const {
  thread_local std::vector<std::pair<uint32_t, float>> within;
  const float most = settings_.maxRadius;
  const double wanted = settings_.neighbours;
  float r = std::min(settings_.startRadius, most);
  for (int attempt = 0;; ++attempt) {
    const float r2 = r * r;
    double sum[3] = {0, 0, 0}, luminance = 0, luminance2 = 0;
    size_t alike = 0;
    photons_.Within(x, r, within);
    for (const auto& [i, d2] : within) {
      const double w = std::max(0.0, double(1 - d2 / r2)) * Orientation(photons_[i].normal, n);
      if (!(w > 0)) continue;
      const Rgb& phi = photons_[i].flux;
      sum[0] += phi.r * w, sum[1] += phi.g * w, sum[2] += phi.b * w;
      const double l = double(Luminance(phi)) * w;
      luminance += l, luminance2 += l * l, ++alike;
    }
    const bool last = attempt == kMostReaches;
    // Reach further while the photons of like orientation are fewer than half `neighbours` (up to `most`), nearer
    // while they are over four times as many.
    if (!last && 2 * double(alike) < wanted && r < most) {
      r = std::min(float(r * std::clamp(std::sqrt(wanted / std::max<double>(double(alike), 1)), 1.5, 4.0)), most);
      continue;
    }
    if (!last && double(alike) > 4 * wanted) {
      r = float(r * std::sqrt(wanted / double(alike)));
      continue;
    }
    if (alike == 0) return {};  // nothing of like orientation within reach: no light to divide, no area to count
    double area = 0, areaWeight = 0;
    area_.Within(x, r, within);
    for (const auto& [i, d2] : within) {
      const double w = std::max(0.0, double(1 - d2 / r2)) * Orientation(area_[i].normal, n);
      area += double(area_[i].flux.r) * w, areaWeight += w;
    }
    if (!last && areaWeight < kMinAreaSamples) {  // the area below the photons is a sliver: reach further, past `most`
      r *= 2;
      continue;
    }
    if (!(area > 0)) return {};
    const Rgb irradiance{float(sum[0] / area), float(sum[1] / area), float(sum[2] / area)};
    return {irradiance, luminance > 0 ? std::sqrt(luminance2) / luminance : 0.0};
  }
}

}  // namespace pb
