// The mesh operators of refinement, with no light: longest-edge bisection (mesh/refine.h) keeps the mesh
// conforming and its angles bounded, uniform subdivision (mesh/subdivide.h) keeps the geometry, and the exact-
// geometry decimation module (mesh/decimate.h) refuses every collapse that would move the outline, a corner or a
// crease.
#include <gtest/gtest.h>

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>

#include <algorithm>
#include <cmath>

#include "mesh/decimate.h"
#include "mesh/half_edge_mesh.h"
#include "mesh/obj_loader.h"
#include "mesh/refine.h"
#include "mesh/subdivide.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

using Vec3d = OpenMesh::Vec3d;

struct Loaded {
  Scene scene;
  SurfaceSet surfaces;
  explicit Loaded(const std::string& obj) : scene(LoadObj(obj).scene), surfaces(BuildSurfaces(scene)) {}
};

double TotalArea(const HalfEdgeMesh& m) {
  double area = 0;
  for (auto f : m.faces()) area += m.FaceArea(f);
  return area;
}

double SmallestAngle(const HalfEdgeMesh& m) {
  double smallest = M_PI;
  for (auto f : m.faces()) {
    const auto p = m.Corners(f);
    for (int k = 0; k < 3; ++k) {
      const Vec3d a = (p[(k + 1) % 3] - p[k]).normalized(), b = (p[(k + 2) % 3] - p[k]).normalized();
      smallest = std::min(smallest, std::acos(std::clamp(a | b, -1.0, 1.0)));
    }
  }
  return smallest;
}

// Refines every face that touches a small ball, however small it gets: the deepest refinement a shadow's corner
// could ask for.
class NearPoint : public RefineModule {
 public:
  NearPoint(Vec3d centre, double radius, double smallest) : centre_(centre), radius_(radius), smallest_(smallest) {}
  std::string_view Name() const override { return "near a point"; }
  double Priority(const HalfEdgeMesh& m, HalfEdgeMesh::FaceHandle f) override {
    const auto p = m.Corners(f);
    const Vec3d c = (p[0] + p[1] + p[2]) / 3;
    const double size = std::max({(p[1] - p[0]).norm(), (p[2] - p[1]).norm(), (p[0] - p[2]).norm()});
    return (c - centre_).norm() < radius_ + size && size > smallest_ ? size : kNoSplit;
  }

 private:
  Vec3d centre_;
  double radius_, smallest_;
};

TEST(RefineMesh, LongestEdgeBisectionStaysConformingWithBoundedAngles) {
  const Loaded box(test::WriteClosedBox(test::TempDirectory("lepp"), 1.0f, 0.5f, 0.2f, 1.0f));
  HalfEdgeMesh mesh = BuildHalfEdgeMesh(box.scene, box.surfaces);
  const double area = TotalArea(mesh), angle = SmallestAngle(mesh);
  const size_t boundaryBefore = std::count_if(mesh.edges_begin(), mesh.edges_end(), [&](auto e) { return mesh.is_boundary(e); });
  NearPoint corner({0.0, 0.0, 0.0}, 0.01, 0.002);  // a corner of the box, where three walls meet
  const RefineStats stats = RefineAdaptive(mesh, corner, {});
  EXPECT_GT(stats.splits, 300u);
  EXPECT_NEAR(TotalArea(mesh), area, 1e-9 * area);
  // Every cut splits both faces on its edge: the walls gain no open edge (only the floating light has one).
  const size_t boundaryAfter = std::count_if(mesh.edges_begin(), mesh.edges_end(), [&](auto e) { return mesh.is_boundary(e); });
  EXPECT_EQ(boundaryAfter, boundaryBefore);
  // Rivara: longest-edge bisection never takes the smallest angle below half the input's.
  EXPECT_GE(SmallestAngle(mesh), 0.5 * angle - 1e-9);
  // Every new vertex lies on its face's base triangle's plane.
  for (auto f : mesh.faces()) {
    const Normal3 n = box.scene.FrontNormal(mesh.BaseTriangle(f));
    const Point3 q = box.scene.Corner(mesh.BaseTriangle(f), 0);
    for (const Vec3d& p : mesh.Corners(f))
      ASSERT_NEAR((p[0] - q.x) * n.x + (p[1] - q.y) * n.y + (p[2] - q.z) * n.z, 0.0, 1e-7);
  }
}

