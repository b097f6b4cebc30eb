// Each light's photons form one stream of its own, stored by attenuation (baker/1_trace_photons.h): a store
// extended from n to m photons holds the same bytes as one traced with m at once, the flux in the store is the
// lights' total at every step, and an interrupted extension keeps every light's photons a prefix of its stream.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstring>
#include <random>
#include <thread>

#include "baker/runtime/interrupt.h"
#include "estimators/emission.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

void ExpectSameSum(const RgbSum& a, const RgbSum& b, const char* what) {
  EXPECT_EQ(a.r, b.r) << what;
  EXPECT_EQ(a.g, b.g) << what;
  EXPECT_EQ(a.b, b.b) << what;
}

// Byte-identical hits, identical ranges, and stats equal to the last bit.
void ExpectSameStore(const PhotonStore& a, const PhotonStore& b) {
  ASSERT_EQ(a.emitted, b.emitted);
  ASSERT_EQ(a.blocks.size(), b.blocks.size());
  for (size_t k = 0; k < a.blocks.size(); ++k) {
    ASSERT_EQ(a.ranges[k].light, b.ranges[k].light);
    ASSERT_EQ(a.ranges[k].first, b.ranges[k].first);
    ASSERT_EQ(a.ranges[k].end, b.ranges[k].end);
    ASSERT_EQ(a.blocks[k].size(), b.blocks[k].size()) << "block " << k;
    ASSERT_EQ(0, std::memcmp(a.blocks[k].data(), b.blocks[k].data(), a.blocks[k].size() * sizeof(PhotonHit)))
        << "block " << k;
  }
  EXPECT_EQ(a.stats.hits, b.stats.hits);
  EXPECT_EQ(a.stats.absorbed, b.stats.absorbed);
  ExpectSameSum(a.stats.fluxEmitted, b.stats.fluxEmitted, "emitted");
  ExpectSameSum(a.stats.fluxAbsorbed, b.stats.fluxAbsorbed, "absorbed");
  ExpectSameSum(a.stats.fluxEscaped, b.stats.fluxEscaped, "escaped");
}

// The flux the store's photons left their lights with is the lights' total flux.
void ExpectStoreFluxIsLightFlux(const test::TracedScene& s, const PhotonStore& store) {
  double phi = 0;
  for (const Light& light : s.lights) phi += light.Power().g;
  EXPECT_NEAR(store.stats.fluxEmitted.g, phi, 1e-6 * phi);
}

PhotonStore ExtendedStore(const test::TracedScene& s, const std::vector<uint64_t>& steps, uint64_t seed) {
  PhotonStore store = s.Trace(steps[0], seed);
  ExpectStoreFluxIsLightFlux(s, store);
  for (size_t i = 1; i < steps.size(); ++i) {
    EXPECT_TRUE(ExtendPhotons(store, s, {steps[i], seed}, Log(true)));
    ExpectStoreFluxIsLightFlux(s, store);
  }
  return store;
}

