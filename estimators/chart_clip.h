// Clipping of convex polygons and segments in a chart's plane (u, v) [m], as the covers' lattice needs it
// (estimators/surface_cover.h): corners counter-clockwise, in float, with the arithmetic in double.
#pragma once

#include <vector>

#include "mesh/geometry.h"

namespace pb {

// The part of convex counter-clockwise `polygon` left of the line a -> b.
std::vector<Point2> ClipLeftOf(const std::vector<Point2>& polygon, Point2 a, Point2 b);
// Twice the polygon's signed area [m^2]: positive when counter-clockwise.
double TwiceSignedArea(const std::vector<Point2>& polygon);
// The part of convex polygon `polygon` (either winding) inside the box, counter-clockwise.
std::vector<Point2> ClipToWindow(std::vector<Point2> polygon, const Bounds2& box);
// Cuts segment a -> b to the box (Liang and Barsky); false when nothing of it is inside.
bool ClipToBox(Point2& a, Point2& b, const Bounds2& box);

}  // namespace pb
