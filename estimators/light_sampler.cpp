#include "estimators/light_sampler.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "estimators/sky_sampling.h"
#include "estimators/warps.h"
#include "mesh/errors.h"

namespace pb {
namespace {


// Adds sample e, arriving from w at `cosine` to the normal, to `cell` of `mean`; with `moments`, its moment vector
// too, and its moments at weight 1 / samples.
void AddSample(StratifiedMean& mean, IncidentMoments* moments, uint32_t cell, Rgb e, Vector3 w, float cosine,
               uint32_t samples) {
  if (moments == nullptr) return mean.Add(cell, e);
  if (e.IsBlack()) return mean.Add(cell, e, Vector3{});
  mean.Add(cell, e, MomentVector(e, w, cosine));
  moments->Add(e, w, cosine, 1.0f / float(samples));
}

// The stratified samples' mean, their moments' covariance added to `moments` when given.
DirectSample Finish(const StratifiedMean& mean, IncidentMoments* moments) {
  if (moments != nullptr) moments->covariance.Add(mean.VectorCovariance(), 1);
  return mean.Result();
}

// A random order of the cells 0..n-1 (Fisher-Yates).
std::vector<uint32_t> Shuffled(uint32_t n, Rng& rng) {
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  for (uint32_t i = n; i > 1; --i) std::swap(order[i - 1], order[std::min(uint32_t(rng.Uniform() * float(i)), i - 1)]);
  return order;
}

}  // namespace

LightSampler::LightSampler(const Scene& scene, const std::vector<Light>& lights, const RayScene& rays,
                           size_t treeFrom, double solidAngleFrom, float curvedSpread)
    : scene_(scene), lights_(lights), rays_(rays), solidAngleFrom_(solidAngleFrom), curvedSpread_(curvedSpread) {
  for (uint32_t l = 0; l < lights.size(); ++l) (lights[l].IsArea() ? areas_ : others_).push_back(l);
  for (uint32_t l : areas_) {
    const Light& light = lights[l];
    for (uint32_t t : light.triangles) areaOfTriangle_.emplace(t, uint32_t(shapes_.size()));
    LightShape shape;
    Vector3 weighted{0, 0, 0};
    for (uint32_t t : light.triangles) {
      const double area = 0.5 * Length(scene.AreaVector(t));
      const Point3 c = scene.PointAt(t, 1.0f / 3, 1.0f / 3);
      weighted = weighted + Vector3{c.x, c.y, c.z} * float(area / light.area);
      for (float b1 : {0.0f, 1.0f})
        for (float b2 : {0.0f, 1.0f})
          if (b1 + b2 <= 1) shape.corners.push_back(scene.PointAt(t, b1, b2));
    }
    shape.centroid = {weighted.x, weighted.y, weighted.z};
    for (const Point3& corner : shape.corners) shape.radius = std::max(shape.radius, Length(corner - shape.centroid));
    shape.radius *= 1.0001f;  // rounding must not shrink it
    shape.power = Luminance(light.radiance) * light.area;
    const LightBounds cone = BoundsOf(shape, light);
    shape.axis = cone.axis, shape.spread = cone.spread, shape.lo = cone.lo, shape.hi = cone.hi;
    shape.nearest = INFINITY;
    for (const Point3& corner : shape.corners) shape.nearest = std::min(shape.nearest, Dot(corner - Point3{0, 0, 0}, shape.axis));
    shapes_.push_back(std::move(shape));
  }
  if (areas_.size() < treeFrom) return;
  std::vector<LightBounds> bounds;
  for (size_t i = 0; i < areas_.size(); ++i) bounds.push_back(BoundsOf(shapes_[i], lights[areas_[i]]));
  tree_.emplace(bounds);
}

// The light's box, the cone about its area-weighted front normal that holds every triangle's, and its power
// (floored so that a black emitter still has a leaf the tree can weigh).
LightBounds LightSampler::BoundsOf(const LightShape& shape, const Light& light) const {
  LightBounds b;
  b.Enclose(shape.corners);
  Vector3 sum{0, 0, 0};
  for (uint32_t t : light.triangles) sum = sum + scene_.AreaVector(t);
  const float length = Length(sum);
  if (!(length > 1e-6f * float(light.area))) {
    b.spread = kPi;
  } else {
    b.axis = sum * (1.0f / length);
    for (uint32_t t : light.triangles) {
      const float cosine = std::clamp(Dot(b.axis, scene_.FrontNormal(t)), -1.0f, 1.0f);
      b.spread = std::max(b.spread, std::acos(cosine));
    }
    b.spread = std::min(b.spread * 1.0001f + 1e-5f, kPi);  // rounding must not shrink the cone
  }
  b.power = std::max(shape.power, 1e-30);
  return b;
}

bool LightSampler::CanReach(const LightShape& shape, const Light& light, Point3 p, Normal3 n) const {
  if (light.triangles.size() > kExactReachTriangles) return MayReach(shape, p, n);
  const bool inFrontOfX = std::any_of(shape.corners.begin(), shape.corners.end(),
                                      [&](Point3 c) { return Dot(c - p, n) > 0; });
  if (!inFrontOfX) return false;
  return std::any_of(light.triangles.begin(), light.triangles.end(), [&](uint32_t t) {
    return Dot(p - scene_.PointAt(t, 0, 0), scene_.FrontNormal(t)) > 0;
  });
}

// Conservative: false only when the light's box lies wholly behind p's plane, or when no triangle can face p, by
// either of two bounds on the largest dot(p - y, n_t) over the light's points y and front normals n_t:
//  - its sphere and cone: |p - c| cos(max(0, psi - theta_o)) + r, with psi the angle between p - c and the axis;
//  - its planes: dot(p, a) - min_y dot(y, a) + (|p - c| + r) 2 sin(theta_o / 2), exact for a flat light.
bool LightSampler::MayReach(const LightShape& shape, Point3 p, Normal3 n) {
  float front = -Dot(p - Point3{0, 0, 0}, n);  // the box's farthest corner along n, less p's
  for (int k = 0; k < 3; ++k) {
    const float nk = k == 0 ? n.x : k == 1 ? n.y : n.z;
    const float lo = k == 0 ? shape.lo.x : k == 1 ? shape.lo.y : shape.lo.z, hi = k == 0 ? shape.hi.x : k == 1 ? shape.hi.y : shape.hi.z;
    front += std::max(lo * nk, hi * nk);
  }
  if (!(front > 0)) return false;
  const Vector3 d = p - shape.centroid;
  const float distance = Length(d);
  const float tilt = (distance + shape.radius) * 2 * std::sin(0.5f * std::min(shape.spread, kPi));
  if (!(Dot(p - Point3{0, 0, 0}, shape.axis) - shape.nearest + tilt > 0)) return false;
  if (!(distance > shape.radius) || shape.spread >= kPi) return true;
  const float psi = std::acos(std::clamp(Dot(d, shape.axis) / distance, -1.0f, 1.0f));
  return distance * std::cos(std::max(0.0f, psi - shape.spread)) + shape.radius > 0;
}

double LightSampler::Guess(size_t i, Point3 p, Normal3 n) const {
  const Light& light = lights_[areas_[i]];
  if (!CanReach(shapes_[i], light, p, n)) return -1;
  return shapes_[i].power / std::max(double(LengthSquared(shapes_[i].centroid - p)), light.area);
}

std::vector<double> LightSampler::SelectionCdf(Point3 p, Normal3 n) const {
  std::vector<double> guess(areas_.size(), 0.0);
  size_t reachable = 0;
  for (size_t i = 0; i < areas_.size(); ++i) {
    const double g = Guess(i, p, n);
    if (g < 0) continue;
    ++reachable;
    guess[i] = g;
  }
  if (reachable == 0) return {};
  const double total = std::accumulate(guess.begin(), guess.end(), 0.0);
  std::vector<double> cdf(areas_.size());
  double sum = 0;
  for (size_t i = 0; i < areas_.size(); ++i) {
    const bool can = guess[i] > 0;
    sum += can ? Share(guess[i], total, reachable) : 0.0;
    cdf[i] = sum;
  }
  for (double& c : cdf) c /= sum;
  cdf.back() = 1;
  return cdf;
}

LightSampler::Arrival LightSampler::SampleOne(size_t area, Point3 p, Normal3 n, Point2 u, SubtendedCache& cache) const {
  const Light& light = lights_[areas_[area]];
  auto [entry, first] = cache.lights.try_emplace(uint32_t(area));
  Seen& seen = entry->second;
  if (first) {
    Subtended subtended;
    Facing facing;
    if (SubtendedAt(area, p, cache.triangles, subtended))
      seen.subtended = std::move(subtended);
    else if (FacingAt(area, p, std::max(kFacingTriangles, cache.triangles), facing))
      seen.facing = std::move(facing);
  }
  if (seen.subtended) return SampleBySolidAngle(light, *seen.subtended, p, n, u);
  return seen.facing ? SampleByFacing(light, *seen.facing, p, n, u) : SampleByArea(light, p, n, u);
}

bool LightSampler::FacingAt(size_t area, Point3 p, size_t triangles, Facing& facing) const {
  const Light& light = lights_[areas_[area]];
  if (!(shapes_[area].spread > curvedSpread_) || light.triangles.size() > triangles) return false;
  facing.triangles.clear(), facing.cdf.clear(), facing.density.clear();
  double total = 0;
  for (uint32_t t : light.triangles) {
    const Vector3 toP = p - scene_.PointAt(t, 1.0f / 3, 1.0f / 3);
    const double d2 = LengthSquared(toP), height = Dot(toP, scene_.FrontNormal(t));
    if (!(height > 0) || !(d2 > 0)) continue;
    const double area = 0.5 * Length(scene_.AreaVector(t)), weight = area * height / (d2 * std::sqrt(d2));
    if (!(weight > 0) || !std::isfinite(weight)) continue;
    facing.triangles.push_back(t), facing.density.push_back(weight / area);
    facing.cdf.push_back(total += weight);
  }
  for (double& c : facing.cdf) c /= total;
  for (double& d : facing.density) d /= total;
  if (!facing.cdf.empty()) facing.cdf.back() = 1;
  return true;
}

// Ke V cos cos / d^2 over the density of y: a triangle in proportion to its projected solid angle, y uniform on it.
LightSampler::Arrival LightSampler::SampleByFacing(const Light& light, const Facing& facing, Point3 p, Normal3 n,
                                                   Point2 u) const {
  const auto pick = SampleDiscreteCdf(facing.cdf, u.u);
  if (!pick) return {};  // no triangle faces p
  const uint32_t triangle = facing.triangles[pick->index];
  const Barycentrics b = SampleUniformTriangle({pick->uRemapped, u.v});
  const Point3 y = scene_.PointAt(triangle, b.b1, b.b2);
  const Vector3 toLight = y - p;
  const double d2 = LengthSquared(toLight);
  const double cosY = -Dot(toLight, scene_.FrontNormal(triangle)) / std::sqrt(d2);
  if (!(d2 > 0) || !(cosY > 0)) return {};
  const double density = facing.density[pick->index];
  return {Unoccluded(light, p, n, y) * float(cosY / (d2 * density)), toLight * float(1 / std::sqrt(d2)),
          float(density * d2 / cosY)};
}

bool LightSampler::SubtendedAt(size_t area, Point3 p, size_t triangles, Subtended& seen) const {
  const Light& light = lights_[areas_[area]];
  const LightShape& shape = shapes_[area];
  if (light.triangles.size() > triangles) return false;
  // The sphere that holds the light subtends 2 pi (1 - cos) with sin = r / d, at least the light's solid angle.
  const double d2 = LengthSquared(p - shape.centroid), r2 = double(shape.radius) * shape.radius;
  if (d2 > r2 && 2 * kPi * (1 - std::sqrt(1 - r2 / d2)) < solidAngleFrom_) return false;
  seen.parts.clear(), seen.triangles.clear(), seen.cdf.clear(), seen.total = 0;
  for (uint32_t t : light.triangles) {
    if (!(Dot(p - scene_.Corner(t, 0), scene_.FrontNormal(t)) > 0)) continue;
    const auto part = SphericalTriangle::From(p, scene_.Corner(t, 0), scene_.Corner(t, 1), scene_.Corner(t, 2));
    if (!part) continue;
    seen.parts.push_back(*part), seen.triangles.push_back(t);
    seen.cdf.push_back(seen.total += part->SolidAngle());
  }
  if (!(seen.total >= solidAngleFrom_)) return false;
  for (double& c : seen.cdf) c /= seen.total;
  seen.cdf.back() = 1;
  return true;
}

// Ke V cos(theta_x) Omega: a direction uniform over the light's solid angle at p (the triangle in proportion to
// its part of it), its ray continued to the triangle's plane for the shadow ray.
LightSampler::Arrival LightSampler::SampleBySolidAngle(const Light& light, const Subtended& seen, Point3 p, Normal3 n,
                                                       Point2 u) const {
  const auto pick = SampleDiscreteCdf(seen.cdf, u.u);
  const Vector3 w = seen.parts[pick->index].Sample({pick->uRemapped, u.v});
  const uint32_t triangle = seen.triangles[pick->index];
  const Normal3 front = scene_.FrontNormal(triangle);
  const float along = Dot(scene_.Corner(triangle, 0) - p, front) / Dot(w, front);
  if (!(along > 0) || !std::isfinite(along) || !(Dot(w, n) > 0)) return {};
  return {Unoccluded(light, p, n, p + w * along) * float(seen.total), w, float(1 / seen.total)};
}

// Ke V cos cos / d^2 times the light's area, for the point of `light` that u picks (uniform over its area).
LightSampler::Arrival LightSampler::SampleByArea(const Light& light, Point3 p, Normal3 n, Point2 u) const {
  const auto pick = SampleDiscreteCdf(light.triangleCdf, u.u);
  PB_CHECK(pick.has_value(), "a light has at least one triangle");
  const uint32_t triangle = light.triangles[pick->index];
  const Barycentrics b = SampleUniformTriangle({pick->uRemapped, u.v});
  const Point3 y = scene_.PointAt(triangle, b.b1, b.b2);
  const Vector3 toLight = y - p;
  const float d2 = LengthSquared(toLight);
  if (!(d2 > 0)) return {};
  const float cosY = -Dot(toLight, scene_.FrontNormal(triangle)) / std::sqrt(d2);
  if (cosY <= 0) return {};
  return {Unoccluded(light, p, n, y) * float(double(cosY) / d2 * light.area), toLight * (1 / std::sqrt(d2)),
          float(d2 / (double(cosY) * light.area))};
}

Rgb LightSampler::Unoccluded(const Light& light, Point3 p, Normal3 n, Point3 y) const {
  const Vector3 toLight = y - p;
  const float d = Length(toLight);
  const float cosX = d > 0 ? Dot(toLight, n) / d : 0.0f;
  if (!(cosX > 0)) return {};
  const Point3 origin = rays_.SpawnPoint(p, n);
  const Vector3 span = y - origin;
  const float length = Length(span);
  if (rays_.Occluded(origin, span * (1.0f / length), length * (1 - 1e-4f))) return {};
  return light.radiance * cosX;
}

std::optional<LightSampler::Pick> LightSampler::PickLight(const std::vector<double>& cdf, Point3 p, Normal3 n,
                                                          float u) const {
  if (tree_) {
    const auto choice = tree_->Choose(p, n, u);
    if (!choice) return std::nullopt;
    return Pick{choice->light, choice->pmf};
  }
  const auto choice = SampleDiscreteCdf(cdf, u);
  if (!choice) return std::nullopt;
  return Pick{choice->index, choice->pmf};
}

DirectSample LightSampler::AreaIrradiance(Point3 p, Normal3 n, uint32_t samples, Rng& rng,
                                          IncidentMoments* moments) const {
  if (samples == 0 || areas_.empty()) return {};
  std::vector<double> cdf;  // the exact guess, without a tree
  if (tree_ ? !tree_->AnyCanReach(p, n) : (cdf = SelectionCdf(p, n)).empty()) return {};
  const auto side = uint32_t(std::ceil(std::sqrt(double(samples))));
  const std::vector<uint32_t> cells = Shuffled(side * side, rng);
  StratifiedMean mean(side);
  SubtendedCache cache{std::max<size_t>(kSolidAngleTriangles, samples / 4), {}};
  for (uint32_t j = 0; j < samples; ++j) {
    const auto pick = PickLight(cdf, p, n, std::min((float(j) + rng.Uniform()) / float(samples), 0x1.fffffep-1f));
    const uint32_t cell = cells[j];
    const Point2 jitter = rng.Uniform2();
    const Point2 u{(float(cell % side) + jitter.u) / float(side), (float(cell / side) + jitter.v) / float(side)};
    const Arrival a = pick ? SampleOne(pick->area, p, n, u, cache) : Arrival{};
    AddSample(mean, moments, cell, a.irradiance * float(pick ? 1.0 / pick->pmf : 0.0), a.from, Dot(a.from, n), samples);
  }
  return Finish(mean, moments);
}

bool LightSampler::Escapes(Point3 origin, Vector3 w) const { return !rays_.Occluded(origin, w); }

Rgb LightSampler::DeltaIrradiance(const AnalyticLight& light, Point3 p, Normal3 n, IncidentMoments* moments) const {
  const Arrival a = DeltaArrival(light, p, n);
  if (moments != nullptr && !a.irradiance.IsBlack()) moments->Add(a.irradiance, a.from, Dot(a.from, n));  // exact
  return a.irradiance;
}

LightSampler::Arrival LightSampler::DeltaArrival(const AnalyticLight& light, Point3 p, Normal3 n) const {
  const Point3 origin = rays_.SpawnPoint(p, n);
  if (light.kind == LightKind::kSun) {
    const Vector3 w = -light.direction;
    const float cosX = Dot(w, n);
    return {cosX > 0 && Escapes(origin, w) ? light.intensity * cosX : Rgb{}, w};
  }
  const Vector3 toLight = light.position - p;
  const float d2 = LengthSquared(toLight);
  if (!(d2 > 0)) return {};
  const Vector3 w = toLight * (1.0f / std::sqrt(d2));
  const float cosX = Dot(w, n);
  if (cosX <= 0) return {};
  const float falloff = RelativeIntensity(light, -w);
  if (falloff <= 0) return {};
  const Vector3 span = light.position - origin;
  const float length = Length(span);
  if (rays_.Occluded(origin, span * (1.0f / length), length * (1 - 1e-4f))) return {};
  return {light.intensity * (falloff * cosX / d2), w};
}

DirectSample LightSampler::SkyIrradiance(const AnalyticLight& sky, Point3 p, Normal3 n, uint32_t samples, Rng& rng,
                                         IncidentMoments* moments) const {
  const auto side = uint32_t(std::ceil(std::sqrt(double(samples))));
  const Frame frame = Frame::FromNormal(n);
  const Point3 origin = rays_.SpawnPoint(p, n);
  StratifiedMean mean(side);
  for (uint32_t cell = 0; cell < samples; ++cell) {
    const Point2 jitter = rng.Uniform2();
    const Point2 u{(float(cell % side) + jitter.u) / float(side), (float(cell / side) + jitter.v) / float(side)};
    const Vector3 w = frame.ToWorld(SampleCosineHemisphere(u).direction);
    const bool open = (sky.wholeSphere || Dot(w, sky.up) > 0) && Escapes(origin, w);
    AddSample(mean, moments, cell, open ? sky.intensity * float(kPi) : Rgb{}, w, Dot(w, n), samples);
  }
  return Finish(mean, moments);
}

// Per stratum, one cosine-distributed direction, one drawn from the image and, with portals, one toward them, each
// weighted by the balance heuristic (Veach and Guibas 1995): L cos / (sum of the techniques' pdfs) for each that
// escapes toward the sky.
DirectSample LightSampler::AimedSkyIrradiance(const Light& sky, Point3 p, Normal3 n, uint32_t samples, Rng& rng,
                                              IncidentMoments* moments) const {
  const auto side = uint32_t(std::ceil(std::sqrt(double(samples))));
  const Frame frame = Frame::FromNormal(n);
  const Point3 origin = rays_.SpawnPoint(p, n);
  const bool portals = !sky.portals.empty();
  Vector3 stratumVector;  // the moment vectors of the stratum's directions
  const auto weighed = [&](Vector3 w) {
    const float cosX = Dot(w, n);
    if (!(cosX > 0)) return Rgb{};
    const Rgb radiance = SkyRadianceFrom(sky.analytic, w);
    if (radiance.IsBlack() || !Escapes(origin, w)) return Rgb{};
    const float pdf = CosineHemispherePdf(cosX) + SkyImagePdf(sky, w) + (portals ? TowardPortalsPdf(sky, p, w) : 0);
    const Rgb e = radiance * (cosX / pdf);
    if (moments != nullptr) {
      moments->Add(e, w, cosX, 1.0f / float(samples));
      stratumVector = stratumVector + MomentVector(e, w, cosX);
    }
    return e;
  };
  const auto stratum = [&](uint32_t cell) {
    const Point2 jitter = rng.Uniform2();
    return Point2{(float(cell % side) + jitter.u) / float(side), (float(cell / side) + jitter.v) / float(side)};
  };
  StratifiedMean mean(side);
  for (uint32_t cell = 0; cell < samples; ++cell) {
    stratumVector = {};
    Rgb e = weighed(frame.ToWorld(SampleCosineHemisphere(stratum(cell)).direction));
    if (const std::optional<SkySample> image = SampleSkyImage(sky, stratum(cell))) e += weighed(image->from);
    if (portals)
      if (const std::optional<SkySample> out = SampleTowardPortals(sky, p, stratum(cell))) e += weighed(out->from);
    moments != nullptr ? mean.Add(cell, e, stratumVector) : mean.Add(cell, e);
  }
  return Finish(mean, moments);
}

DirectSample LightSampler::Irradiance(Point3 p, Normal3 n, uint32_t samples, Rng& rng, IncidentMoments* moments) const {
  DirectSample result = AreaIrradiance(p, n, samples, rng, moments);
  result.samples = samples;
  if (others_.empty() || samples == 0) return result;
  IndependentSum sum(result);
  for (uint32_t l : others_) {
    const AnalyticLight& light = lights_[l].analytic;
    if (light.image || (light.kind == LightKind::kSky && !lights_[l].portals.empty()))
      sum.Add(AimedSkyIrradiance(lights_[l], p, n, samples, rng, moments));
    else
      sum.Add(light.kind == LightKind::kSky ? SkyIrradiance(light, p, n, samples, rng, moments)
                                            : NoisyIrradiance{DeltaIrradiance(light, p, n, moments)});  // exact: no noise
  }
  static_cast<NoisyIrradiance&>(result) = sum.Total();
  return result;
}

uint32_t LightSampler::AdaptiveCount(double relativeNoise, uint32_t samples, double target, uint32_t maxSamples) {
  const double ratio = relativeNoise / target;
  // Rounded up to a square, so that the samples fill their stratification grid and its error estimate holds.
  const double side = std::ceil(std::sqrt(double(samples) * std::pow(ratio, 1 / kStratifiedOrder)));
  return uint32_t(std::clamp(side * side, double(kPilotSamples), double(std::max(maxSamples, kPilotSamples))));
}

DirectSample LightSampler::AdaptiveIrradiance(Point3 p, Normal3 n, double target, uint32_t maxSamples, Rng& rng,
                                              IncidentMoments* moments) const {
  Rng pilotRng = PilotStream(rng);
  const DirectSample pilot = Irradiance(p, n, kPilotSamples, pilotRng);
  const uint32_t count = AdaptiveCount(pilot.relativeNoise, kPilotSamples, target, maxSamples);
  DirectSample result = Irradiance(p, n, count, rng, moments);
  result.samples = count + kPilotSamples;
  return result;
}

Rgb LightSampler::SkyRadiance(Vector3 w) const {
  Rgb radiance;
  for (uint32_t l : others_) {
    const AnalyticLight& sky = lights_[l].analytic;
    if (sky.kind == LightKind::kSky) radiance = radiance + SkyRadianceFrom(sky, w);  // 0 below its horizon
  }
  return radiance;
}

void StratifiedMean::Add(uint32_t cell, Rgb e) {
  all_.Add(e);
  byCell_[cell] = Luminance(e);
  order_.push_back(cell);
}

void StratifiedMean::Add(uint32_t cell, Rgb e, Vector3 v) {
  all_.Add(e, v);
  byCell_[cell] = Luminance(e);
  order_.push_back(cell);
  if (vectors_.empty()) vectors_.resize(byCell_.size());
  vectors_[cell] = v;
}

template <typename Triple>
double StratifiedMean::ForEachTriple(bool byOrder, Triple triple) const {
  if (byOrder) {
    for (size_t k = 0; k + 2 < order_.size(); ++k) triple(order_[k], order_[k + 1], order_[k + 2]);
    return double(order_.size());
  }
  double n = 0;
  for (uint32_t b = 0; b < side_; ++b)
    for (uint32_t a = 0; a < side_; ++a) {
      const size_t cell = size_t(b) * side_ + a;
      if (byCell_[cell] < 0) continue;
      ++n;
      if (a + 2 < side_ && byCell_[cell + 1] >= 0 && byCell_[cell + 2] >= 0) triple(cell, cell + 1, cell + 2);
    }
  return n;
}

// The variance of the mean from one kind of triples, or -1 with fewer than two.
double StratifiedMean::TripleVariance(bool byOrder) const {
  double squares = 0, triples = 0;
  const double n = ForEachTriple(byOrder, [&](size_t a, size_t b, size_t c) {
    squares += std::pow(byCell_[a] - 2 * byCell_[b] + byCell_[c], 2), ++triples;
  });
  // Per sample, a triple gives (f_1 - 2 f_2 + f_3)^2 / 6; the mean of n samples has n times that over n^2.
  return triples < 2 ? -1.0 : squares / (6 * triples) / n;
}

StratifiedMean::Variance StratifiedMean::SmallerVariance() const {
  const double cells = TripleVariance(false), order = TripleVariance(true);
  const bool byOrder = order >= 0 && (cells < 0 || order < cells);
  return {byOrder ? order : cells, byOrder};
}

DirectSample StratifiedMean::Result() const {
  DirectSample result = all_.Result();
  const double mean = Luminance(result.irradiance);
  const double variance = SmallerVariance().ofMean;
  if (variance < 0 || !(mean > 0)) return result;  // too few triples: the independent-sample error
  result.relativeNoise = std::sqrt(variance) / mean;
  return result;
}

Symmetric3 StratifiedMean::VectorCovariance() const {
  Symmetric3 squares;
  double triples = 0;
  const double n = ForEachTriple(SmallerVariance().byOrder, [&](size_t a, size_t b, size_t c) {
    squares.AddOuter(vectors_[a] - 2.0f * vectors_[b] + vectors_[c], 1), ++triples;
  });
  if (triples < 2) return all_.VectorCovariance();
  Symmetric3 covariance;
  covariance.Add(squares, 1 / (6 * triples) / n);
  return covariance;
}

Symmetric3 SampleMean::VectorCovariance() const {
  Symmetric3 covariance;
  if (n_ < 2) return covariance;
  const double n = n_;
  // (sum v v^T - n m m^T) / (n - 1), the sample covariance, over n for the mean's.
  covariance.Add(outer_, 1 / (n * (n - 1)));
  const Vector3 mean{float(vectorSum_[0] / n), float(vectorSum_[1] / n), float(vectorSum_[2] / n)};
  covariance.AddOuter(mean, -n / (n * (n - 1)));
  return covariance;
}

DirectSample SampleMean::Result() const {
  if (n_ == 0) return {};
  const double mean = luminance_ / n_;
  DirectSample result{{sum_.ToRgb() * float(1.0 / n_), 0.0}};
  if (mean > 0 && n_ > 1) {
    const double variance = std::max(squares_ / n_ - mean * mean, 0.0) * n_ / (n_ - 1.0);
    result.relativeNoise = std::sqrt(variance / n_) / mean;
  }
  return result;
}

}  // namespace pb