TEST(PhotonStreams, ExtendingTheBoxEqualsTracingAtOnce) {
  const test::TracedScene box(PB_SOURCE_DIR "/data/box/box.obj");
  ASSERT_EQ(box.lights.size(), 2u);
  // 100k leaves each light a partial block, which 250k continues in place.
  const PhotonStore extended = ExtendedStore(box, {100'000, 250'000, 400'000}, 5);
  ExpectSameStore(extended, box.Trace(400'000, 5));
}

TEST(PhotonStreams, ExtendingTwoLightsOfVeryDifferentPowerEqualsTracingAtOnce) {
  const std::string dir = test::TempDirectory("streams-two-lights");
  // Same radiance, areas 0.0025 and 1 m^2: the big lamp has 400 times the power; the small one gets 249
  // photons of 100k (a partial first block), then 997 of 400k.
  const test::TracedScene s(test::WriteFloorWithLamps(dir, 0.5f, 2.0f, {{-1.0f, -0.95f, 0, 0.05f, 1}, {0, 1, 0, 1, 1}}));
  ASSERT_EQ(s.lights.size(), 2u);
  const PhotonStore extended = ExtendedStore(s, {100'000, 400'000}, 7);
  EXPECT_LT(extended.emitted[0] * 300, extended.emitted[1]);
  ExpectSameStore(extended, s.Trace(400'000, 7));
}

// ExtendPhotons with a Ctrl-C (RequestInterrupt, from another thread) `milliseconds` after it starts; returns
// whether the extension completed.
bool ExtendInterrupted(PhotonStore& store, const PreparedScene& scene, const TraceSettings& settings, int milliseconds) {
  const InterruptScope scope;
  std::thread ctrlC([milliseconds] {
    std::this_thread::sleep_for(std::chrono::milliseconds(milliseconds));
    RequestInterrupt();
  });
  const bool complete = ExtendPhotons(store, scene, settings, Log(true));
  ctrlC.join();
  return complete;
}

TEST(PhotonStreams, AnInterruptedExtensionKeepsAPrefixOfEachStreamAndResumesExactly) {
  const test::TracedScene box(PB_SOURCE_DIR "/data/box/box.obj");
  PhotonStore store = box.Trace(100'000, 3);
  EXPECT_FALSE(ExtendInterrupted(store, box, {1'500'000, 3}, 10)) << "1.5M photons took under 10 ms";
  uint64_t hits = 0;
  std::vector<uint64_t> next(box.lights.size(), 0);
  for (size_t k = 0; k < store.blocks.size(); ++k) {
    const BlockRange& r = store.ranges[k];
    EXPECT_EQ(r.first, next[r.light]) << "a gap in light " << r.light << "'s stream";
    next[r.light] = r.end;
    hits += store.blocks[k].size();
  }
  EXPECT_EQ(next, store.emitted);
  EXPECT_EQ(hits, store.stats.hits);
  ExpectStoreFluxIsLightFlux(box, store);
  ASSERT_TRUE(ExtendPhotons(store, box, {1'500'000, 3}, Log(true)));
  ExpectSameStore(store, box.Trace(1'500'000, 3));
}

// Lights are traced interleaved: interrupted part-way, two lamps of equal power each keep about the same share of
// their photons (within the blocks in flight), where tracing them one after the other left the second with none.
TEST(PhotonStreams, AnInterruptionLeavesEveryLightItsShare) {
  const test::TracedScene lamps(test::WriteFloorWithLamps(test::TempDirectory("streams-interleaved"), 0.5f, 1.0f,
                                                          {{-1.5f, -0.5f, -0.5f, 0.5f, 1}, {0.5f, 1.5f, -0.5f, 0.5f, 1}}));
  ASSERT_EQ(lamps.lights.size(), 2u);
  PhotonStore store = EmptyPhotonStore(lamps.lights);
  ASSERT_FALSE(ExtendInterrupted(store, lamps, {200'000'000, 3}, 50)) << "200M photons took under 50 ms";
  const uint64_t inFlight = kBlockPhotons * uint64_t(std::max(2, tbb::this_task_arena::max_concurrency()));
  EXPECT_GT(store.emitted[0], 0u);
  EXPECT_GT(store.emitted[1], 0u);
  EXPECT_LE(std::max(store.emitted[0], store.emitted[1]) - std::min(store.emitted[0], store.emitted[1]), inFlight)
      << store.emitted[0] << " and " << store.emitted[1] << " photons";
}

TEST(PhotonStreams, EachLightsCountNeverShrinksAsTheTotalGrows) {
  std::mt19937 random(11);
  std::uniform_real_distribution<float> radiance(0.01f, 10.0f);
  std::vector<Light> lights(7);
  for (Light& l : lights) {
    l.radiance = {radiance(random), radiance(random), radiance(random)};
    l.area = radiance(random);
  }
  std::vector<uint64_t> previous(lights.size(), 0);
  for (uint64_t n = 1; n < 20'000; n += 1 + n / 50) {
    const std::vector<uint64_t> counts = AllocatePhotons(lights, n);
    uint64_t sum = 0;
    for (size_t l = 0; l < lights.size(); ++l) {
      ASSERT_GE(counts[l], previous[l]) << "light " << l << " at n = " << n;
      sum += counts[l];
    }
    ASSERT_LE(sum, n);
    ASSERT_GT(sum + lights.size(), n);
    previous = counts;
  }
}

}  // namespace
}  // namespace pb
