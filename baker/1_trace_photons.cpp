#include "baker/1_trace_photons.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "estimators/emission.h"
#include "estimators/scatter.h"
#include "estimators/rng.h"

namespace pb {
namespace {


struct Block {
  HitBlock hits;
  TraceStats stats;
};

// The photon loop. kInterreflect: diffuse surfaces scatter (else a photon ends at its first diffuse surface).
// kSpecular: materials of every class are sampled, with mirror and glass events (else every surface is
// treated as the diffuse class, which the plan guarantees it is).
template <bool kInterreflect, bool kSpecular>
class PhotonTracer {
 public:
  PhotonTracer(const Scene& scene, const RayScene& rays, const TransportPlan& plan, uint32_t maxBounces)
      : scene_(scene), rays_(rays), maxBounces_(maxBounces), reflection_(plan.On(Effect::kReflection)),
        refraction_(plan.On(Effect::kRefraction)), caustics_(plan.On(Effect::kCaustics)) {}

  // Traces one photon from `light` with the flux `power` [W], appending its hits to `block`.
  void Trace(const AreaLight& light, Rgb power, Rng& rng, Block& block) const {
    const EmissionSample e = SampleEmission(scene_, light, rng);
    block.stats.powerEmitted.Add(power);
    ++block.stats.emitted;
    Point3 origin = rays_.SpawnPoint(e.position, e.normal);
    Vector3 direction = e.direction;
    bool afterSpecular = false;
    for (uint32_t bounce = 0; bounce < maxBounces_; ++bounce) {
      const auto hit = rays_.Intersect(origin, direction);
      if (!hit) return Escape(power, block.stats);
      const Normal3 front = scene_.FrontNormal(hit->triangle);
      const bool onFront = Dot(direction, front) < 0;
      const Normal3 side = onFront ? front : -front;  // the side the photon arrived on
      const Material& material = scene_.MaterialOf(hit->triangle);
      if (kSpecular && afterSpecular && !material.IsSpecular()) {
        if (!caustics_) return Forbid(power, block.stats);
        ++block.stats.causticHits;
      }
      block.hits.emplace_back(power, -direction, hit->triangle, onFront, hit->b1, hit->b2);
      const Rgb albedo = scene_.AlbedoAt(material, hit->triangle, hit->b1, hit->b2);
      if constexpr (!kInterreflect && !kSpecular) return StopAtFirstSurface(albedo, power, block.stats);
      const float uEvent = rng.Uniform();
      const Point2 uDirection = rng.Uniform2();
      const ScatterSample s = kSpecular ? SampleScatter(material, albedo, -direction, front, TransportMode::kImportance,
                                                        uEvent, uDirection)
                                        : ScatterDiffuse(albedo, side, uEvent, uDirection);
      block.stats.powerAbsorbed.Add(power * s.expectedAbsorbed);
      if (s.Absorbed()) {
        ++block.stats.absorbed;
        return;
      }
      power = power * s.weight;
      if (!Allowed(s.event)) return Forbid(power, block.stats);
      Count(s.event, block.stats);
      origin = rays_.SpawnPoint(scene_.PointAt(hit->triangle, hit->b1, hit->b2), s.transmitted ? -side : side);
      direction = s.wi;
      afterSpecular = s.Specular();
    }
    ++block.stats.truncated;
  }

 private:
  static void Escape(Rgb power, TraceStats& stats) {
    ++stats.escaped;
    stats.powerEscaped.Add(power);
  }
  static void Forbid(Rgb power, TraceStats& stats) {
    ++stats.forbidden;
    stats.powerForbidden.Add(power);
  }
  // Without interreflection: the absorbed and the forbidden (reflected) parts are tallied in expectation.
  static void StopAtFirstSurface(Rgb albedo, Rgb power, TraceStats& stats) {
    stats.powerAbsorbed.Add(power * (Rgb{1, 1, 1} - albedo));
    stats.powerForbidden.Add(power * albedo);
    ++(albedo.IsBlack() ? stats.absorbed : stats.forbidden);
  }
  bool Allowed(ScatterEvent event) const {
    switch (event) {
      case ScatterEvent::kDiffuse: return kInterreflect;
      case ScatterEvent::kMirror:
      case ScatterEvent::kFresnelReflection: return reflection_;
      case ScatterEvent::kRefraction: return refraction_;
      case ScatterEvent::kAbsorbed: break;
    }
    return false;
  }
  static void Count(ScatterEvent event, TraceStats& stats) {
    if constexpr (!kSpecular) {
      ++stats.diffuseBounces;
      return;
    }
    switch (event) {
      case ScatterEvent::kDiffuse: ++stats.diffuseBounces; break;
      case ScatterEvent::kMirror: ++stats.mirrorReflections; break;
      case ScatterEvent::kFresnelReflection: ++stats.fresnelReflections; break;
      case ScatterEvent::kRefraction: ++stats.refractions; break;
      case ScatterEvent::kAbsorbed: break;
    }
  }

