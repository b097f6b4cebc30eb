// Uniform random numbers in [0, 1) from PCG32: O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient
// Statistically Good Algorithms for Random Number Generation" (the XSH-RR 64/32 member).
//
// Determinism: Rng(seed, index) is the stream of photon (or path) `index`, a pure function of (seed, index).
// Both are scrambled with SplitMix64 (Steele et al. 2014) before seeding, so neighbouring indices give
// unrelated streams. Results therefore do not depend on which thread traces which photon.
#pragma once

#include <cstdint>

#include "mesh/geometry.h"

namespace pb {

inline uint64_t SplitMix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

class Rng {
 public:
  Rng(uint64_t seed, uint64_t index) {
    const uint64_t key = SplitMix64(seed ^ SplitMix64(index));
    increment_ = (SplitMix64(key + index) << 1u) | 1u;  // any odd increment selects a stream
    state_ = 0;
    NextU32();
    state_ += key;
    NextU32();
  }

  uint32_t NextU32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + increment_;
    const auto xorShifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const auto rotation = uint32_t(old >> 59u);
    return (xorShifted >> rotation) | (xorShifted << ((-rotation) & 31u));
  }

  // 24 random bits, so every value is exactly representable and the result is strictly below 1.
  float Uniform() { return float(NextU32() >> 8) * 0x1p-24f; }
  Point2 Uniform2() {
    const float a = Uniform();
    return {a, Uniform()};
  }

 private:
  uint64_t state_ = 0;
  uint64_t increment_ = 1;
};

// A pilot's stream of its own, drawn from `rng`: an adaptive count's pilot (LightSampler::AdaptiveIrradiance,
// IrradianceGatherer::AdaptiveScatteredIrradiance) must not share the numbers of the samples it sizes.
inline Rng PilotStream(Rng& rng) {
  const uint64_t seed = (uint64_t(rng.NextU32()) << 32) | rng.NextU32();
  return Rng(seed, 0x70696c6f74ull);  // "pilot"
}

}  // namespace pb
