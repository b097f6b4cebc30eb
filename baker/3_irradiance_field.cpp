#include "baker/3_irradiance_field.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include "baker/1_trace_photons.h"
#include "baker/distribution.h"
#include "baker/3_surface_point.h"
#include "estimators/cover_probe.h"

namespace pb {

IrradianceField::IrradianceField(const PreparedScene& scene, std::unique_ptr<PhotonIrradiance> photons)
    : scene_(&scene), photons_(photons.get()) {
  contributions_.push_back(std::move(photons));
}

std::unique_ptr<PhotonIrradiance> IrradianceField::TakePhotons() && {
  std::unique_ptr<PhotonIrradiance> photons(static_cast<PhotonIrradiance*>(contributions_.front().release()));
  contributions_.clear(), photons_ = nullptr;
  return photons;
}

void IrradianceField::Add(std::unique_ptr<IrradianceContribution> contribution) {
  contributions_.push_back(std::move(contribution));
}

void IrradianceField::GatherGaps(std::unique_ptr<GapGather> gaps) { gaps_ = std::move(gaps); }

FieldWork IrradianceField::Work() const {
  FieldWork work{0, gaps_ ? gaps_->RaysCast() : 0};
  for (const auto& c : contributions_) work.pointSamples += c->SamplesDrawn();
  return work;
}

std::span<const uint32_t> IrradianceField::SmallLeftOut() const {
  return gaps_ ? std::span<const uint32_t>(gaps_->SmallLeftOut()) : std::span<const uint32_t>();
}

const ImportanceCache* IrradianceField::Guide(std::unique_ptr<ImportanceCache> guide) {
  guide_ = std::move(guide);
  return guide_.get();
}

std::optional<SurfacePoint> IrradianceField::RaysStart(const SurfacePoint& p) const {
  if (!gaps_ && !scene_->enclosureByPoint[p.surface] && !AtItsCoversRim(p)) return std::nullopt;
  return RayStart(*scene_, p);
}

bool IrradianceField::AtItsCoversRim(const SurfacePoint& p) const {
  const SurfaceCover& cover = scene_->covers[p.surface];
  if (cover.Empty() || cover.Covered(p.uv)) return false;
  const float r = cover.Spacing() / 64;  // along the sides and the diagonals: a corner of a face covered whole
  for (const float du : {-r, 0.0f, r})
    for (const float dv : {-r, 0.0f, r})
      if (cover.Covered({p.uv.u + du, p.uv.v + dv})) return true;
  return false;
}

bool IrradianceField::Enclosed(const SurfacePoint& p, const std::optional<SurfacePoint>& start) const {
  const SurfaceCover& cover = scene_->covers[p.surface];
  if (!cover.Empty() && cover.Covered(p.uv))  // its domain's photons read it, unless it is pressed against a face
    return PressedAt(scene_->scene, scene_->surfaces, *scene_->rays, p.surface, p.position, p.normal);
  if (!start) return false;
  const auto enclosed = [&] {
    return EnclosedAt(scene_->scene, scene_->surfaces, *scene_->rays, p.surface, start->position, p.normal);
  };
  if (scene_->enclosureByPoint[p.surface]) return enclosed();
  return OnBoundary(p, *start) && AtItsCoversRim(p) &&
         (PressedAt(scene_->scene, scene_->surfaces, *scene_->rays, p.surface, start->position, p.normal) || enclosed());
}

IrradianceField::Replacement IrradianceField::ReplacedAt(const SurfacePoint& p) const {
  const std::optional<SurfacePoint> start = RaysStart(p);
  if (Enclosed(p, start)) return {true, std::nullopt};
  if (!gaps_) return {};
  const GapGather::Kind kind = gaps_->KindOf(p, *start);
  if (kind == GapGather::Kind::kNone) return {};
  const NoisyIrradiance gathered = gaps_->Gathered(p, *start);
  if (!GapGather::Weighed(kind)) return {false, GapTerm{Blend(gathered, {}, 1), std::nullopt}};
  const NoisyIrradiance photons = contributions_.front()->WithNoise(p);
  return {false, GapTerm{Blend(gathered, photons, GapWeightOf(p.surface).alpha), std::pair(gathered, photons)}};
}

Rgb IrradianceField::Irradiance(const SurfacePoint& p) const {
  const auto [enclosed, gap] = ReplacedAt(p);
  Rgb sum = enclosed ? Rgb{} : gap ? gap->blended.value.irradiance : contributions_.front()->At(p);
  for (size_t i = 1; i < contributions_.size() && !enclosed; ++i) sum = sum + contributions_[i]->At(p);
  return sum;
}

SurfaceLight IrradianceField::LightWith(const SurfacePoint& p, Rgb irradiance) const {
  const Material& material = scene_->scene.materials[scene_->surfaces.surfaces[p.surface].material];
  return {irradiance, scene_->scene.AlbedoAtTexcoord(material, p.texcoord), material.emission};
}

SurfaceLight IrradianceField::Light(const SurfacePoint& p) const { return LightWith(p, Irradiance(p)); }

IncidentMoments IrradianceField::Moments(const SurfacePoint& p) const {
  IncidentMoments moments;
  const std::optional<SurfacePoint> start = RaysStart(p);
  const bool enclosed = Enclosed(p, start);
  const GapGather::Kind kind = gaps_ && !enclosed ? gaps_->KindOf(p, *start) : GapGather::Kind::kNone;
  const double alpha = GapGather::Weighed(kind) ? GapWeightOf(p.surface).alpha : 1.0;
  if (enclosed) {
    // inside a closed object: no photon, no gathered path reaches it
  } else if (kind != GapGather::Kind::kNone && alpha >= 1) {
    gaps_->Gathered(p, *start, &moments);
  } else if (kind != GapGather::Kind::kNone) {  // a narrow gap's mix, as its H
    IncidentMoments gathered, photons;
    gaps_->Gathered(p, *start, &gathered);
    contributions_.front()->AddMoments(p, photons);
    moments.Add(gathered, float(alpha)), moments.Add(photons, float(1 - alpha));
  } else {
    contributions_.front()->AddMoments(p, moments);
  }
  for (size_t i = 1; i < contributions_.size() && !enclosed; ++i) contributions_[i]->AddMoments(p, moments);
  return moments;
}

void IrradianceField::SetNoise(SurfaceLight& light, uint32_t surface, float areaRatio, const GapTerm* gap,
                               const NoisyIrradiance& first, const IndependentSum& sum) const {
  const NoisyIrradiance total = sum.Total();
  light.irradiance = total.irradiance;
  light.relativeNoise = total.relativeNoise;
  const double all = sum.Variance(), mean = Luminance(total.irradiance);
  // Outside a gap the first term is the photons'; in one, the gathered paths' or their mix with the photons'.
  const double photonVariance = gap ? gap->blended.photonVariance : first.Variance();
  const double photonLight = Luminance(gap ? gap->blended.photonPart : first.irradiance);
  light.photonVarianceShare = all > 0 ? photonVariance / all : 1.0;
  light.gatheredVarianceShare = all > 0 && gap ? gap->blended.gatheredVariance / all : 0.0;
  light.sampledShare = mean > 0 ? std::clamp(1 - photonLight / mean, 0.0, 1.0) : 0.0;
  // The photons' bias: their surface's outside a gap; in a narrow gap, what the mix keeps of it; else none.
  const GapWeight weight = GapWeightOf(surface);
  const double bias = !gap ? photons_->Bias(surface) * areaRatio : gap->estimates ? (1 - weight.alpha) * weight.bias : 0.0;
  light.relativeBias = mean > 0 ? bias / mean : 0.0;
}

namespace {

NoisyIrradiance Sum(const NoisyIrradiance& a, const NoisyIrradiance& b) {
  IndependentSum sum(a);
  sum.Add(b);
  return sum.Total();
}

}  // namespace

SurfaceLight IrradianceField::LightWithNoise(const SurfacePoint& p) const {
  // Independent contributions: their variances add (IndependentSum). Inside a closed object the photons' term is 0.
  const auto [enclosed, gap] = ReplacedAt(p);
  const NoisyIrradiance first = enclosed ? NoisyIrradiance{} : gap ? gap->blended.value : contributions_.front()->WithNoise(p);
  IndependentSum sum(first);
  NoisyIrradiance rest;  // the other terms' sum: the one other term itself (the direct light), as Remix adds it
  for (size_t i = 1; i < contributions_.size() && !enclosed; ++i) {
    const NoisyIrradiance term = contributions_[i]->WithNoise(p);
    sum.Add(term);
    rest = i == 1 ? term : Sum(rest, term);
  }
  SurfaceLight light = LightWith(p, first.irradiance);
  SetNoise(light, p.surface, enclosed ? 0.0f : p.areaRatio, gap ? &*gap : nullptr, first, sum);
  if (gap && gap->estimates) light.gap = {p.surface, gap->estimates->first, gap->estimates->second, rest};
  return light;
}

std::vector<std::byte> IrradianceField::LateState() const {
  const size_t surfaces = scene_->surfaces.surfaces.size();
  const std::span<const uint32_t> left = SmallLeftOut();
  std::vector<std::byte> bytes(surfaces * sizeof(GapWeight) + left.size());
  for (size_t s = 0; s < surfaces; ++s) {
    const GapWeight w = GapWeightOf(uint32_t(s));
    std::memcpy(bytes.data() + s * sizeof(GapWeight), &w, sizeof w);
  }
  for (size_t k = 0; k < left.size(); ++k)
    bytes[surfaces * sizeof(GapWeight) + k] = std::byte(gaps_->GatheredAtPoints(left[k]) ? 1 : 0);
  return bytes;
}

void IrradianceField::SetLateState(std::span<const std::byte> bytes) {
  const size_t surfaces = scene_->surfaces.surfaces.size();
  const std::span<const uint32_t> left = SmallLeftOut();
  PB_CHECK_EQ(bytes.size(), surfaces * sizeof(GapWeight) + left.size());
  gapWeights_.resize(surfaces);
  for (size_t s = 0; s < surfaces; ++s) std::memcpy(&gapWeights_[s], bytes.data() + s * sizeof(GapWeight), sizeof(GapWeight));
  for (size_t k = 0; k < left.size(); ++k)
    gaps_->GatherAtPoints(left[k], bytes[surfaces * sizeof(GapWeight) + k] != std::byte(0));
}

void IrradianceField::TakeRankZerosLateState(const Distribution& distribution) {
  std::vector<std::byte> bytes = LateState();
  distribution.Broadcast(bytes);
  SetLateState(bytes);
}

void IrradianceField::WeighGaps(const std::vector<GapPair>& pairs) {
  const size_t surfaces = scene_->surfaces.surfaces.size();
  const std::vector<GapWeight> learned = LearnGapWeights(pairs, surfaces);
  gapWeights_.resize(surfaces);
  for (size_t s = 0; s < surfaces; ++s)
    if (learned[s].vertices > 0) gapWeights_[s] = learned[s];
}

void IrradianceField::Remix(SurfaceLight& light) const {
  if (!light.gap.Present()) return;
  const GapPair& pair = light.gap;
  const GapTerm gap{Blend(pair.gathered, pair.photons, GapWeightOf(pair.surface).alpha), std::pair(pair.gathered, pair.photons)};
  IndependentSum sum(gap.blended.value);
  sum.Add(pair.rest);
  SetNoise(light, pair.surface, 1.0f, &gap, gap.blended.value, sum);
}

namespace {

constexpr uint32_t kGuideNeighbours = 800;  // photons per map, render's default (docs/render.md, "Settings")

// The guide's importance maps: `photons` traced from a stream family of their own, their first hits left out (the
// gathered paths' first directions look for light that has scattered), cached as render caches them.
std::unique_ptr<ImportanceCache> GuideMaps(const PreparedScene& scene, uint64_t photons, uint64_t seed) {
  const TraceSettings trace{photons, SplitMix64(seed ^ 0x67756964652d6d61ull), kDefaultMaxBounces, false};
  return std::make_unique<ImportanceCache>(MapPhotonsOf(scene.scene, TracePhotons(scene, trace, Log(true))),
                                           MapSettings{kGuideNeighbours, 4, 8, 0.3f});
}

}  // namespace

namespace {

// Adds to `field` the terms at the points that `settings` asks for.
void AddSampledTerms(IrradianceField& field, const PreparedScene& scene, const FieldSettings& settings, StageClock& clock) {
  const bool gathers = settings.referencePaths > 0 || (settings.direct.mode == DirectLight::kSampled && settings.gaps.paths > 0);
  const ImportanceCache* guide =
      gathers && settings.guidePhotons > 0
          ? field.Guide(clock.Time("guide maps", [&] { return GuideMaps(scene, settings.guidePhotons, settings.seed); }))
          : nullptr;
  if (settings.referencePaths > 0)
    field.Add(std::make_unique<ReferenceIrradiance>(scene, settings.referencePaths, settings.seed, guide));
  else if (settings.direct.mode == DirectLight::kSampled) {
    auto direct = clock.Time("lights", [&] { return std::make_unique<DirectIrradiance>(scene, settings.direct, settings.seed); });
    const LightSampler& lights = direct->Sampler();  // owned by the field from here on
    field.Add(std::move(direct));
    if (settings.gaps.paths > 0)
      field.GatherGaps(std::make_unique<GapGather>(scene, field.Photons(), lights, settings.gaps, settings.seed, guide));
  }
}

}  // namespace

IrradianceField BuildIrradianceField(const PreparedScene& scene, const SurfaceBins& bins, const FieldSettings& settings,
                                     StageClock& clock, const Log* log) {
  const EstimatorSettings& estimator = settings.estimator;
  std::vector<float> bandwidths = clock.Time("bandwidth", [&] {
    return settings.heldBandwidths.empty()
               ? SurfaceBandwidths(scene.regions, bins, estimator, log)
               : settings.heldBandwidths;
  });
  IrradianceField field = clock.Time("estimators", [&] {
    return IrradianceField(scene, std::make_unique<PhotonIrradiance>(scene, bins, estimator, std::move(bandwidths), log, settings.pool));
  });
  AddSampledTerms(field, scene, settings, clock);
  return field;
}

IrradianceField WithSampledTerms(IrradianceField field, const PreparedScene& scene, const FieldSettings& settings,
                                 StageClock& clock) {
  IrradianceField rebuilt(scene, std::move(field).TakePhotons());
  AddSampledTerms(rebuilt, scene, settings, clock);
  return rebuilt;
}

namespace {

// A stride coprime to `count` near its golden section: k -> k * stride mod count visits every one of count items
// once, neighbours far apart.
size_t ScatteringStride(size_t count) {
  size_t stride = std::max<size_t>(1, size_t(0.6180339887 * double(count)));
  while (std::gcd(stride, count) != 1) ++stride;
  return stride;
}

// Calls f(v, point of v) for every vertex of `mesh`, in chunks of kVertexChunk in parallel, with `title`'s progress
// on `log`; with `owns`, only in the chunks it owns. The chunks are taken in a scattered order: the vertices come
// surface by surface, and a point in a room lit through a door can cost 20 times one in the lit room, so in order
// the progress line's rate (the lit room's) foretold "2 s left" for 35 s, and a time budget that cut the last
// chunks short cut one part of the scene. A vertex's light is its own (seeded by the vertex), so the order changes
// no value.
template <typename F>
void ForEachVertex(const SplitMesh& mesh, const Log& log, const char* title, const std::function<bool(size_t)>& owns,
                   F f) {
  const size_t n = mesh.VertexCount(), chunks = (n + kVertexChunk - 1) / kVertexChunk;
  const size_t stride = ScatteringStride(chunks);
  Progress progress(log, title, n);
  tbb::parallel_for(size_t(0), chunks, [&](size_t k) {
    const size_t c = size_t(uint64_t(k) * stride % chunks);  // chunks < 2^32: no overflow
    const size_t begin = c * kVertexChunk, end = std::min(n, begin + kVertexChunk);
    if (!owns || owns(c))
      for (size_t v = begin; v != end; ++v) f(v, mesh.Point(v));
    progress.Advance(end - begin);
  });
}

}  // namespace

BakedMesh EstimateIrradiance(const IrradianceField& field, SplitMesh mesh, const Log& log, bool withNoise,
                             const std::function<bool(size_t)>& owns) {
  BakedMesh baked;
  const size_t n = mesh.VertexCount();
  baked.irradiance.resize(n);
  baked.albedo.resize(n);
  baked.emitted.resize(n);
  if (withNoise)
    baked.irradianceNoise.assign(n, 0.0), baked.photonVarianceShare.assign(n, 1.0), baked.sampledShare.assign(n, 0.0),
        baked.irradianceBias.assign(n, 0.0), baked.gatheredVarianceShare.assign(n, 0.0), baked.gapPairs.assign(n, {});
  ForEachVertex(mesh, log, "estimate irradiance", owns, [&](size_t v, const SurfacePoint& p) {
    SetVertexLight(baked, v, withNoise ? field.LightWithNoise(p) : field.Light(p));
  });
  baked.mesh = std::move(mesh);
  return baked;
}

void SetVertexLight(BakedMesh& baked, size_t v, const SurfaceLight& light) {
  baked.irradiance[v] = light.irradiance;
  baked.albedo[v] = light.albedo;
  baked.emitted[v] = light.emitted;
  if (baked.irradianceNoise.empty()) return;
  baked.irradianceNoise[v] = light.relativeNoise, baked.photonVarianceShare[v] = light.photonVarianceShare;
  baked.sampledShare[v] = light.sampledShare, baked.irradianceBias[v] = light.relativeBias;
  baked.gatheredVarianceShare[v] = light.gatheredVarianceShare;
  if (!baked.gapPairs.empty()) baked.gapPairs[v] = light.gap;
}

void WeighGatheredPaths(IrradianceField& field, BakedMesh& baked) {
  if (baked.gapPairs.empty()) return;
  field.WeighGaps(baked.gapPairs);
  for (size_t v = 0; v < baked.gapPairs.size(); ++v) {
    if (!baked.gapPairs[v].Present()) continue;
    SurfaceLight light{baked.irradiance[v], baked.albedo[v], baked.emitted[v]};
    light.gap = baked.gapPairs[v];
    field.Remix(light);
    SetVertexLight(baked, v, light);
  }
  baked.gapPairs = {};
}

void EstimateDirections(const IrradianceField& field, BakedMesh& baked, const Log& log) {
  const size_t n = baked.mesh.VertexCount();
  baked.sh.resize(n), baked.directionNoise.resize(n);
  ForEachVertex(baked.mesh, log, "estimate directions", {}, [&](size_t v, const SurfacePoint& p) {
    const IncidentMoments moments = field.Moments(p);
    baked.sh[v] = ShProjection(moments, p.normal, baked.irradiance[v]);
    baked.directionNoise[v] = DirectionNoise(moments, p.normal, baked.irradiance[v]);
  });
}

}  // namespace pb
