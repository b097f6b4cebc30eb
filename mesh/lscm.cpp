#include "mesh/lscm.h"

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

#include <algorithm>
#include <cmath>

namespace pb {
namespace {

using CgalKernel = CGAL::Simple_cartesian<double>;
using CgalMesh = CGAL::Surface_mesh<CgalKernel::Point_3>;
using VertexIndex = CgalMesh::Vertex_index;
namespace SMP = CGAL::Surface_mesh_parameterization;

// Uniform scale (and a mirror if needed) so that the map keeps orientation and the total area.
bool Normalise(std::vector<Point2>& uv, std::span<const Point3> positions, std::span<const std::array<uint32_t, 3>> triangles) {
  double uvArea = 0, area = 0;
  for (const auto& t : triangles) {
    uvArea += SignedArea(uv[t[0]], uv[t[1]], uv[t[2]]);
    area += 0.5 * double(Length(Cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]])));
  }
  if (!(std::fabs(uvArea) > 0) || !std::isfinite(uvArea)) return false;
  const float scale = float(std::sqrt(area / std::fabs(uvArea))), mirror = uvArea < 0 ? -1.0f : 1.0f;
  for (Point2& p : uv) p = {p.u * scale * mirror, p.v * scale};
  return true;
}

// CGAL's LSCM pins the two vertices extreme along the patch's longest bounding-box axis, scaled by the second
// longest: a patch flat in two axes (its vertices on a line) divides by zero there and crashes. Such a patch, or
// one of a triangle without area, has no conformal map.
bool CanBeMapped(std::span<const Point3> positions, std::span<const std::array<uint32_t, 3>> triangles) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const Point3& p : positions) {
    const double c[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k]);
  }
  int extended = 0;
  for (int k = 0; k < 3; ++k) extended += hi[k] > lo[k];
  if (extended < 2) return false;
  return std::all_of(triangles.begin(), triangles.end(), [&](const auto& t) {
    return Length(Cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]])) > 0;
  });
}

}  // namespace

std::optional<std::vector<Point2>> ConformalMap(std::span<const Point3> positions,
                                               std::span<const std::array<uint32_t, 3>> triangles) {
  if (!CanBeMapped(positions, triangles)) return std::nullopt;
  CgalMesh mesh;
  std::vector<VertexIndex> vertex;
  vertex.reserve(positions.size());
  for (const Point3& p : positions) vertex.push_back(mesh.add_vertex({p.x, p.y, p.z}));
  for (const auto& t : triangles)
    if (mesh.add_face(vertex[t[0]], vertex[t[1]], vertex[t[2]]) == CgalMesh::null_face()) return std::nullopt;

  const auto border = CGAL::Polygon_mesh_processing::longest_border(mesh).first;
  if (border == CgalMesh::null_halfedge()) return std::nullopt;
  auto uvMap = mesh.add_property_map<VertexIndex, CgalKernel::Point_2>("v:uv").first;
  const SMP::Error_code status = SMP::parameterize(mesh, SMP::LSCM_parameterizer_3<CgalMesh>(), border, uvMap);
  if (status != SMP::OK) return std::nullopt;

  std::vector<Point2> uv(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    const auto& p = uvMap[vertex[i]];
    uv[i] = {float(p.x()), float(p.y())};
    if (!std::isfinite(uv[i].u) || !std::isfinite(uv[i].v)) return std::nullopt;
  }
  if (!Normalise(uv, positions, triangles)) return std::nullopt;
  return uv;
}

}  // namespace pb