TEST(RefineMesh, ConstraintsStopTheCuts) {
  const Loaded box(test::WriteClosedBox(test::TempDirectory("lepp-limits"), 1.0f, 0.5f, 0.2f, 1.0f));
  HalfEdgeMesh mesh = BuildHalfEdgeMesh(box.scene, box.surfaces);
  NearPoint everywhere({0.5, 0.5, 0.5}, 10.0, 0.0);  // wants to refine without end
  MinimumEdgeLength minimum(std::vector<double>(box.surfaces.surfaces.size(), 0.05));
  RefineModule* constraints[] = {&minimum};
  const RefineStats stats = RefineAdaptive(mesh, everywhere, constraints);
  EXPECT_GT(stats.refusedFaces, 0u);
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    const double length = (mesh.point(mesh.to_vertex_handle(h)) - mesh.point(mesh.from_vertex_handle(h))).norm();
    EXPECT_GE(length, 0.05 * 0.5) << "a cut below the minimum edge";  // halves of edges >= 2 x minimum, or legs
  }
}

TEST(RefineMesh, UniformSubdivisionQuadruplesFacesAndKeepsTheGeometry) {
  const Loaded box(test::WriteClosedBox(test::TempDirectory("osd"), 1.0f, 0.5f, 0.2f, 1.0f));
  const HalfEdgeMesh mesh = BuildHalfEdgeMesh(box.scene, box.surfaces);
  for (int levels : {1, 2}) {
    const HalfEdgeMesh fine = SubdivideUniform(mesh, levels);
    EXPECT_EQ(fine.n_faces(), mesh.n_faces() << (2 * levels));
    EXPECT_NEAR(TotalArea(fine), TotalArea(mesh), 1e-9 * TotalArea(mesh));
    std::map<uint32_t, double> areaBySurface;
    for (auto f : fine.faces()) areaBySurface[fine.Surface(f)] += fine.FaceArea(f);
    for (const auto& [s, a] : areaBySurface) EXPECT_NEAR(a, box.surfaces.surfaces[s].area, 1e-6) << s;
    // Flat stays flat: no vertex leaves its face's plane (Loop's smoothing would pull corners inward).
    for (auto f : fine.faces()) {
      const Normal3 n = box.scene.FrontNormal(fine.BaseTriangle(f));
      EXPECT_GT(fine.FaceNormal(f) | Vec3d(n.x, n.y, n.z), 1 - 1e-9);
    }
  }
}

// Collapses with no error criterion at all, so only the exact-geometry module decides.
template <typename MeshT>
class ModAnything : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModAnything, MeshT, Anything);
  explicit ModAnything(MeshT& mesh) : Base(mesh, false) {}
  float collapse_priority(const CollapseInfo&) override { return 0; }
};

size_t DecimateFreely(HalfEdgeMesh& mesh) {
  OpenMesh::Decimater::DecimaterT<HalfEdgeMesh> decimater(mesh);
  ModExactGeometryT<HalfEdgeMesh>::Handle geometry;
  ModAnything<HalfEdgeMesh>::Handle anything;
  decimater.add(geometry);
  decimater.add(anything);
  decimater.initialize();
  const size_t collapses = decimater.decimate();
  mesh.garbage_collection();
  return collapses;
}

TEST(RefineMesh, ExactGeometryDecimationKeepsCornersOutlinesAndCreases) {
  // A closed box whose walls are cut into 4 x 4 cells: with every collapse allowed, only the 8 corners, and the
  // light's 4, can remain; the walls' areas and the box's shape stay exactly as they were.
  const Loaded box(test::WriteClosedBox(test::TempDirectory("decimate"), 1.0f, 0.5f, 0.2f, 1.0f));
  HalfEdgeMesh mesh = BuildHalfEdgeMesh(box.scene, box.surfaces);
  const double area = TotalArea(mesh);
  EXPECT_GT(DecimateFreely(mesh), 0u);
  EXPECT_EQ(mesh.n_vertices(), 8u + 4u);
  EXPECT_NEAR(TotalArea(mesh), area, 1e-9 * area);
  for (auto f : mesh.faces()) {
    const Normal3 n = box.scene.FrontNormal(mesh.BaseTriangle(f));
    EXPECT_GT(mesh.FaceNormal(f) | Vec3d(n.x, n.y, n.z), 1 - 1e-9) << "a face left its wall's plane or flipped";
  }
}

TEST(RefineMesh, LockedSurfacesKeepEveryVertex) {
  const Loaded box(test::WriteClosedBox(test::TempDirectory("decimate-locked"), 1.0f, 0.5f, 0.2f, 1.0f));
  HalfEdgeMesh mesh = BuildHalfEdgeMesh(box.scene, box.surfaces);
  const size_t before = mesh.n_vertices();
  LockSurfaces(mesh, std::vector<bool>(box.surfaces.surfaces.size(), true));
  EXPECT_EQ(DecimateFreely(mesh), 0u);
  EXPECT_EQ(mesh.n_vertices(), before);
}

}  // namespace
}  // namespace pb
