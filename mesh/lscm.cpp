#include "mesh/lscm.h"

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

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

}  // namespace

std::optional<std::vector<Point2>> ConformalMap(std::span<const Point3> positions,
                                               std::span<const std::array<uint32_t, 3>> triangles) {
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
