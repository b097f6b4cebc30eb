// Robust rays at the awkward places of a mesh: rays aimed exactly at triangle edges and vertices of a closed box
// must hit it (no crack lets light through), and a ray leaving a surface from SpawnPoint must not hit the
// surface it leaves (no self-intersection), even at an edge or a corner where three walls meet.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace pb
