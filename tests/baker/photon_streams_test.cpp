// Each light's photons form one stream of its own (baker/1_trace_photons.h): a bake with more photons traces
// the same first photons of every light, and then continues. This is what lets photons be added to a bake.
#include <gtest/gtest.h>

#include "tests/traced_scene.h"

namespace pb {
namespace {

// The hits of light l's full blocks, by block.
std::vector<const HitBlock*> FullBlocksOf(const PhotonHits& hits, uint32_t light, uint64_t photonsOfLight) {
  std::vector<const HitBlock*> blocks;
  for (size_t b = 0; b < hits.blocks.size(); ++b)
    if (hits.blockLight[b] == light && blocks.size() < photonsOfLight / kBlockPhotons) blocks.push_back(&hits.blocks[b]);
  return blocks;
}

TEST(PhotonStreams, MorePhotonsContinueEachLightsStream) {
  const test::TracedScene box(PB_SOURCE_DIR "/data/box/box.obj");
  const PhotonHits fewer = box.Trace(300'000, 5), more = box.Trace(700'000, 5);
  ASSERT_EQ(box.lights.size(), 2u);
  for (uint32_t l = 0; l < 2; ++l) {
    const uint64_t n1 = fewer.stats.photonsPerLight[l], n2 = more.stats.photonsPerLight[l];
    ASSERT_GT(n2, n1);
    const auto a = FullBlocksOf(fewer, l, n1), b = FullBlocksOf(more, l, n2);
    ASSERT_GE(a.size(), 1u) << "light " << l << " has no full block at " << n1 << " photons";
    for (size_t k = 0; k < a.size(); ++k) {
      ASSERT_EQ(a[k]->size(), b[k]->size()) << "light " << l << " block " << k;
      for (size_t i = 0; i < a[k]->size(); ++i) {
        const PhotonHit &x = (*a[k])[i], &y = (*b[k])[i];
        ASSERT_EQ(x.triangleSide, y.triangleSide);
        ASSERT_EQ(x.wiOctahedral, y.wiOctahedral);
        ASSERT_EQ(x.b1, y.b1);
        ASSERT_EQ(x.b2, y.b2);
        // Only the flux differs: the light's flux is shared by more photons.
        ASSERT_NEAR(y.power.r * float(n2), x.power.r * float(n1), 1e-5f * x.power.r * float(n1));
      }
    }
  }
}

}  // namespace
}  // namespace pb
