// Robust rays at the awkward places of a mesh: rays aimed exactly at triangle edges and vertices of a closed box
// must hit it (no crack lets light through), and a ray leaving a surface from SpawnPoint must not hit the
// surface it leaves (no self-intersection), even at an edge or a corner where three walls meet. A point query that
// says no ray into a hemisphere can meet anything within reach (MayMeetInFront) must never be contradicted by a ray.
#include <gtest/gtest.h>

#include "estimators/rng.h"
#include "estimators/warps.h"
#include "mesh/obj_loader.h"
#include "mesh/ray_scene.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

TEST(RayScene, EdgesAndVerticesNeitherLeakNorSelfIntersect) {
  const std::string dir = test::TempDirectory("ray-edges");
  const Scene scene = LoadObj(test::WriteClosedBox(dir, 1.0f, 0.5f, 0.2f, 1.0f)).scene;
  const RayScene rays(scene);
  const Point3 centre{0.5f, 0.5f, 0.5f};
  int aimed = 0;
  for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      // Aim exactly at a corner, and at the midpoint of the edge to the next corner (shared with a neighbour).
      const Point3 a = scene.Corner(t, k), b = scene.Corner(t, (k + 1) % 3);
      for (const Point3 aim : {a, Point3{0.5f * (a.x + b.x), 0.5f * (a.y + b.y), 0.5f * (a.z + b.z)}}) {
        const Vector3 d = Normalize(aim - centre);
        const auto hit = rays.Intersect(centre, d);
        ASSERT_TRUE(hit.has_value()) << "a ray through a vertex or edge escaped the closed box";
        ++aimed;
        // Leave the surface toward the centre from the exact hit point, as a reflected photon would.
        const Point3 x = scene.PointAt(hit->triangle, hit->b1, hit->b2);
        const Normal3 front = scene.FrontNormal(hit->triangle);
        const Normal3 side = Dot(d, front) < 0 ? front : -front;
        const auto back = rays.Intersect(rays.SpawnPoint(x, side), Normalize(centre - x));
        ASSERT_TRUE(back.has_value());
        EXPECT_GT(back->t, 0.4f) << "the ray re-hit the surface it left (or a wall at the same corner)";
      }
    }
  }
  EXPECT_GT(aimed, 500);
}

// At points all over the Cornell box (its blocks' faces and the walls they meet, both sides of every surface), at
// reaches from 5 mm to 20 cm: wherever the point query says nothing lies in front within reach, 64 cosine rays cut
// at that reach all miss. And it is not always yes: the open middle of a wall, or an outward side, hears no.
TEST(RayScene, NothingInFrontMeansEveryRayMisses) {
  const Scene scene = LoadObj(PB_SOURCE_DIR "/data/box/box.obj").scene;
  const RayScene rays(scene);
  Rng rng(11, 0);
  int no = 0, yes = 0, yesAndHit = 0;
  for (int i = 0; i < 4000; ++i) {
    const auto t = uint32_t(std::min<size_t>(size_t(rng.Uniform() * scene.triangles.size()), scene.triangles.size() - 1));
    Point2 b = rng.Uniform2();
    if (b.u + b.v > 1) b = {1 - b.u, 1 - b.v};
    const Normal3 side = i % 2 ? scene.FrontNormal(t) : -scene.FrontNormal(t);
    const Point3 origin = rays.SpawnPoint(scene.PointAt(t, b.u, b.v), side);
    const float reach = 0.005f * std::pow(40.0f, rng.Uniform());
    const Frame frame = Frame::FromNormal(side);
    int hits = 0;
    for (int k = 0; k < 64; ++k)
      hits += rays.Intersect(origin, frame.ToWorld(SampleCosineHemisphere(rng.Uniform2()).direction), reach).has_value();
    if (rays.MayMeetInFront(origin, side, reach)) {
      ++yes, yesAndHit += hits > 0;
    } else {
      ++no;
      ASSERT_EQ(hits, 0) << "triangle " << t << ", reach " << reach << " m: a ray met what the point query missed";
    }
  }
  EXPECT_GT(no, 1000);
  EXPECT_GT(yesAndHit, 100);
  EXPECT_GT(yes, yesAndHit);  // conservative: a box's corner on the near side, or within reach, need not be hit
}

