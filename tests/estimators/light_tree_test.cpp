// The light tree (estimators/light_tree.h) and direct light sampled through it (estimators/light_sampler.h):
//  - the union of two cones holds every direction of both;
//  - at any point its pmf sums to the chance that a choice reaches a light (1 unless bounds rule out a whole
//    branch below the root), and Choose reports the pmf that Pmf gives;
//  - chi-square: the lights that uniform u's choose follow Pmf;
//  - conservative bounds: every light with a point in front of the receiver that faces it has pmf > 0, so the
//    choice is unbiased;
//  - lamps on a point's tangent plane are ruled out at the root;
//  - stratified u's stay stratified: S evenly spaced u's choose each light within one of S times its pmf;
//  - closed form: 400 small lights of radiances over three decades over a black floor (a tree of 799 nodes): the
//    sampled E_d at 100 floor points matches the sum of Lambert's formula over the lights within 5 of its predicted
//    standard errors, mean z^2 at most 1.5, and the mean relative error within 5 of its standard errors.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "estimators/light_sampler.h"
#include "estimators/light_tree.h"
#include "tests/chi2.h"
#include "tests/lambert.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

Vector3 RandomDirection(std::mt19937& g) {
  std::normal_distribution<float> normal;
  return Normalize(Vector3{normal(g), normal(g), normal(g)});
}

// A square light: its four corners, bounds and front normal.
struct Panel {
  std::array<Point3, 4> corners;
  Vector3 normal;
  double power;
};

Panel RandomPanel(std::mt19937& g) {
  std::uniform_real_distribution<float> position(-2, 2), size(0.02f, 0.3f), power(-3, 0);
  const Vector3 n = RandomDirection(g);
  const Frame frame = Frame::FromNormal(NormalFrom(n));
  const Point3 c{position(g), position(g), position(g)};
  const float s = size(g);
  const Vector3 a = frame.ToWorld({s, 0, 0}), b = frame.ToWorld({0, s, 0});
  return {{c, c + a, c + a + b, c + b}, n, std::pow(10.0, double(power(g)))};
}

LightBounds BoundsOf(const Panel& panel) {
  LightBounds b;
  b.Enclose({panel.corners.begin(), panel.corners.end()});
  b.axis = panel.normal;
  b.spread = 0;
  b.power = panel.power;
  return b;
}

struct RandomLights {
  std::vector<Panel> panels;
  std::vector<LightBounds> bounds;
  explicit RandomLights(int count, uint32_t seed) {
    std::mt19937 g(seed);
    for (int i = 0; i < count; ++i) panels.push_back(RandomPanel(g)), bounds.push_back(BoundsOf(panels.back()));
  }
};

TEST(LightTree, TheUnionOfTwoConesHoldsBoth) {
  std::mt19937 g(3);
  std::uniform_real_distribution<float> angle(0, kPi);
  for (int trial = 0; trial < 2000; ++trial) {
    const NormalCone a{RandomDirection(g), angle(g) * 0.5f}, b{RandomDirection(g), angle(g) * 0.5f};
    const NormalCone u = UnionOfCones(a, b);
    ASSERT_NEAR(Length(u.axis), 1.0f, 1e-5f);
    for (const NormalCone& c : {a, b})
      for (int k = 0; k < 20; ++k) {
        // A direction on the rim of c, which is the farthest from u's axis that c holds in that plane.
        const Frame f = Frame::FromNormal(NormalFrom(c.axis));
        const float phi = 2 * kPi * float(k) / 20;
        const Vector3 w = f.ToWorld({std::sin(c.spread) * std::cos(phi), std::sin(c.spread) * std::sin(phi),
                                     std::cos(c.spread)});
        EXPECT_LE(std::acos(std::clamp(Dot(w, u.axis), -1.0f, 1.0f)), u.spread + 2e-3f) << trial;
      }
  }
}

