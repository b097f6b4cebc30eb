#include "baker/photon_store.h"

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
  std::vector<TraceStats> perLight(emitted.size());
  for (size_t b = 0; b < blocks.size(); ++b)
    perLight[ranges[b].light].Add(blockStats[b]);  // in block order: the sums do not depend on threads
  stats = TraceStats{};
  for (size_t l = 0; l < emitted.size(); ++l) stats.Add(perLight[l], PhotonFlux(l));
}

}  // namespace pb
