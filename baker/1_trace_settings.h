// Stage 1 as the command line sets it beyond the photon count and seed: the bounce limit (--max-bounces). The
// tracer itself is baker/1_trace_photons.h.
#pragma once

#include <cstdint>

namespace pb {

// The default bounce limit, --max-bounces: unlimited in practice, since Russian roulette ends a path long before
// (a path survives 10,000 bounces of albedo 0.99 with probability 2e-44); it only stops a closed white box.
inline constexpr uint32_t kDefaultMaxBounces = 10'000;

}  // namespace pb