// Closed form: a unit square 1 cm in front of a point facing it. Within 2 cm: yes; within 5 mm: no; facing away: no.
TEST(RayScene, AParallelPlaneInFrontIsFoundWithinReachOnly) {
  Scene scene;
  scene.positions = {{-0.5f, -0.5f, 0.01f}, {0.5f, -0.5f, 0.01f}, {0.5f, 0.5f, 0.01f}, {-0.5f, 0.5f, 0.01f}};
  scene.triangles = {{{0, 1, 2}}, {{0, 2, 3}}};
  const RayScene rays(scene);
  EXPECT_TRUE(rays.MayMeetInFront({0.2f, 0.1f, 0}, {0, 0, 1}, 0.02f));
  EXPECT_FALSE(rays.MayMeetInFront({0.2f, 0.1f, 0}, {0, 0, 1}, 0.005f));
  EXPECT_FALSE(rays.MayMeetInFront({0.2f, 0.1f, 0}, {0, 0, -1}, 0.02f));
  // On the plane itself, spawned off it: the plane is behind, and does not count.
  EXPECT_FALSE(rays.MayMeetInFront(rays.SpawnPoint({0.2f, 0.1f, 0.01f}, {0, 0, -1}), {0, 0, -1}, 0.5f));
}

// A 1 m plane of 2 x 40 x 40 triangles: off its centre, facing away from it, nothing is in front. Within 5 cm (about
// 30 triangles' boxes) the query proves it; within 1 m (all 3,200) it stops looking past 512 and answers "may",
// which costs the caller's rays but never a wrong "no" (the conservative test above).
TEST(RayScene, AFinelyTessellatedPlaneBehindIsProvenNearAndLeftToTheRaysFar) {
  Scene scene;
  constexpr int kCells = 40;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) scene.positions.push_back({float(i) / kCells - 0.5f, float(j) / kCells - 0.5f, 0});
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const uint32_t a = j * (kCells + 1) + i, b = a + 1, c = a + kCells + 1, d = c + 1;
      scene.triangles.push_back({{a, b, d}}), scene.triangles.push_back({{a, d, c}});
    }
  const RayScene rays(scene);
  const Point3 origin = rays.SpawnPoint({0.01f, 0.01f, 0}, {0, 0, 1});
  EXPECT_FALSE(rays.MayMeetInFront(origin, {0, 0, 1}, 0.05f));
  EXPECT_TRUE(rays.MayMeetInFront(origin, {0, 0, 1}, 1.0f));
}

}  // namespace
// TrianglesNear against brute force on the box: every triangle whose bounding box comes within the radius is
// listed, once, in ascending order, at 200 points and radii from 1 mm to the box's size.
TEST(RayScene, TrianglesNearListsEveryTriangleWithinTheRadiusOnce) {
  const Scene scene = LoadObj(PB_SOURCE_DIR "/data/box/box.obj").scene;
  const RayScene rays(scene);
  Rng rng(7, 0);
  for (int k = 0; k < 200; ++k) {
    const Point3 p{0.56f * rng.Uniform(), 0.55f * rng.Uniform(), 0.56f * rng.Uniform()};
    const float radius = 0.001f * std::pow(500.0f, rng.Uniform());
    std::vector<uint32_t> near;
    rays.TrianglesNear(p, radius, near);
    EXPECT_TRUE(std::is_sorted(near.begin(), near.end()));
    EXPECT_EQ(std::adjacent_find(near.begin(), near.end()), near.end());
    for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
      float d2 = 0;  // from p to t's bounding box
      for (int axis = 0; axis < 3; ++axis) {
        float lo = INFINITY, hi = -INFINITY;
        for (uint32_t v : scene.triangles[t].v) {
          const Point3& q = scene.positions[v];
          const float c = axis == 0 ? q.x : axis == 1 ? q.y : q.z;
          lo = std::min(lo, c), hi = std::max(hi, c);
        }
        const float c = axis == 0 ? p.x : axis == 1 ? p.y : p.z;
        const float d = std::max({lo - c, c - hi, 0.0f});
        d2 += d * d;
      }
      if (d2 < 0.99f * radius * radius) EXPECT_TRUE(std::binary_search(near.begin(), near.end(), t)) << t;
    }
  }
}

}  // namespace pb
