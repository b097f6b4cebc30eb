// Least-squares conformal map of a disc-shaped triangle patch to the plane (Levy et al. 2002, "Least Squares
// Conformal Maps for Automatic Texture Atlas Generation"), computed by CGAL's Surface_mesh_parameterization.
// Only this header is seen by the rest of photonbake; CGAL stays inside mesh/lscm.cpp.
//
// The (u,v) it returns are scaled so that the patch's total (u,v) area equals its surface area [m^2]: a
// conformal map preserves angles, and this makes it preserve area on average too.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "mesh/geometry.h"

namespace pb {

// positions [m] of the patch's vertices; triangles index them, counter-clockwise seen from the front. The patch
// must be connected, manifold, and a topological disc (one boundary loop, Euler characteristic 1).
// Returns one (u,v) [m] per vertex, counter-clockwise like the input, or nothing if CGAL cannot map it.
std::optional<std::vector<Point2>> ConformalMap(std::span<const Point3> positions,
                                               std::span<const std::array<uint32_t, 3>> triangles);

}  // namespace pb
