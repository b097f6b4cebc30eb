// Triangulation of one polygon face (an OBJ 'f' with more than three corners), in metres, any shape.
//
// The polygon is taken in its own plane: Newell's normal (the area vector of the polygon, which is exact for a
// planar polygon and a least-squares plane for a warped one) fixes the plane and which side is the front. A convex
// polygon is cut as a fan from its first corner, as every OBJ reader does. A concave one of up to 64 corners is cut
// by ear clipping (Eberly, "Triangulation by Ear Clipping", Geometric Tools 2002): repeatedly cut off a convex
// corner whose triangle holds no other corner of what remains. A larger one is cut by constrained Delaunay
// triangulation (mesh/polygon_cdt.h) in O(n log n); if it touches or crosses itself, it is ear-clipped up to 256
// corners and cut as a fan beyond (marked irregular), so that no polygon costs more than O(n log n) + O(256^3). For a simple polygon (no edge crosses another) the triangles
// tile it exactly: their areas add up to the polygon's, and every one faces the polygon's front. Corners on a
// straight line give zero-area triangles, which the loader drops.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace pb {

using PolygonCorner = std::array<double, 3>;

struct PolygonTriangulation {
  std::vector<std::array<uint32_t, 3>> triangles;  // indices into the corners, wound like the polygon
  bool concave = false;  // ear clipping was needed
  bool irregular = false;  // edges cross (no ear was found at some step, or over 256 corners): cut as a fan
};

// The polygon's triangles; corners.size() - 2 of them. Needs at least three corners.
PolygonTriangulation TriangulatePolygon(const std::vector<PolygonCorner>& corners);

// The area vector of a polygon, by Newell's formula: its length is the (projected) area [m^2], its direction the
// front normal (counter-clockwise winding).
PolygonCorner PolygonAreaVector(const std::vector<PolygonCorner>& corners);

}  // namespace pb
