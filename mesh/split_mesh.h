// The display mesh: the scene's triangles with vertices split where surfaces meet, because irradiance and
// albedo are discontinuous there. Every vertex belongs to exactly one surface and carries its chart position
// (u,v) [m] and a normal: the surface's normal if planar, the area-weighted mean of its triangles' normals at the
// vertex if curved. `uvAreaRatio` is the chart's local area scale at the vertex, (u,v) area / surface area over
// the vertex's triangles (exactly 1 on planar surfaces): a density per (u,v) area times it is a density per
// surface area. Positions are in metres.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "mesh/geometry.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

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
};

// Vertices are ordered by surface, then by first use; faces by surface, then by scene order.
SplitMesh SplitBySurface(const Scene& scene, const SurfaceSet& surfaces);

}  // namespace pb
