// Uniform refinement of a half-edge mesh with OpenSubdiv: `levels` rounds of 1-to-4 triangle splitting (Loop
// topology), each edge cut at its midpoint. Positions are interpolated linearly (OpenSubdiv's "varying"
// interpolation), never by Loop's smoothing weights, so every new vertex lies on its parent face and the
// geometry does not change: planar faces stay planar and the silhouette is exact. Each child face keeps its
// parent's surface and base triangle. The vertex count grows about 4x per level.
//
// The baker uses it for `--subdivide N`, and the refinement benchmark uses it as the uniform baseline that the
// adaptive refinement (mesh/refine.h) must beat.
#pragma once

#include <cstdint>
#include <functional>

#include "mesh/half_edge_mesh.h"

namespace pb {

// `mesh` must have no deleted elements. levels = 0 returns a copy. `built`, when given, is told the faces of the
// finest level as they are built (every 65,536, and at the end), for progress.
HalfEdgeMesh SubdivideUniform(const HalfEdgeMesh& mesh, int levels,
                              const std::function<void(uint64_t faces)>& built = {});

}  // namespace pb
