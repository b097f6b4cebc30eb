// Photons binned while they are traced (baker/2_bin_photons.h, PhotonBinner):
// - on the 25 mm Cornell box, blocks on the floor and their covered parts included, a bake that bins its photons as
//   they are traced writes the same bytes on one and two threads as a bake that stores them (--save-photons) and
//   bins them afterwards; at h = 0.05 m every surface is binned and no hit is stored, at h = 0.1 m the blocks'
//   faces (0.165 m, narrower than 2 h) keep theirs, and the result is still the same;
// - the report's per-surface tallies (hits, mean irradiance) are those of the stored bake;
// - Ctrl-C during such a bake stops it with a message and writes nothing (the photons' flux was binned for the
//   photon count planned), while an earlier output survives.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <thread>

#include "baker/bake.h"
#include "baker/runtime/interrupt.h"
#include "mesh/errors.h"
#include "tests/ply_reader.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

BakeOptions BoxOptions(const std::string& output, float h, unsigned threads) {
  BakeOptions o;
  o.scenePath = PB_SOURCE_DIR "/data/box/box_25mm.obj";
  o.outputPath = output;
  o.photons = 400'000;
  o.direct.mode = DirectLight::kPhotons;  // every hit on the surfaces: the photons carry all of the light
  o.estimator.bandwidth = h;
  o.threads = threads;
  o.quiet = true;
  return o;
}

class BinnedWhileTraced : public testing::TestWithParam<float> {};

TEST_P(BinnedWhileTraced, EqualsTheStoredBakeOnAnyThreadCount) {
  const float h = GetParam();
  const std::string dir = test::TempDirectory("binned-while-traced");
  const BakeReport two = Bake(BoxOptions(dir + "/two.ply", h, 2), Log(true));
  const BakeReport one = Bake(BoxOptions(dir + "/one.ply", h, 1), Log(true));
  BakeOptions storing = BoxOptions(dir + "/stored.ply", h, 2);
  storing.savePhotonsPath = dir + "/box.photons";
  const BakeReport stored = Bake(storing, Log(true));

  EXPECT_EQ(stored.storedHits, stored.trace.hits) << "--save-photons keeps every hit";
  EXPECT_LT(two.storedHits, stored.storedHits / 4) << "the binned surfaces' hits are not kept";
  if (h == 0.05f) {
    EXPECT_EQ(two.storedHits, 0u) << "every surface of the box is 2 h wide";
  }
  if (h == 0.1f) {
    EXPECT_GT(two.storedHits, 0u) << "the blocks' faces are narrower than 2 h";
  }
  const std::string bytes = test::ReadBytes(dir + "/stored.ply");
  EXPECT_TRUE(test::ReadBytes(dir + "/two.ply") == bytes) << "binned while traced, 2 threads";
  EXPECT_TRUE(test::ReadBytes(dir + "/one.ply") == bytes) << "binned while traced, 1 thread";
  ASSERT_EQ(two.surfaces.size(), stored.surfaces.size());
  for (size_t s = 0; s < two.surfaces.size(); ++s) {
    EXPECT_EQ(two.surfaces[s].frontHits, stored.surfaces[s].frontHits) << "surface " << s;
    EXPECT_EQ(two.surfaces[s].backHits, stored.surfaces[s].backHits) << "surface " << s;
    EXPECT_EQ(two.surfaces[s].photonIrradiance, stored.surfaces[s].photonIrradiance) << "surface " << s;
  }
  EXPECT_EQ(two.trace.hits, stored.trace.hits);
}

INSTANTIATE_TEST_SUITE_P(Bandwidths, BinnedWhileTraced, testing::Values(0.05f, 0.1f));

TEST(BinnedWhileTraced, CtrlCStopsTheBakeAndWritesNothing) {
  const std::string dir = test::TempDirectory("binned-ctrl-c");
  // A lamp 50 m above a floor: 400M photons take half a minute; the interruption comes within a second.
  const std::string scene = test::WriteFloorWithLamps(dir, 0.5f, 1.0f, {{-0.5f, 0.5f, -0.5f, 0.5f, 50.0f}});
  BakeOptions o;
  o.scenePath = scene;
  o.outputPath = dir + "/out.ply";
  o.photons = 400'000'000;
  o.quiet = true;
  std::ofstream(o.outputPath) << "earlier output";
  std::atomic<bool> done{false};
  std::thread ctrlC([&] {  // repeated: the bake's own InterruptScope clears a request made before it starts
    while (!done) std::this_thread::sleep_for(std::chrono::milliseconds(100)), RequestInterrupt();
  });
  try {
    Bake(o, Log(true));
    ADD_FAILURE() << "an interrupted bake that bins while tracing wrote its outputs";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("interrupted after"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--save-photons"), std::string::npos) << e.what();
  }
  done = true;
  ctrlC.join();
  EXPECT_EQ(test::ReadBytes(o.outputPath), "earlier output");
}

}  // namespace
}  // namespace pb
