// Constrained Delaunay triangulation by CGAL (CGAL 2D Triangulations, "Constrained Delaunay Triangulations"); the
// inside is marked by the parity of boundary crossings, as in the user manual's polygon-domain example.
#include "mesh/polygon_cdt.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <deque>
#include <utility>

namespace pb {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<uint32_t, Kernel>;
constexpr int kUnvisited = -1;
struct Depth {  // boundary crossings from the unbounded face
  int crossings = kUnvisited;
};
using FaceInfo = CGAL::Triangulation_face_base_with_info_2<Depth, Kernel>;
using FaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel, FaceInfo>;
using Structure = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Constraints may touch at a corner but never cross: a crossing throws, and the polygon is not simple.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Structure, CGAL::No_constraint_intersection_tag>;

// Every face's number of boundary crossings from the unbounded face, by a breadth-first walk that pays one
// crossing for each constrained edge it steps over.
void MarkCrossings(Cdt& cdt) {
  std::deque<std::pair<Cdt::Face_handle, int>> open{{cdt.infinite_face(), 0}};
  std::deque<std::pair<Cdt::Face_handle, int>> beyond;  // faces one more crossing away
  while (!open.empty() || !beyond.empty()) {
    if (open.empty()) std::swap(open, beyond);
    auto [face, crossings] = open.front();
    open.pop_front();
    if (face->info().crossings != kUnvisited) continue;
    face->info().crossings = crossings;
    for (int e = 0; e < 3; ++e) {
      const Cdt::Face_handle next = face->neighbor(e);
      if (next->info().crossings != kUnvisited) continue;
      if (cdt.is_constrained({face, e}))
        beyond.push_back({next, crossings + 1});
      else
        open.push_back({next, crossings});
    }
  }
}

}  // namespace

std::optional<std::vector<std::array<uint32_t, 3>>> TriangulateSimplePolygon(
    std::span<const std::array<double, 2>> corners) {
  const uint32_t n = uint32_t(corners.size());
  std::vector<std::pair<Kernel::Point_2, uint32_t>> points;
  points.reserve(n);
  for (uint32_t i = 0; i < n; ++i) points.push_back({{corners[i][0], corners[i][1]}, i});
  Cdt cdt;
  cdt.insert(points.begin(), points.end());  // spatially sorted: O(n log n)
  if (cdt.number_of_vertices() != n) return std::nullopt;  // corners coincide
  std::vector<Cdt::Vertex_handle> vertex(n);
  for (Cdt::Vertex_handle v : cdt.finite_vertex_handles()) vertex[v->info()] = v;
  try {
    for (uint32_t i = 0; i < n; ++i) cdt.insert_constraint(vertex[i], vertex[(i + 1) % n]);
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    return std::nullopt;  // edges cross
  }
  MarkCrossings(cdt);
  std::vector<std::array<uint32_t, 3>> triangles;
  triangles.reserve(n - 2);
  for (Cdt::Face_handle f : cdt.finite_face_handles())
    if (f->info().crossings % 2 == 1)
      triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  if (triangles.size() != n - 2) return std::nullopt;  // a corner on another edge: not simple
  return triangles;
}

}  // namespace pb
