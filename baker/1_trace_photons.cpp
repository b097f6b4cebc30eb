#include "baker/1_trace_photons.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "estimators/emission.h"
#include "estimators/lambertian.h"
#include "estimators/rng.h"

namespace pb {
namespace {

// Photons per block: the unit of parallel work and of deterministic ordering.
constexpr uint64_t kBlockPhotons = 4096;

struct Block {
  std::vector<PhotonHit> hits;
  TraceStats stats;
};

class PhotonTracer {
 public:
  PhotonTracer(const Scene& scene, const RayScene& rays, uint32_t maxBounces)
      : scene_(scene), rays_(rays), maxBounces_(maxBounces) {}

  // Traces one photon from `light` with the flux `power` [W], appending its hits to `block`.
  void Trace(const AreaLight& light, Rgb power, Rng& rng, Block& block) const {
    const EmissionSample e = SampleEmission(scene_, light, rng);
    block.stats.powerEmitted.Add(power);
    ++block.stats.emitted;
    Point3 origin = rays_.SpawnPoint(e.position, e.normal);
    Vector3 direction = e.direction;
    for (uint32_t bounce = 0; bounce < maxBounces_; ++bounce) {
      const auto hit = rays_.Intersect(origin, direction);
      if (!hit) {
        ++block.stats.escaped;
        block.stats.powerEscaped.Add(power);
        return;
      }
      const Normal3 front = scene_.FrontNormal(hit->triangle);
      const bool onFront = Dot(direction, front) < 0;
      const Normal3 side = onFront ? front : -front;  // the side the photon arrived on
      const Point3 p = scene_.PointAt(hit->triangle, hit->b1, hit->b2);
      block.hits.emplace_back(power, -direction, hit->triangle, onFront, hit->b1, hit->b2);
      const Rgb albedo = scene_.MaterialOf(hit->triangle).albedo;
      block.stats.powerAbsorbed.Add(power * (Rgb{1, 1, 1} - albedo));
      const float survival = albedo.Max();
      if (rng.Uniform() >= survival) {
        ++block.stats.absorbed;
        return;
      }
      const BsdfSample s = SampleLambertian(albedo, side, rng.Uniform2());
      power = power * s.weight / survival;
      origin = rays_.SpawnPoint(p, side);
      direction = s.wi;
    }
    ++block.stats.truncated;
  }

 private:
  const Scene& scene_;
  const RayScene& rays_;
  uint32_t maxBounces_;
};

}  // namespace

void TraceStats::Add(const TraceStats& b) {
  emitted += b.emitted;
  hits += b.hits;
  absorbed += b.absorbed;
  escaped += b.escaped;
  truncated += b.truncated;
  powerEmitted.Add(b.powerEmitted);
  powerAbsorbed.Add(b.powerAbsorbed);
  powerEscaped.Add(b.powerEscaped);
}

PhotonHits TracePhotons(const Scene& scene, const std::vector<AreaLight>& lights,
                        const RayScene& rays, const TraceSettings& settings, const Log& log) {
  const std::vector<uint64_t> perLight = AllocatePhotons(lights, settings.photons);
  std::vector<uint64_t> firstPhotonOf(lights.size() + 1, 0);  // photon i belongs to light l when
  for (size_t l = 0; l < lights.size(); ++l) firstPhotonOf[l + 1] = firstPhotonOf[l] + perLight[l];
  std::vector<Rgb> photonPower(lights.size());
  for (size_t l = 0; l < lights.size(); ++l)
    photonPower[l] = perLight[l] ? lights[l].Power() / float(perLight[l]) : Rgb{};

  const PhotonTracer tracer(scene, rays, settings.maxBounces);
  const uint64_t blockCount = (settings.photons + kBlockPhotons - 1) / kBlockPhotons;
  std::vector<Block> blocks(blockCount);
  Progress progress(log, "trace photons", settings.photons);
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, blockCount, 1), [&](const tbb::blocked_range<uint64_t>& r) {
    for (uint64_t b = r.begin(); b != r.end(); ++b) {
      blocks[b].hits.reserve(kBlockPhotons * 3);  // ~2.5 hits per photon in a box: growth copies are rare
      const uint64_t begin = b * kBlockPhotons, end = std::min(settings.photons, begin + kBlockPhotons);
      size_t light = size_t(std::upper_bound(firstPhotonOf.begin(), firstPhotonOf.end(), begin) - firstPhotonOf.begin()) - 1;
      for (uint64_t i = begin; i < end; ++i) {
        while (i >= firstPhotonOf[light + 1]) ++light;
        Rng rng(settings.seed, i);
        tracer.Trace(lights[light], photonPower[light], rng, blocks[b]);
      }
      blocks[b].stats.hits = blocks[b].hits.size();
      progress.Advance(end - begin);
    }
  });

  PhotonHits result;
  result.stats.photonsPerLight = perLight;
  for (Block& b : blocks) {
    result.stats.Add(b.stats);  // in block order: the double sums do not depend on threads
    result.blocks.push_back(std::move(b.hits));
  }
  return result;
}

}  // namespace pb