// Where the root's bounds admit a light but both children of some node rule theirs out, a choice ends there with
// none (the lights there cannot reach the point, so the estimate stays unbiased; only the sample is spent): the
// pmf then sums to the chance of reaching a leaf, which Choose's rate of success matches.
TEST(LightTree, ThePmfSumsToTheChanceOfALightAndChooseReportsIt) {
  const RandomLights lights(300, 11);
  const LightTree tree(lights.bounds);
  std::mt19937 g(5);
  std::uniform_real_distribution<float> position(-3, 3), u01(0, 1);
  int reachable = 0;
  double chance = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const Point3 p{position(g), position(g), position(g)};
    const Normal3 n = NormalFrom(RandomDirection(g));
    if (!tree.AnyCanReach(p, n)) continue;
    ++reachable;
    double sum = 0;
    for (uint32_t l = 0; l < lights.bounds.size(); ++l) sum += tree.Pmf(p, n, l);
    EXPECT_LE(sum, 1.0 + 1e-9) << trial;
    chance += sum;
    constexpr int kDraws = 2000;
    int chosen = 0;
    for (int k = 0; k < kDraws; ++k) {
      const auto choice = tree.Choose(p, n, u01(g));
      if (!choice) continue;
      ++chosen;
      EXPECT_NEAR(choice->pmf, tree.Pmf(p, n, choice->light), 1e-12 * choice->pmf);
    }
    // Binomial: within 5 standard deviations of the pmf's sum.
    EXPECT_NEAR(chosen, kDraws * sum, 5 * std::sqrt(kDraws * sum * (1 - sum)) + 1) << trial;
  }
  EXPECT_GT(reachable, 40);
  // Lights facing every way around the points lose about a quarter of the choices (0.725 on this seed); lamps that
  // face the points lose none (FourHundredLamps... below).
  std::printf("mean chance of a light: %.3f\n", chance / reachable);
  EXPECT_GT(chance / reachable, 0.6);
}

TEST(LightTree, ChosenLightsFollowThePmf) {
  const RandomLights lights(200, 12);
  const LightTree tree(lights.bounds);
  std::mt19937 g(6);
  std::uniform_real_distribution<float> u01(0, 1);
  for (const auto& [p, n] : {std::pair{Point3{0, 0, 0}, Normal3{0, 1, 0}}, std::pair{Point3{1, -2, 0.5f}, Normal3{1, 0, 0}},
                            std::pair{Point3{-2.5f, 2.5f, -2.5f}, NormalFrom(Vector3{1, -1, 1})}}) {
    constexpr int kDraws = 200'000;
    std::vector<double> observed(lights.bounds.size(), 0), expected(lights.bounds.size(), 0);
    for (int k = 0; k < kDraws; ++k)
      if (const auto choice = tree.Choose(p, n, u01(g))) ++observed[choice->light];
    for (uint32_t l = 0; l < lights.bounds.size(); ++l) expected[l] = kDraws * tree.Pmf(p, n, l);
    const test::Chi2Result r = test::Chi2Test(observed, expected);
    EXPECT_GT(r.pValue, 1e-3) << r.histograms;
    EXPECT_GT(r.degreesOfFreedom, 20);
  }
}

TEST(LightTree, EveryLightThatCanReachAPointCanBeChosen) {
  const RandomLights lights(500, 13);
  const LightTree tree(lights.bounds);
  std::mt19937 g(7);
  std::uniform_real_distribution<float> position(-3, 3);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Point3 p{position(g), position(g), position(g)};
    const Normal3 n = NormalFrom(RandomDirection(g));
    for (uint32_t l = 0; l < lights.panels.size(); ++l) {
      const Panel& panel = lights.panels[l];
      const bool facesP = Dot(p - panel.corners[0], panel.normal) > 1e-4f;
      bool inFront = false;
      for (Point3 c : panel.corners) inFront = inFront || Dot(c - p, n) > 1e-4f;
      if (!facesP || !inFront) continue;
      ++checked;
      EXPECT_GT(tree.Pmf(p, n, l), 0) << trial << " light " << l;
    }
  }
  EXPECT_GT(checked, 10'000);
}

// Lamps in one plane facing down (an LED ceiling): a point among them, facing down too, has every lamp on its
// tangent plane and none in front, so the tree rules them all out at the root instead of descending to each;
// 1 mm below, facing up, every lamp can reach it.
TEST(LightTree, LampsInAPointsTangentPlaneAreRuledOutAtTheRoot) {
  std::vector<LightBounds> lamps;
  for (int i = 0; i < 32; ++i)
    for (int j = 0; j < 32; ++j) {
      LightBounds b;
      b.Enclose({{0.1f * i, 2, 0.1f * j}, {0.1f * i + 0.02f, 2, 0.1f * j + 0.02f}});
      b.axis = {0, -1, 0};
      b.power = 1;
      lamps.push_back(b);
    }
  const LightTree tree(lamps);
  EXPECT_FALSE(tree.AnyCanReach({1.51f, 2, 1.51f}, {0, -1, 0}));
  EXPECT_FALSE(tree.Choose({1.51f, 2, 1.51f}, {0, -1, 0}, 0.5f).has_value());
  EXPECT_TRUE(tree.AnyCanReach({1.51f, 1.999f, 1.51f}, {0, 1, 0}));
  for (uint32_t l = 0; l < lamps.size(); ++l) ASSERT_GT(tree.Pmf({1.51f, 1.999f, 1.51f}, {0, 1, 0}, l), 0) << l;
}

