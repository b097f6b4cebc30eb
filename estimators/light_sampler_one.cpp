// LightSampler's one-sample path for a path tracer (estimators/light_sampler.h): next-event estimation with
// multiple importance sampling (Veach and Guibas 1995, "Optimally combining sampling techniques for Monte Carlo
// rendering"). A sample chooses its light with the probabilities Irradiance uses (the light tree's, or the
// unoccluded guess's, here in two passes over the lights instead of a CDF), then a point by area (a curved light's
// by projected solid angle) or a direction by solid angle, as Irradiance would at that point for one sample; the
// pdf of a direction is the light's probability times that of the point's direction (d^2 / (A cos(theta_y)), or
// the point's density per unit area times d^2 / cos(theta_y)) or 1 / Omega. Nothing is allocated per
// call beyond the scratch's first use.
#include <algorithm>
#include <cmath>

#include "estimators/light_sampler.h"
#include "estimators/warps.h"

namespace pb {
// The lights' guesses at a point (in the scratch, < 0 where a light cannot reach it), their sum and counts.
struct LightSampler::Selection {
  const std::vector<double>& guess;
  double total = 0;
  size_t reachable = 0, positive = 0;
  // Light i's probability: SelectionCdf's, renormalised over the lights whose guess is positive.
  double Pmf(size_t i) const {
    if (!(guess[i] > 0) || !(total > 0)) return 0;
    const double norm = (1 - kUniformShare) + kUniformShare * double(positive) / double(reachable);
    return Share(guess[i], total, reachable) / norm;
  }
};

LightSampler::Selection LightSampler::SelectionAt(Point3 p, Normal3 n, OneSampleScratch& scratch) const {
  scratch.guesses.resize(areas_.size());
  Selection s{scratch.guesses};
  for (size_t i = 0; i < areas_.size(); ++i)
    if (const double g = scratch.guesses[i] = Guess(i, p, n); g >= 0) s.total += g, ++s.reachable, s.positive += g > 0;
  return s;
}

std::optional<LightSampler::Pick> LightSampler::PickOne(Point3 p, Normal3 n, float u, OneSampleScratch& scratch) const {
  if (tree_) {
    const auto choice = tree_->Choose(p, n, u);
    if (!choice) return std::nullopt;
    return Pick{choice->light, choice->pmf};
  }
  const Selection selection = SelectionAt(p, n, scratch);
  std::optional<Pick> last;
  double sum = 0;
  for (size_t i = 0; i < areas_.size(); ++i) {
    const double pmf = selection.Pmf(i);
    if (pmf <= 0) continue;
    last = Pick{uint32_t(i), pmf};
    if (double(u) < (sum += pmf)) break;
  }
  return last;  // the last light with a chance where u's rounding runs past the end
}

double LightSampler::PmfOf(uint32_t area, Point3 p, Normal3 n, OneSampleScratch& scratch) const {
  if (tree_) return tree_->Pmf(p, n, area);
  return SelectionAt(p, n, scratch).Pmf(area);
}

LightSampler::AreaSample LightSampler::SampleAreaLights(Point3 p, Normal3 n, Rng& rng, OneSampleScratch& scratch) const {
  if (areas_.empty()) return {};
  const float uPick = rng.Uniform();
  const Point2 u = rng.Uniform2();
  const auto pick = PickOne(p, n, uPick, scratch);
  if (!pick || !(pick->pmf > 0)) return {};
  const Light& light = lights_[areas_[pick->area]];
  const Arrival a = SubtendedAt(pick->area, p, kSolidAngleTriangles, scratch.seen)
                        ? SampleBySolidAngle(light, scratch.seen, p, n, u)
                    : FacingAt(pick->area, p, kFacingTriangles, scratch.facing)
                        ? SampleByFacing(light, scratch.facing, p, n, u)
                        : SampleByArea(light, p, n, u);
  return {a.irradiance * float(1 / pick->pmf), a.from, float(a.pdf * pick->pmf)};
}

float LightSampler::AreaLightPdf(Point3 p, Normal3 n, uint32_t triangle, Point3 y, OneSampleScratch& scratch) const {
  const auto it = areaOfTriangle_.find(triangle);
  if (it == areaOfTriangle_.end()) return 0;
  const double pmf = PmfOf(it->second, p, n, scratch);
  if (!(pmf > 0)) return 0;
  if (SubtendedAt(it->second, p, kSolidAngleTriangles, scratch.seen)) return float(pmf / scratch.seen.total);
  const Vector3 toLight = y - p;
  const double d2 = LengthSquared(toLight);
  const double cosY = -Dot(toLight, scene_.FrontNormal(triangle)) / std::sqrt(d2);
  if (!(d2 > 0) || !(cosY > 0)) return 0;
  double density = 1 / lights_[areas_[it->second]].area;  // of y per unit area
  if (FacingAt(it->second, p, kFacingTriangles, scratch.facing)) {
    const auto& ts = scratch.facing.triangles;
    const auto at = std::find(ts.begin(), ts.end(), triangle);
    if (at == ts.end()) return 0;
    density = scratch.facing.density[size_t(at - ts.begin())];
  }
  return float(pmf * density * d2 / cosY);
}

Rgb LightSampler::OtherIrradiance(Point3 p, Normal3 n, Rng& rng) const {
  Rgb sum;
  for (uint32_t l : others_) {
    const AnalyticLight& light = lights_[l].analytic;
    if (light.image || (light.kind == LightKind::kSky && !lights_[l].portals.empty()))
      sum += AimedSkyIrradiance(lights_[l], p, n, 1, rng, nullptr).irradiance;
    else if (light.kind == LightKind::kSky)
      sum += SkyIrradiance(light, p, n, 1, rng, nullptr).irradiance;
    else
      sum += DeltaIrradiance(light, p, n, nullptr);
  }
  return sum;
}

}  // namespace pb
