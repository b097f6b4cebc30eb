// Triangulation of a large simple polygon in O(n log n): the constrained Delaunay triangulation of its corners with
// its edges as constraints (CGAL's Constrained_Delaunay_triangulation_2), keeping the faces inside the boundary.
// Coordinates are the polygon's own, in its plane [m]; only this header is seen by the rest of photonbake.
//
// A face is inside when a walk from the unbounded face to it crosses the boundary an odd number of times. For a
// simple polygon of n corners that gives n - 2 triangles, which tile it exactly and add no corner.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace pb {

// The triangles (indices into `corners`, counter-clockwise like a counter-clockwise polygon), or nothing if the
// polygon is not simple: two corners coincide or two edges cross, so that no triangulation uses only its corners.
std::optional<std::vector<std::array<uint32_t, 3>>> TriangulateSimplePolygon(
    std::span<const std::array<double, 2>> corners);

}  // namespace pb