TEST(LightTree, StratifiedNumbersStayStratifiedOverTheLights) {
  const RandomLights lights(100, 14);
  const LightTree tree(lights.bounds);
  const Point3 p{0.2f, 0.1f, -0.3f};
  const Normal3 n{0, 0, 1};
  constexpr int kSamples = 4096;
  std::vector<int> count(lights.bounds.size(), 0);
  for (int j = 0; j < kSamples; ++j)
    if (const auto choice = tree.Choose(p, n, (float(j) + 0.5f) / kSamples)) ++count[choice->light];
  for (uint32_t l = 0; l < lights.bounds.size(); ++l)
    EXPECT_NEAR(count[l], kSamples * tree.Pmf(p, n, l), 1.0 + 1e-6) << l;
}

TEST(LightTree, FourHundredLampsMatchLambertWithinTheSampledNoise) {
  // 400 lamps of 5 cm at a pitch of 0.1 m, 1 m over a black 4 x 4 m floor.
  constexpr int kLamps = 20;
  const test::TracedScene prepared(test::WriteLampGrid(test::TempDirectory("light-tree-lamps"), kLamps, 0.1f, 0.05f, 1, 4));
  std::vector<std::vector<test::V3>> squares;
  std::vector<double> radiance;
  for (int i = 0; i < kLamps; ++i)
    for (int j = 0; j < kLamps; ++j) {
      squares.emplace_back();
      for (const auto& c : test::LampGridSquare(kLamps, 0.1f, 0.05f, 1, i, j)) squares.back().push_back({c[0], c[1], c[2]});
      radiance.push_back(test::LampGridRadiance(i, j));
    }
  ASSERT_EQ(prepared.lights.size(), 400u);
  const LightSampler sampler(prepared.scene, prepared.lights, *prepared.rays, /*treeFrom=*/1);
  std::vector<LightBounds> bounds;  // as the sampler bounds them: each lamp faces straight down
  for (const std::vector<test::V3>& square : squares)
    bounds.push_back({{float(square[0].x), 1, float(square[0].z)}, {float(square[2].x), 1, float(square[2].z)},
                      {0, -1, 0}, 0, 1});
  const LightTree tree(bounds);
  double z2 = 0, errors = 0, variance = 0;
  constexpr int kSide = 10;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j) {
      const double x = -1.8 + 3.6 * (i + 0.5) / kSide, z = -1.8 + 3.6 * (j + 0.5) / kSide;
      double exact = 0;
      for (size_t l = 0; l < squares.size(); ++l)
        exact += test::LambertPolygonIrradiance({x, 0, z}, {0, 1, 0}, squares[l], radiance[l]);
      double chance = 0;  // every floor point can reach every lamp: no choice is lost
      for (uint32_t l = 0; l < bounds.size(); ++l) chance += tree.Pmf({float(x), 0, float(z)}, {0, 1, 0}, l);
      EXPECT_NEAR(chance, 1.0, 1e-9);
      Rng rng(9, uint64_t(i * kSide + j));
      const DirectSample e = sampler.Irradiance({float(x), 0, float(z)}, {0, 1, 0}, 256, rng);
      const double sigma = e.relativeNoise * e.irradiance.g;
      ASSERT_GT(sigma, 0) << x << ", " << z;
      EXPECT_NEAR(e.irradiance.g, exact, 5 * sigma) << x << ", " << z;
      z2 += std::pow((e.irradiance.g - exact) / sigma, 2);
      errors += e.irradiance.g / exact - 1;
      variance += std::pow(sigma / exact, 2);
    }
  const double n = kSide * kSide;
  std::printf("400 lamps: mean z^2 %.3f, mean relative error %.2e (standard error %.2e), mean relative noise %.3f\n",
              z2 / n, errors / n, std::sqrt(variance) / n, std::sqrt(variance / n));
  EXPECT_LE(z2 / n, 1.5);
  EXPECT_LE(std::fabs(errors / n), 5 * std::sqrt(variance) / n);
}

}  // namespace
}  // namespace pb
