#include "baker/photon_store.h"

#include "mesh/errors.h"

namespace pb {

void TraceStats::Add(const TraceStats& b, Rgb flux) {
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
  const auto add = [&](RgbSum& to, const RgbSum& from) {
    to.r += double(flux.r) * from.r;
    to.g += double(flux.g) * from.g;
    to.b += double(flux.b) * from.b;
  };
  add(fluxEmitted, b.fluxEmitted);
  add(fluxAbsorbed, b.fluxAbsorbed);
  add(fluxEscaped, b.fluxEscaped);
  add(fluxForbidden, b.fluxForbidden);
}

void PhotonStore::Summarise() {
  // Blocks are ordered by light: each light's blocks are summed in block order (so the sums do not depend on
  // threads), then added in watts. No array per light: 100,000 LEDs made that 18 MB zeroed at every call.
  stats = TraceStats{};
  for (size_t b = 0; b < blocks.size();) {
    const uint32_t light = ranges[b].light;
    PB_CHECK(b == 0 || ranges[b - 1].light < light, "photon blocks out of light order");
    TraceStats sum;
    for (; b < blocks.size() && ranges[b].light == light; ++b) sum.Add(blockStats[b]);
    stats.Add(sum, PhotonFlux(light));
  }
}

}  // namespace pb
