// The display mesh: the scene's triangles with vertices split where surfaces meet, because irradiance and
// albedo are discontinuous there. Every vertex belongs to exactly one surface and carries its chart position
// (u,v) [m] and a normal: the surface's normal if planar, the area-weighted mean of its triangles' normals at the
// vertex if curved. `uvAreaRatio` is the chart's local area scale at the vertex, (u,v) area / surface area over
// the vertex's triangles (exactly 1 on planar surfaces): a density per (u,v) area times it is a density per
// surface area. Positions are in metres.
#pragma once

#include <array>
#include <optional>
#include <string_view>
#include <cstdint>
#include <vector>

#include "mesh/geometry.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

// A point on a surface.
struct SurfacePoint {
  uint32_t surface = 0;
  Point3 position;        // local [m] (Scene::ToWorld gives world coordinates)
  Normal3 normal;         // the chart's normal on planar surfaces; the input's smooth normals, interpolated, on curved
  Point2 uv;              // chart position [m]
  Point2 texcoord;        // texture coordinates on textured surfaces, else (0, 0)
  float areaRatio = 1;    // (u,v) area per surface area: 1 on planar surfaces, interpolated from the vertices on curved
};

struct SplitMesh {
  std::array<double, 3> origin{0, 0, 0};  // Scene::origin: world = origin + position [m]
  std::vector<Point3> positions;          // local [m]
  std::vector<Normal3> normals;
  std::vector<Point2> uv;             // in the chart of `surface[i]` [m]
  std::vector<Point2> texcoord;       // OBJ texture coordinates (s, t) on textured surfaces, else (0, 0)
  std::vector<uint32_t> surface;      // owning surface of each vertex
  std::vector<float> uvAreaRatio;     // dimensionless, 1 on planar surfaces
  std::vector<std::array<uint32_t, 3>> faces;  // counter-clockwise seen from the front
  size_t VertexCount() const { return positions.size(); }
  // Appends a vertex; returns its index.
  uint32_t AddVertex(Point3 position, Normal3 normal, Point2 chartUv, Point2 st, uint32_t owner, float areaRatio) {
    positions.push_back(position);
    normals.push_back(normal);
    uv.push_back(chartUv);
    texcoord.push_back(st);
    surface.push_back(owner);
    uvAreaRatio.push_back(areaRatio);
    return uint32_t(positions.size() - 1);
  }
  SurfacePoint Point(size_t v) const {
    return {surface[v], positions[v], normals[v], uv[v], texcoord[v], uvAreaRatio[v]};
  }
};

// Each vertex's share of the mesh's area: a third of each face it is a corner of [m^2]. Over a surface's vertices,
// sum_v A_v f_v is the integral of f interpolated linearly across the faces.
std::vector<double> VertexAreas(const SplitMesh& mesh);

// Vertices are ordered by surface, then by first use; faces by surface, then by scene order. With `keep` (one flag
// per surface), only the kept surfaces, in the same order: their vertices are those of the whole mesh, less the
// others.
SplitMesh SplitBySurface(const Scene& scene, const SurfaceSet& surfaces, const std::vector<bool>& keep = {});

// The surfaces whose object or material name matches one of `patterns`, comma-separated shell globs ("table*,
// book_?"; fnmatch); an object without a name ('o' missing in an OBJ) matches by its material only. InputError
// naming `option` when no surface matches.
std::vector<bool> SurfacesNamed(const Scene& scene, const SurfaceSet& surfaces, std::string_view patterns,
                                const char* option);

// Barycentrics (b1, b2) of point p (local [m], double precision) in scene triangle t; p need not lie inside it.
using Point3d = std::array<double, 3>;
std::array<double, 2> BarycentricsIn(const Scene& scene, uint32_t t, const Point3d& p);

// Evaluates SurfacePoint anywhere on the scene's surfaces. `base` is SplitBySurface(scene, surfaces): it holds
// the input's per-corner normals and area ratios, which points on curved surfaces interpolate on their triangle.
class SurfacePointSampler {
 public:
  SurfacePointSampler(const Scene& scene, const SurfaceSet& surfaces, const SplitMesh& base);
  // The point at position p of `surface`, on (or in the plane of) scene triangle `triangle`. On planar surfaces
  // the chart is the plane's own projection, so p need not lie inside the triangle (as after decimation).
  SurfacePoint At(uint32_t surface, uint32_t triangle, const Point3d& p) const;
  // The point of `surface` at chart position uv; off the surface, the surface's nearest point in the chart. On
  // the surface, a grid of its chart triangles finds it in constant time; off it, the search is linear in the
  // surface's triangle count.
  SurfacePoint AtChartPoint(uint32_t surface, Point2 uv) const;

 private:
  // A uniform grid over one surface's chart: the triangles whose bounds meet cell c are
  // triangles[start[c] .. start[c+1]), ascending.
  struct ChartGrid {
    Bounds2 bounds;
    float cell = 1;
    int nu = 1, nv = 1;
    std::vector<uint32_t> start, triangles;
  };
  static ChartGrid BuildChartGrid(const SurfaceSet& surfaces, const Surface& surface);
  // The first of the surface's triangles (in its order) whose chart triangle holds uv, if any.
  std::optional<uint32_t> TriangleHolding(uint32_t surface, Point2 uv) const;

  SurfacePoint Interpolated(uint32_t surface, uint32_t triangle, const std::array<double, 2>& b) const;

  const Scene& scene_;
  const SurfaceSet& surfaces_;
  const SplitMesh& base_;
  std::vector<uint32_t> splitFace_;  // scene triangle -> its face in `base`
  std::vector<ChartGrid> grids_;     // per surface
};

}  // namespace pb