  const Scene& scene_;
  const RayScene& rays_;
  uint32_t maxBounces_;
  bool reflection_, refraction_, caustics_;
};

// Photons per light and the flux each carries [W].
struct PhotonSchedule {
  std::vector<uint64_t> perLight;
  std::vector<Rgb> photonPower;  // [W] per photon of each light

  PhotonSchedule(const std::vector<AreaLight>& lights, const TransportPlan& plan, uint64_t photons)
      : perLight(AllocatePhotons(lights, photons, plan.lightReaches)), photonPower(lights.size()) {
    for (size_t l = 0; l < lights.size(); ++l)
      photonPower[l] = perLight[l] ? lights[l].Power() / float(perLight[l]) : Rgb{};
  }
};

// The unit of work: photons [first, end) of one light's stream, aligned to kBlockPhotons within that stream, so
// that a light's first blocks are the same whatever the photon count.
struct BlockRange {
  size_t light;
  uint64_t first, end;
};

std::vector<BlockRange> BlockRanges(const std::vector<uint64_t>& perLight) {
  std::vector<BlockRange> ranges;
  for (size_t l = 0; l < perLight.size(); ++l)
    for (uint64_t first = 0; first < perLight[l]; first += kBlockPhotons)
      ranges.push_back({l, first, std::min(perLight[l], first + kBlockPhotons)});
  return ranges;
}

template <typename Tracer>
std::vector<Block> TraceBlocks(const Tracer& tracer, const std::vector<AreaLight>& lights,
                               const PhotonSchedule& schedule, const std::vector<BlockRange>& ranges,
                               const TraceSettings& settings, const Log& log) {
  std::vector<Block> blocks(ranges.size());
  uint64_t total = 0;
  for (uint64_t n : schedule.perLight) total += n;
  Progress progress(log, "trace photons", total);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, ranges.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t b = r.begin(); b != r.end(); ++b) {
      const BlockRange& range = ranges[b];
      blocks[b].hits.reserve(kBlockPhotons * 3);  // ~2.5 hits per photon in a box: growth copies are rare
      for (uint64_t j = range.first; j < range.end; ++j) {
        Rng rng(settings.seed, PhotonStream(range.light, j));
        tracer.Trace(lights[range.light], schedule.photonPower[range.light], rng, blocks[b]);
      }
      blocks[b].stats.hits = blocks[b].hits.size();
      progress.Advance(range.end - range.first);
    }
  });
  return blocks;
}

}  // namespace

void TraceStats::Add(const TraceStats& b) {
  emitted += b.emitted;
  hits += b.hits;
  absorbed += b.absorbed;
  escaped += b.escaped;
  forbidden += b.forbidden;
  truncated += b.truncated;
  diffuseBounces += b.diffuseBounces;
  mirrorReflections += b.mirrorReflections;
  fresnelReflections += b.fresnelReflections;
  refractions += b.refractions;
  causticHits += b.causticHits;
  powerEmitted.Add(b.powerEmitted);
  powerAbsorbed.Add(b.powerAbsorbed);
  powerEscaped.Add(b.powerEscaped);
  powerForbidden.Add(b.powerForbidden);
}

PhotonHits TracePhotons(const Scene& scene, const std::vector<AreaLight>& lights, const RayScene& rays,
                        const TransportPlan& plan, const TraceSettings& settings, const Log& log) {
  const PhotonSchedule schedule(lights, plan, settings.photons);
  const std::vector<BlockRange> ranges = BlockRanges(schedule.perLight);
  const auto run = [&]<bool kInterreflect, bool kSpecular>() {
    const PhotonTracer<kInterreflect, kSpecular> tracer(scene, rays, plan, settings.maxBounces);
    return TraceBlocks(tracer, lights, schedule, ranges, settings, log);
  };
  const bool bounce = plan.On(Effect::kInterreflection), specular = plan.NeedsSpecularKernel();
  std::vector<Block> blocks = specular ? (bounce ? run.template operator()<true, true>()
                                                 : run.template operator()<false, true>())
                                       : (bounce ? run.template operator()<true, false>()
                                                 : run.template operator()<false, false>());
  PhotonHits result;
  result.stats.photonsPerLight = schedule.perLight;
  for (size_t b = 0; b < blocks.size(); ++b) {
    result.stats.Add(blocks[b].stats);  // in block order: the double sums do not depend on threads
    result.blocks.push_back(std::move(blocks[b].hits));
    result.blockLight.push_back(uint32_t(ranges[b].light));
  }
  return result;
}

}  // namespace pb
