// Stage 3: what every estimate that casts rays from a surface point starts from (the shadow rays of the direct
// light, the gathered paths of a gap or a reference): the point's own random numbers, the same whichever thread
// or process asks, and where its rays start.
#pragma once

#include <cstdint>

#include "baker/0_prepare_scene.h"
#include "estimators/rng.h"
#include "mesh/split_mesh.h"

namespace pb {

// The random numbers of point p: a stream keyed by the seed, p's surface and its chart position (-0 as +0).
Rng PointStream(uint64_t seed, const SurfacePoint& p);

// Where rays for point p start. A vertex where a wall meets the floor lies on the wall's plane too: half the rays
// gathered there would leave through the wall, and shadow rays would graze it. The value at such a point is the
// limit from inside its surface, so a point on a planar surface's boundary starts just inside it.
SurfacePoint RayStart(const PreparedScene& scene, const SurfacePoint& p);

// Whether RayStart stepped p inward to `start`: p lies on its planar surface's boundary (an edge, a contact line).
inline bool OnBoundary(const SurfacePoint& p, const SurfacePoint& start) {
  return !(start.uv.u == p.uv.u && start.uv.v == p.uv.v);
}

}  // namespace pb
